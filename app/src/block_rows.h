#pragma once
// Rows of a distributed whole-body array moved into contiguous blocks, one per MPI rank, so that
// each rank writes its block as one hyperslab (a union of many row runs is slow to select in
// HDF5 1.10: 0.06 s for 1,000 runs, 12.6 s for 10,000).

#include <mpi.h>

#include <cstdint>
#include <string>
#include <vector>

namespace app
{
  /// The first row of rank `rank`'s block of `n` rows over `n_ranks` ranks: n rank / n_ranks.
  std::size_t block_start(std::size_t n, int rank, int n_ranks);

  /// `rows` (`width` doubles per row; this rank's rows, of the whole array's rows
  /// `global_index`, ascending) moved to the rank whose block of the array's `n` rows holds them:
  /// rank r gets rows [block_start(r), block_start(r + 1)) in order. One MPI_Alltoallv.
  /// Collective over `comm`.
  std::vector<double> rows_in_blocks(const std::vector<double> &rows, std::size_t width,
                                     const std::vector<std::int64_t> &global_index, std::size_t n,
                                     MPI_Comm comm);

  /// MPI_Bcast of a string from rank 0 of `comm`.
  void broadcast(std::string &text, MPI_Comm comm);
} // namespace app
