#pragma once
/// @file
/// Heterogeneous rock: per-particle strength factors drawn from a Weibull distribution (mean 1,
/// modulus m), for sph::Body::set_strength_factors.

#include <sph/types.h>

#include <cstdint>
#include <vector>

namespace sph
{
  /// One Weibull strength factor (mean 1, modulus `modulus` >= 1) per particle at reference
  /// positions `x0`. Each particle's uniform number is a hash of `seed` and its cell of a grid of
  /// edge `spacing` [m] (a lattice's spacing; smaller for sets not on a lattice, so that each
  /// cell holds one particle), so a particle's factor depends neither on the particle order nor
  /// on the thread count, and the same seed gives the same rock at every run. Throws
  /// std::invalid_argument for modulus < 1 or spacing <= 0.
  template <int dim>
  std::vector<double> weibull_strength_factors(const std::vector<Vector<dim>> &x0, double spacing,
                                               double modulus, std::uint64_t seed);
} // namespace sph
