#pragma once
/// @file
/// Rate-dependent strength of the SPH rock: the strengths of a material scaled by
/// rock::rate_strength_factor (rock_models.h), the law `cosim diagnose` fits,
///
///   factor = max(1 + A log10(rate / reference_rate), 0.1),
///
/// A the strength gain per decade of strain rate. The factor multiplies the cohesive strengths
/// (Mohr-Coulomb c and tension cut-off, Hoek-Brown sigma_ci), so the uniaxial compressive and
/// tensile strengths scale by it exactly; the friction angle and the moduli are rate independent.

#include <sph/parameters.h>
#include <sph/rock_models.h>

namespace sph
{
  /// `m` with its strengths multiplied by `factor` (> 0) [-].
  inline MaterialParameters with_strength_factor(MaterialParameters m, const double factor)
  {
    m.cohesion *= factor;
    m.tensile_strength *= factor;
    m.hb_sigma_ci *= factor;
    return m;
  }

  /// `m` at the nominal strain rate `rate` [1/s] for a rate sensitivity A (per decade) [-] and
  /// the reference (quasi-static) rate `reference_rate` [1/s]; `m` unchanged when A = 0.
  inline MaterialParameters at_strain_rate(const MaterialParameters &m, const double rate,
                                           const double A, const double reference_rate)
  {
    if (A == 0)
      return m;
    return with_strength_factor(m, rock::rate_strength_factor(rate, reference_rate, A));
  }
} // namespace sph
