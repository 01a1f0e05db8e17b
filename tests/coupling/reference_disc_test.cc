// The Brazilian disc's 3-D elastic FE reference (coupling/reference_disc.h): a thin disc is
// Hondros's plane solution on its mid-plane and on its faces. (The thick disc's faces against its
// mid-plane: CoupledBodyFitted.ElasticFlattenedDiscCarriesItsFlatsLoadAsHondrosSays.)
#include "hondros.h"

#include <coupling/reference_disc.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>

using namespace coupling;
using namespace coupling::test;

TEST(ReferenceDisc, AThinDiscIsHondrosPlaneSolution)
{
  // t / D = 0.1, arcs of 2 x 10 deg, 3 refinements (41,667 dofs, about 10 s)
  const double a = 10 * 3.14159265358979323846 / 180, D = 0.05, t = 0.005;
  const std::vector<double> rho{0, 0.25, 0.5};
  const DiscReferenceProfile r = elastic_disc_reference(D, t, a, 97e9, 0.28, 1e5, rho, 3);
  // the quadrature applies the arcs' pressure to within 6 % (measured 1.034 P): the stresses
  // are read per the load applied
  EXPECT_NEAR(r.load / 1e5, 1.0, 0.06);
  const double T = 2 * r.load / (3.14159265358979323846 * D * t);
  for (std::size_t k = 0; k < rho.size(); ++k)
  {
    const double h = hondros(0, rho[k], a).first;
    std::printf("rho %.2f: mid %.4f face %.4f Hondros %.4f\n", rho[k], r.mid[k] / T, r.face[k] / T, h);
    // 4 %: the mesh's (2 to 3 refinements move the centre 3 %; measured +0.7 % mid, +1.5 % face
    // at the centre, -0.7 / +2.8 % at half the radius); the thick disc's face is 25-70 % off
    EXPECT_NEAR(r.mid[k] / T / h, 1.0, 0.04) << "rho " << rho[k];
    EXPECT_NEAR(r.face[k] / T / h, 1.0, 0.04) << "rho " << rho[k];
  }
}

TEST(ReferenceDisc, BadArgumentsAreRefused)
{
  EXPECT_THROW(elastic_disc_reference(0.05, 0.025, 0.2, 97e9, 0.28, 1e5, {0.0}, 1, 0.02),
               std::invalid_argument); // face depth beyond the mid-plane
  EXPECT_THROW(elastic_disc_reference(0.05, 0.025, 0.2, 97e9, 0.5, 1e5, {0.0}, 1),
               std::invalid_argument); // incompressible
  EXPECT_THROW(elastic_disc_reference(0.05, 0.025, 0.2, 97e9, 0.28, 1e5, {1.0}, 1),
               std::invalid_argument); // on the rim
}
