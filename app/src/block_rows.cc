#include "block_rows.h"

#include <algorithm>
#include <stdexcept>

namespace app
{
  std::size_t block_start(const std::size_t n, const int rank, const int n_ranks)
  {
    return n * static_cast<std::size_t>(rank) / static_cast<std::size_t>(n_ranks);
  }

  std::vector<double> rows_in_blocks(const std::vector<double> &rows, const std::size_t width,
                                     const std::vector<std::int64_t> &global_index,
                                     const std::size_t n, const MPI_Comm comm)
  {
    int rank = 0, size = 1;
    MPI_Comm_rank(comm, &rank);
    MPI_Comm_size(comm, &size);
    if (rows.size() != width * global_index.size())
      throw std::logic_error("rows_in_blocks: rows and global indices disagree");
    // each row goes with its global index in front
    const std::size_t   w = width + 1;
    std::vector<double> send;
    send.reserve(w * global_index.size());
    for (std::size_t i = 0; i < global_index.size(); ++i)
    {
      send.push_back(static_cast<double>(global_index[i]));
      send.insert(send.end(), rows.begin() + width * i, rows.begin() + width * (i + 1));
    }
    std::vector<int> send_counts(size), send_offsets(size), receive_counts(size), receive_offsets(size);
    std::size_t      row = 0;
    for (int r = 0; r < size; ++r)
    {
      const auto end_index = static_cast<std::int64_t>(block_start(n, r + 1, size));
      const std::size_t end = static_cast<std::size_t>(
        std::lower_bound(global_index.begin(), global_index.end(), end_index) - global_index.begin());
      send_offsets[r] = static_cast<int>(row * w);
      send_counts[r]  = static_cast<int>((end - row) * w);
      row             = end;
    }
    MPI_Alltoall(send_counts.data(), 1, MPI_INT, receive_counts.data(), 1, MPI_INT, comm);
    int total = 0;
    for (int r = 0; r < size; ++r)
    {
      receive_offsets[r] = total;
      total += receive_counts[r];
    }
    std::vector<double> received(static_cast<std::size_t>(total));
    MPI_Alltoallv(send.data(), send_counts.data(), send_offsets.data(), MPI_DOUBLE, received.data(),
                  receive_counts.data(), receive_offsets.data(), MPI_DOUBLE, comm);
    const std::size_t   first = block_start(n, rank, size);
    std::vector<double> block((block_start(n, rank + 1, size) - first) * width);
    for (std::size_t at = 0; at + w <= received.size(); at += w)
    {
      const std::size_t k = static_cast<std::size_t>(received[at]) - first;
      std::copy(received.begin() + at + 1, received.begin() + at + w, block.begin() + k * width);
    }
    return block;
  }

  void broadcast(std::string &text, const MPI_Comm comm)
  {
    unsigned long size = text.size();
    MPI_Bcast(&size, 1, MPI_UNSIGNED_LONG, 0, comm);
    text.resize(size);
    MPI_Bcast(text.data(), static_cast<int>(size), MPI_CHAR, 0, comm);
  }
} // namespace app
