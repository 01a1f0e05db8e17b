#pragma once
/// @file
/// O(N) neighbour search with cell lists, and the pair list the solver loops over.

#include <sph/types.h>

#include <cstdint>
#include <vector>

namespace sph
{
  /// All pairs (i, j), i < j, closer than a cut-off radius, sorted by i then j, plus for each
  /// particle the pairs it belongs to (CSR) so that per-particle sums are gathers.
  struct PairList
  {
    std::vector<std::int32_t> first;  ///< pair p joins first[p] ...
    std::vector<std::int32_t> second; ///< ... and second[p], first[p] < second[p]
    std::vector<std::int32_t> offsets; ///< pairs of particle i: incidence[offsets[i] .. offsets[i+1])
    std::vector<std::int32_t> incidence; ///< pair indices, ascending per particle

    /// Number of pairs.
    std::size_t n_pairs() const { return first.size(); }
    /// The other particle of pair `p` seen from particle `i`.
    std::int32_t other(const std::int32_t p, const std::int32_t i) const
    {
      return first[p] + second[p] - i;
    }
  };

  /// Rebuilds the incidence lists (offsets, incidence) of `pairs` for `n` particles from its pair
  /// arrays (first, second).
  void build_incidence(std::size_t n, PairList &pairs);

  /// Builds the pair list of all particles closer than `radius` [m] (strictly) with a cell list of
  /// cell size `radius`. O(N) for bounded density. Deterministic (same input, same output).
  template <int dim>
  void find_pairs(const std::vector<Vector<dim>> &x, double radius, PairList &pairs);

  /// Brute-force O(N^2) reference of find_pairs (tests only).
  template <int dim>
  void find_pairs_brute_force(const std::vector<Vector<dim>> &x, double radius, PairList &pairs);
} // namespace sph
