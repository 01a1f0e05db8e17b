// The driver's rock body (coupling/src/driver_common.h, make_rock_body): Rock/Scatter length
// reaches the particles' strength factors, so that two spacings give the same rock.
#include "../../coupling/src/driver_common.h"

#include <sph/body.h>
#include <sph/lattice.h>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <map>

using namespace coupling;

namespace
{
  // a small heterogeneous Mohr-Coulomb cylinder case at spacing dx (D 20 x 20 mm)
  CaseParameters heterogeneous(const double dx, const double scatter_length)
  {
    CaseParameters p;
    p.test                       = "UCS";
    p.diameter                   = 0.02;
    p.length                     = 0.02;
    p.sph.spacing                = dx;
    p.rock.model                 = sph::RockModel::mohr_coulomb;
    p.rock.youngs_modulus        = 97.07e9;
    p.rock.poissons_ratio        = 0.28;
    p.rock.cohesion              = 32.99e6;
    p.rock.friction_angle        = 63.68 * M_PI / 180.0;
    p.rock_case.strength_scatter = 10;
    p.rock_case.scatter_length   = scatter_length;
    return p;
  }

  // strength factor of every particle, keyed by its 5 mm cell (the last particle's in a cell)
  std::map<std::array<long, 3>, double> factors_by_cell(const CaseParameters &p)
  {
    const auto lattice = sph::make_cylinder<3>(p.diameter, p.length, p.sph.spacing);
    const auto body    = make_rock_body(p, lattice);
    std::map<std::array<long, 3>, double> by_cell;
    for (unsigned int i = 0; i < body->n_particles(); ++i)
    {
      const auto &x = body->reference_positions()[i];
      by_cell[{std::lround(std::floor(x[0] / 5e-3)), std::lround(std::floor(x[1] / 5e-3)),
               std::lround(std::floor(x[2] / 5e-3))}] = body->strength_factor(i);
    }
    return by_cell;
  }
} // namespace

// With 5 mm cells every particle of a 2.5 mm and of a 1.25 mm cylinder in one cell carries that
// cell's factor; without them (one factor per particle) the two spacings are two rocks.
TEST(RockBody, ScatterLengthGivesTheSameRockAtTwoSpacings)
{
  const auto check = [](const double scatter_length) {
    const auto lattice = sph::make_cylinder<3>(0.02, 0.02, 1.25e-3);
    const auto fine    = make_rock_body(heterogeneous(1.25e-3, scatter_length), lattice);
    const auto coarse  = factors_by_cell(heterogeneous(2.5e-3, scatter_length));
    std::size_t same = 0, compared = 0;
    for (unsigned int i = 0; i < fine->n_particles(); ++i)
    {
      const auto &x = fine->reference_positions()[i];
      const auto it = coarse.find({std::lround(std::floor(x[0] / 5e-3)), std::lround(std::floor(x[1] / 5e-3)),
                                   std::lround(std::floor(x[2] / 5e-3))});
      if (it == coarse.end())
        continue;
      ++compared;
      same += fine->strength_factor(i) == it->second;
    }
    EXPECT_GT(compared, fine->n_particles() / 2);
    return static_cast<double>(same) / compared;
  };
  EXPECT_EQ(check(5e-3), 1.0) << "with Rock/Scatter length every shared cell has one factor";
  // per particle: a fine particle draws its own number; a match is a coincidence of doubles
  EXPECT_LT(check(0.0), 0.01) << "without it the two spacings are two rocks";
}
