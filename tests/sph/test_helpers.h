#pragma once
// Small drivers shared by the SPH physics tests.
#include <sph/body.h>
#include <sph/lattice.h>

#include <functional>

namespace sph_test
{
  using namespace sph;

  /// Result of a quasi-static axial test between frictionless rigid walls.
  struct AxialResult
  {
    double peak_stress = 0;   ///< peak |axial stress| on the true section [Pa]
    double stress      = 0;   ///< |axial stress| at the end [Pa]
    double strain      = 0;   ///< |axial strain| at the end [-]
    double radial      = 0;   ///< radial strain at mid-height at the end [-]
    int    steps       = 0;
    double kinetic_ratio = 0; ///< kinetic / internal energy at the end
  };

  /// Elastic basalt (Group M1-like: rho = 2900 kg/m^3, E = 97.07 GPa, nu = 0.28), the base of the
  /// cylinder tests; plastic tests set the model and strength on a copy.
  MaterialParameters basalt_elastic();

  /// P-wave speed sqrt(E (1 - nu) / ((1 + nu) (1 - 2 nu) rho)) of `mat` [m/s].
  double p_wave_speed(const MaterialParameters &mat);

  /// Loads a cylinder of diameter D and length L (dx) axially between frictionless rigid walls
  /// (end layers: only the axial velocity prescribed) to `strain` (sign: - compression) over
  /// `ramp_transits` P-wave transits with a smooth velocity profile, with mass-proportional
  /// damping `damping` [1/s] applied as external force (dynamic relaxation), then holds for
  /// `hold_transits`. Radial strain: mean u_r / r of the particles at mid-height.
  AxialResult axial_test(const Parameters &prm, const MaterialParameters &mat, double D, double L,
                         double strain, double ramp_transits, double hold_transits,
                         double damping);
} // namespace sph_test
