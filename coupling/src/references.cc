/// @file
/// The closed forms of coupling/references.h.

#include <coupling/references.h>

#include <algorithm>
#include <cmath>

namespace coupling
{
  namespace
  {
    constexpr double pi = 3.14159265358979323846;
  } // namespace

  double mohr_coulomb_axial_strength(const double c, const double phi_deg, const double sigma3)
  {
    const double s = std::sin(phi_deg * pi / 180.0);
    return 2 * c * std::cos(phi_deg * pi / 180.0) / (1 - s) + sigma3 * (1 + s) / (1 - s);
  }

  CsmEstimate csm_cutter_force(const double ucs, const double bts, const double radius,
                               const double tip_width, const double penetration,
                               const double spacing, const double psi)
  {
    CsmEstimate e;
    e.contact_angle = std::acos((radius - penetration) / radius);
    // the CSM fit's constant C = 2.12 holds in any consistent units: the bracket is a stress cubed
    e.base_pressure = 2.12 * std::cbrt(spacing * ucs * ucs * bts /
                                       (e.contact_angle * std::sqrt(radius * tip_width)));
    e.total         = e.base_pressure * e.contact_angle * radius * tip_width / (1.0 + psi);
    e.normal        = e.total * std::cos(0.5 * e.contact_angle);
    e.rolling       = e.total * std::sin(0.5 * e.contact_angle);
    return e;
  }

  double sneddon_cone_force(const double youngs, const double nu, const double half_angle,
                            const double depth)
  {
    return 2.0 / pi * youngs / (1.0 - nu * nu) * std::tan(half_angle) * depth * depth;
  }

  double flat_punch_force(const double youngs, const double nu, const double radius,
                          const double depth)
  {
    return 2.0 * radius * youngs / (1.0 - nu * nu) * depth;
  }

  double cavity_expansion_pressure(const double youngs, const double yield, const double half_angle)
  {
    return 2.0 / 3.0 * yield *
           (1.0 + std::log(std::max(1.0, youngs / std::tan(half_angle) / (3.0 * yield))));
  }
} // namespace coupling
