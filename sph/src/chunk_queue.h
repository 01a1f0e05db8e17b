#pragma once
/// @file
/// Chunks of a pass handed to threads (Body's pair passes). Private to sph/src.

#include <atomic>
#include <cstdint>
#include <memory>

namespace sph
{
  /// Chunks [0, n_chunks) for n_blocks threads. Thread t first takes the chunks of its own block
  /// [n_chunks t / n_blocks, n_chunks (t + 1) / n_blocks) from the front, in order: when the
  /// threads run evenly each takes the same chunks in every pass, and their data stays in its
  /// core's cache. A thread whose block is done takes the last chunk left in the block with the
  /// most left: a slower thread hands work over. Which thread takes a chunk must not matter to
  /// the results (Body's passes write only the chunk's own sums).
  /// reset() runs before the threads take (outside the parallel region); next() from each thread.
  class ChunkQueue
  {
  public:
    void reset(const int n_chunks, const int n_blocks)
    {
      if (n_blocks != n_blocks_)
        {
          blocks_   = std::make_unique<Block[]>(n_blocks);
          n_blocks_ = n_blocks;
        }
      for (int b = 0; b < n_blocks; ++b)
        blocks_[b].range.store(pack(static_cast<std::int64_t>(n_chunks) * b / n_blocks,
                                    static_cast<std::int64_t>(n_chunks) * (b + 1) / n_blocks),
                               std::memory_order_relaxed);
    }

    /// The next chunk for thread t (its own block first, then the others'); -1 when none is left.
    int next(const int t)
    {
      if (t < n_blocks_)
        {
          std::uint64_t r = blocks_[t].range.load(std::memory_order_acquire);
          while (front(r) < back(r))
            if (blocks_[t].range.compare_exchange_weak(r, pack(front(r) + 1, back(r)),
                                                       std::memory_order_acq_rel))
              return front(r);
        }
      while (true)
        {
          int           most = -1;
          std::uint32_t left = 0;
          for (int b = 0; b < n_blocks_; ++b)
            {
              const std::uint64_t r = blocks_[b].range.load(std::memory_order_acquire);
              if (back(r) > front(r) && back(r) - front(r) > left)
                {
                  left = back(r) - front(r);
                  most = b;
                }
            }
          if (most < 0)
            return -1;
          std::uint64_t r = blocks_[most].range.load(std::memory_order_acquire);
          while (front(r) < back(r))
            if (blocks_[most].range.compare_exchange_weak(r, pack(front(r), back(r) - 1),
                                                          std::memory_order_acq_rel))
              return static_cast<int>(back(r) - 1);
        }
    }

  private:
    static std::uint64_t pack(const std::uint64_t f, const std::uint64_t b) { return f << 32 | b; }
    static std::uint32_t front(const std::uint64_t r) { return static_cast<std::uint32_t>(r >> 32); }
    static std::uint32_t back(const std::uint64_t r) { return static_cast<std::uint32_t>(r); }

    struct alignas(64) Block // one cache line each: the owners do not share lines
    {
      std::atomic<std::uint64_t> range{0}; // front << 32 | back: chunks [front, back) untaken
    };
    std::unique_ptr<Block[]> blocks_;
    int                      n_blocks_ = 0;
  };
} // namespace sph
