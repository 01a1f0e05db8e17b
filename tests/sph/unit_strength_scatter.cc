// Heterogeneous rock: Weibull strength factors per particle, and the rock models honouring them.
#include <sph/rock_models.h>
#include <sph/strength_scatter.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

namespace
{
  using namespace sph;

  std::vector<Vector<3>> cube_lattice(const int n, const double dx)
  {
    std::vector<Vector<3>> x;
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
          x.emplace_back((i - n / 2 + 0.5) * dx, (j - n / 2 + 0.5) * dx, (k - n / 2 + 0.5) * dx);
    return x;
  }
} // namespace

TEST(SphStrengthScatter, FactorsHaveTheWeibullMeanAndSpread)
{
  const auto x = cube_lattice(50, 1e-3); // 125,000 particles
  for (const double m : {3.0, 10.0})
  {
    const auto f       = weibull_strength_factors<3>(x, 1e-3, m, 42);
    const double n     = static_cast<double>(f.size());
    const double mean  = std::accumulate(f.begin(), f.end(), 0.0) / n;
    double var         = 0;
    for (const double v : f)
      var += (v - mean) * (v - mean);
    const double cv    = std::sqrt(var / (n - 1)) / mean;
    const double cv_th = rock::weibull_coefficient_of_variation(m);
    // sampling error of the mean: cv / sqrt(n) = 1e-3 (m = 3); 5e-3 is five standard errors
    EXPECT_NEAR(mean, 1.0, 5e-3) << "m = " << m;
    // sampling error of a standard deviation: about cv / sqrt(2 n) (relative 2e-3); 2 % allows
    // the Weibull's skew (its kurtosis widens that error a few times)
    EXPECT_NEAR(cv / cv_th, 1.0, 0.02) << "m = " << m;
    EXPECT_GT(*std::min_element(f.begin(), f.end()), 0.0);
  }
}

TEST(SphStrengthScatter, AParticlesFactorDependsOnItsCellAndTheSeedOnly)
{
  auto x       = cube_lattice(8, 2e-3);
  const auto a = weibull_strength_factors<3>(x, 2e-3, 5.0, 7);
  std::reverse(x.begin(), x.end());
  const auto b = weibull_strength_factors<3>(x, 2e-3, 5.0, 7);
  for (std::size_t i = 0; i < a.size(); ++i)
    EXPECT_EQ(a[i], b[a.size() - 1 - i]) << "the same particle gets the same factor in any order";
  const auto c = weibull_strength_factors<3>(x, 2e-3, 5.0, 8);
  std::size_t same = 0;
  for (std::size_t i = 0; i < c.size(); ++i)
    same += c[i] == b[i];
  EXPECT_EQ(same, 0u) << "another seed is another rock";
  // the eight cells around the origin are distinct (floor, not truncation towards 0)
  EXPECT_NE(b[0], b[1]);
}

TEST(SphStrengthScatter, CellsOfAScatterLengthGiveTheSameRockAtEverySpacing)
{
  // Rock/Scatter length: cells of 4 mm fixed in space; a 2 mm and a 1 mm lattice of the same
  // cube must draw the same factor wherever their particles share a cell
  const double cell   = 4e-3;
  const auto coarse   = cube_lattice(8, 2e-3), fine = cube_lattice(16, 1e-3);
  const auto f_coarse = weibull_strength_factors<3>(coarse, cell, 10.0, 3);
  const auto f_fine   = weibull_strength_factors<3>(fine, cell, 10.0, 3);
  const auto key      = [cell](const Vector<3> &x) {
    return std::array<long, 3>{std::lround(std::floor(x[0] / cell)), std::lround(std::floor(x[1] / cell)),
                               std::lround(std::floor(x[2] / cell))};
  };
  std::size_t compared = 0, distinct = 0;
  for (std::size_t i = 0; i < fine.size(); ++i)
    for (std::size_t j = 0; j < coarse.size(); ++j)
      if (key(fine[i]) == key(coarse[j]))
      {
        EXPECT_EQ(f_fine[i], f_coarse[j]) << "particle " << i << " of the fine lattice";
        ++compared;
      }
  for (std::size_t j = 1; j < coarse.size(); ++j)
    distinct += f_coarse[j] != f_coarse[0];
  EXPECT_EQ(compared, fine.size() * 8) << "each fine particle shares its cell with 8 coarse ones";
  // 2 x 2 x 2 coarse particles per cell, 64 cells: the field is not one value
  EXPECT_GT(distinct, coarse.size() / 2);
}

TEST(SphStrengthScatter, BadModulusOrSpacingIsRefused)
{
  const auto x = cube_lattice(2, 1e-3);
  EXPECT_THROW(weibull_strength_factors<3>(x, 1e-3, 0.5, 1), std::invalid_argument);
  EXPECT_THROW(weibull_strength_factors<3>(x, 1e-3, std::nan(""), 1), std::invalid_argument);
  EXPECT_THROW(weibull_strength_factors<3>(x, 0.0, 5.0, 1), std::invalid_argument);
}

TEST(SphStrengthScatter, MohrCoulombYieldsAtTheParticlesScaledCohesion)
{
  MaterialParameters m;
  m.model          = RockModel::mohr_coulomb;
  m.youngs_modulus = 60e9;
  m.poissons_ratio = 0.25;
  m.cohesion       = 20e6;
  m.friction_angle = 40.0 * M_PI / 180;
  const auto p     = rock::make_model_constants(m);
  // uniaxial compression well past the intact strength 2c cos(phi)/(1 - sin(phi)) = 85.8 MPa
  const double ucs = 2 * 20e6 * std::cos(m.friction_angle) / (1 - std::sin(m.friction_angle));
  for (const double factor : {1.0, 0.5, 1.7})
  {
    MaterialState state;
    state.strength   = factor;
    // the strain of a uniaxial stress of 3 UCS
    Tensor3 de       = Tensor3::Zero();
    de(2, 2)         = -3 * ucs / m.youngs_modulus;
    de(0, 0)         = de(1, 1) = 3 * ucs * m.poissons_ratio / m.youngs_modulus;
    const auto up    = rock::update_mohr_coulomb(Tensor3::Zero(), de, state, p);
    Eigen::SelfAdjointEigenSolver<Tensor3> e(up.stress);
    const rock::Principal s(e.eigenvalues()[2], e.eigenvalues()[1], e.eigenvalues()[0]);
    // on the surface of cohesion factor * c, to the returns' round-off (1e-8 of the stress)
    EXPECT_NEAR(rock::mohr_coulomb_yield(s, factor * m.cohesion, p.sin_phi, p.cos_phi), 0.0,
                1e-8 * 3 * ucs)
      << "factor " << factor;
    EXPECT_EQ(up.state.strength, factor) << "the factor is the particle's for the whole run";
  }
}
