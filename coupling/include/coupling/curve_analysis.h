#pragma once
/// @file
/// What a laboratory reads off a load curve: the peak, the secant modulus between two fractions of
/// the peak (ISRM: 40-60 %), Poisson's ratio from gauge strains. Pure functions on sampled curves.

#include <cstddef>
#include <vector>

namespace coupling
{
  /// Index of the largest value (the first one on ties). Precondition: !y.empty().
  std::size_t peak_index(const std::vector<double> &y);

  /// Value of x where the rising part of y (before its peak) first reaches `level`, by linear
  /// interpolation between samples. Returns false when y never reaches it before the peak.
  bool crossing(const std::vector<double> &x, const std::vector<double> &y, double level,
                double &x_at_level);

  /// Secant slope of stress over strain between the points where stress first reaches lo and hi
  /// times its peak (default 40 % and 60 %). Returns 0 when the curve does not reach them.
  double secant_modulus(const std::vector<double> &strain, const std::vector<double> &stress,
                        double lo = 0.4, double hi = 0.6);

  /// Poisson's ratio -d(lateral)/d(axial) between the same two stress levels. Returns -1 when the
  /// curve does not reach them or the axial strain does not change.
  double secant_poissons_ratio(const std::vector<double> &axial_strain,
                               const std::vector<double> &lateral_strain,
                               const std::vector<double> &stress, double lo = 0.4, double hi = 0.6);
} // namespace coupling
