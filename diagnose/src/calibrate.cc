#include <diagnose/calibrate.h>

#include <coupling/references.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace diagnose
{
  namespace
  {
    constexpr double pi = 3.14159265358979323846;
    double radians(double deg) { return deg * pi / 180.0; }
  } // namespace

  MohrCoulombStrength calibrate_mohr_coulomb(const double ucs, const double bts)
  {
    if (!(bts > 0 && ucs > bts) || !std::isfinite(ucs))
      throw std::invalid_argument("calibrate_mohr_coulomb: need 0 < BTS < UCS");
    const double sin_phi = (ucs - bts) / (ucs + bts);
    const double phi = std::asin(sin_phi);
    return {ucs * (1.0 - sin_phi) / (2.0 * std::cos(phi)), phi * 180.0 / pi};
  }

  MohrCoulombStrength calibrate_mohr_coulomb_brazilian(const double ucs, const double bts)
  {
    if (!(bts > 0 && ucs > 4 * bts) || !std::isfinite(ucs))
      throw std::invalid_argument("calibrate_mohr_coulomb_brazilian: need 0 < 4 BTS < UCS");
    const double n       = ucs / bts - 3.0;
    const double sin_phi = (n - 1.0) / (n + 1.0);
    return {ucs / (2.0 * std::sqrt(n)), std::asin(sin_phi) * 180.0 / pi};
  }

  double mohr_coulomb_ucs(const MohrCoulombStrength &s)
  {
    return coupling::mohr_coulomb_axial_strength(s.cohesion, s.friction_angle, 0.0);
  }

  double mohr_coulomb_bts(const MohrCoulombStrength &s)
  {
    const double phi = radians(s.friction_angle);
    return 2.0 * s.cohesion * std::cos(phi) / (1.0 + std::sin(phi));
  }
} // namespace diagnose
