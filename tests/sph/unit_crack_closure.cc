// Crack-closure (toe) elasticity of the SPH rock (sph/crack_closure.h) against the closed form
// of its law, rock::crack_closure_strain: a material point driven along a uniaxial stress path.
#include <sph/crack_closure.h>
#include <sph/rate_strength.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace
{
  using namespace sph;
  using namespace sph::rock;

  MaterialParameters closure_rock(const RockModel model)
  {
    MaterialParameters m;
    m.model                 = model;
    m.youngs_modulus        = 60e9;
    m.poissons_ratio        = 0.25;
    m.cohesion              = 20e6;
    m.friction_angle        = 40.0 * M_PI / 180;
    m.closure_modulus_ratio = 0.3;
    m.closure_stress        = 15e6;
    return m;
  }

  /// Axial compressive stress [Pa] after driving `model` from zero stress to the axial strain
  /// -eps_end (compression) in n equal increments with lateral strains -nu de (the uniaxial
  /// stress path of a constant Poisson's ratio); also the largest |lateral stress| seen.
  template <typename Model>
  double uniaxial_path(const Model &model, const ModelConstants &p, const double nu,
                       const double eps_end, const int n, double &max_lateral,
                       std::vector<std::pair<double, double>> *curve = nullptr)
  {
    Tensor3       s = Tensor3::Zero();
    MaterialState h;
    const double  d  = -eps_end / n;
    Tensor3       de = Tensor3::Zero();
    de(0, 0) = de(1, 1) = -nu * d;
    de(2, 2)            = d;
    max_lateral         = 0;
    const double lateral_stiffness = 2.0 * (p.K + p.G / 3.0); // d(sigma_lat)/d(eps_lat), intact
    for (int k = 1; k <= n; ++k)
      {
        // lateral strains that keep the lateral stresses zero (elastic: -nu de at once; plastic
        // flow changes them): fixed point with the intact stiffness, which overestimates every
        // tangent and so converges monotonically
        StressUpdate up = model(s, de, h, p);
        for (int it = 0; it < 200 && std::abs(up.stress(0, 0)) > 1e-9 * std::abs(up.stress(2, 2));
             ++it)
          {
            de(0, 0) -= up.stress(0, 0) / lateral_stiffness;
            de(1, 1) = de(0, 0);
            up       = model(s, de, h, p);
          }
        s                     = up.stress;
        h                     = up.state;
        max_lateral = std::max({max_lateral, std::abs(s(0, 0)), std::abs(s(1, 1))});
        if (curve)
          curve->emplace_back(k * eps_end / n, -s(2, 2));
      }
    return -s(2, 2);
  }
} // namespace

// The stress-strain curve of the closure law: the strain at each stress is the closed-form
// integral of 1/E_t. The midpoint tangent makes the update second order in the increment:
// 2000 increments to 3e-3 give 3.6e-7 relative, 500 give 5.7e-6 (16 x: second order); 1e-5
// leaves room for round-off and fails an update an order less accurate.
TEST(SphCrackClosure, UniaxialPathFollowsTheClosedFormStrain)
{
  const MaterialParameters m = closure_rock(RockModel::elastic);
  const ModelConstants     p = make_model_constants(m);
  const ModelChoice        model = make_model_choice(m);
  ASSERT_TRUE(std::holds_alternative<WithCrackClosure<Elastic>>(model));
  const auto &closure = std::get<WithCrackClosure<Elastic>>(model);
  std::vector<std::pair<double, double>> curve;
  double                                 lateral = 0;
  uniaxial_path(closure, p, m.poissons_ratio, 3e-3, 2000, lateral, &curve);
  double worst = 0;
  for (const auto &[eps, sigma] : curve)
    {
      const double closed = crack_closure_strain(0.0, sigma, m.youngs_modulus,
                                                 m.closure_modulus_ratio * m.youngs_modulus,
                                                 m.closure_stress);
      worst = std::max(worst, std::abs(closed - eps) / eps);
    }
  EXPECT_LT(worst, 1e-5);
  std::printf("closure: worst relative strain error %.3g over %zu increments\n", worst, curve.size());
  // the lateral stresses stay zero: K and G scale together, Poisson's ratio is kept
  EXPECT_LT(lateral, 1e-6 * curve.back().second);
  // the end of the toe: far above sigma_cc the tangent is the intact E (to exp(-sigma/sigma_cc))
  const double s1 = curve[curve.size() - 2].second, s2 = curve.back().second;
  const double E_t = (s2 - s1) / (curve.back().first - curve[curve.size() - 2].first);
  EXPECT_NEAR(E_t / m.youngs_modulus, 1.0, 2e-3);
  // and at the start the modulus is E0 (first increment, 1.5e-6 strain: p / sigma_cc = 2e-3)
  EXPECT_NEAR(curve.front().second / curve.front().first / (0.3 * m.youngs_modulus), 1.0, 2e-3);
}

// Closure changes the stiffness, not the strength: a Mohr-Coulomb point with closure still
// fails at the closed-form UCS 2c cos(phi)/(1 - sin(phi)) (lateral stresses held at zero to
// 1e-9 of the axial one: the peak to 1e-8).
TEST(SphCrackClosure, MohrCoulombStrengthIsUnchanged)
{
  const MaterialParameters m     = closure_rock(RockModel::mohr_coulomb);
  const ModelConstants     p     = make_model_constants(m);
  const ModelChoice        model = make_model_choice(m);
  double                   lateral = 0;
  const double             peak =
    std::visit([&](const auto &f) { return uniaxial_path(f, p, m.poissons_ratio, 5e-3, 2000, lateral); },
               model);
  const double ucs = 2 * m.cohesion * std::cos(m.friction_angle) / (1 - std::sin(m.friction_angle));
  EXPECT_NEAR(peak / ucs, 1.0, 1e-8);
}

// Without closure (E0/E = 1, the default) the choice is the plain model: default runs unchanged.
TEST(SphCrackClosure, DefaultIsThePlainModel)
{
  MaterialParameters m;
  EXPECT_TRUE(std::holds_alternative<MohrCoulomb>(make_model_choice(m)));
  m.model = RockModel::elastic;
  EXPECT_TRUE(std::holds_alternative<Elastic>(make_model_choice(m)));
}

// Rate-dependent strength scales the strengths by the surrogate's factor and nothing else.
TEST(SphRateStrength, StrengthsScaleByTheFactor)
{
  MaterialParameters m;
  m.tensile_strength         = 5e6;
  const MaterialParameters r = at_strain_rate(m, 1e-1, 0.05, 1e-5);
  const double             f = 1 + 0.05 * 4; // four decades above the reference rate
  EXPECT_NEAR(r.cohesion / m.cohesion, f, 1e-14);
  EXPECT_NEAR(r.tensile_strength / m.tensile_strength, f, 1e-14);
  EXPECT_NEAR(r.hb_sigma_ci / m.hb_sigma_ci, f, 1e-14);
  EXPECT_EQ(r.friction_angle, m.friction_angle);
  EXPECT_EQ(r.youngs_modulus, m.youngs_modulus);
  EXPECT_EQ(at_strain_rate(m, 1e-1, 0.0, 1e-5).cohesion, m.cohesion); // A = 0: off
}
