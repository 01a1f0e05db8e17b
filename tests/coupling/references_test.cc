// The closed forms of coupling/references.h against numbers worked by hand (Python, double
// precision, quoted to 7 digits), so that a slip in a formula shows here and not as a drift of the
// drivers' comparisons. The CSM estimate has its own hand check in physics_cutting_test.cc.
#include <coupling/references.h>

#include <gtest/gtest.h>

#include <cmath>

using namespace coupling;

namespace
{
  constexpr double pi = 3.14159265358979323846;
  // the hand values are quoted to 7 significant digits
  constexpr double quoted = 1e-6;
} // namespace

TEST(References, MohrCoulombAxialStrengthByHand)
{
  // c = 10 MPa, phi = 30 deg: sin = 1/2, cos = sqrt(3)/2, so 2c cos/(1 - sin) = 2 sqrt(3) c =
  // 34.64102 MPa; with sigma3 = 5 MPa the slope (1 + sin)/(1 - sin) = 3 adds 15 MPa
  EXPECT_NEAR(mohr_coulomb_axial_strength(10e6, 30.0, 0.0) / 34.64102e6, 1.0, quoted);
  EXPECT_NEAR(mohr_coulomb_axial_strength(10e6, 30.0, 5e6) / 49.64102e6, 1.0, quoted);
  // phi = 0 (Tresca): 2c, and confinement adds itself
  EXPECT_NEAR(mohr_coulomb_axial_strength(10e6, 0.0, 5e6) / 25e6, 1.0, 1e-15);
}

TEST(References, SneddonConeByHand)
{
  // E = 50 GPa, nu = 0.25, alpha = 60 deg, h = 1 mm: 2/pi 50e9/0.9375 sqrt(3) 1e-6 = 58808.42 N
  const double f = sneddon_cone_force(50e9, 0.25, 60.0 * pi / 180.0, 1e-3);
  EXPECT_NEAR(f / 58808.42, 1.0, quoted);
  // quadratic in the depth
  EXPECT_NEAR(sneddon_cone_force(50e9, 0.25, 60.0 * pi / 180.0, 2e-3) / f, 4.0, 1e-12);
}

TEST(References, FlatPunchByHand)
{
  // a = 5 mm, E = 97.07 GPa, nu = 0.28, h = 0.1 mm: 2 0.005 97.07e9 / 0.9216 1e-4 = 105327.7 N
  EXPECT_NEAR(flat_punch_force(97.07e9, 0.28, 0.005, 1e-4) / 105327.7, 1.0, quoted);
}

TEST(References, ExpandingCavityByHand)
{
  // E = 97.07 GPa, Y = 200 MPa, alpha = 60 deg: E cot(alpha)/(3 Y) = 93.40565,
  // p_m = 2/3 200e6 (1 + ln 93.40565) = 738.2602 MPa
  EXPECT_NEAR(cavity_expansion_pressure(97.07e9, 200e6, 60.0 * pi / 180.0) / 738.2602e6, 1.0,
              quoted);
  // a blunt indenter (E cot(alpha) < 3 Y): no plastic zone beyond the core, p_m = 2/3 Y
  const double blunt = std::atan(97.07e9 / (3 * 200e6) * 2.0); // cot(alpha) = 3 Y / (2 E)
  EXPECT_NEAR(cavity_expansion_pressure(97.07e9, 200e6, blunt) / (2.0 / 3.0 * 200e6), 1.0, 1e-15);
}
