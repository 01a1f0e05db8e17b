// SPH/Threads holds for the coupling's own OpenMP loops while a run lives, and the caller's
// thread count comes back after it (coupling::ThreadLimit, used by run_case).
#include "../../coupling/src/driver_common.h"

#include <gtest/gtest.h>
#include <omp.h>

namespace
{
  int threads_in_a_parallel_region()
  {
    int n = 0;
#pragma omp parallel
    {
#pragma omp single
      n = omp_get_num_threads();
    }
    return n;
  }
} // namespace

TEST(ThreadLimit, SetsTheCountForTheRunAndRestoresIt)
{
  const int before = omp_get_max_threads();
  {
    const coupling::ThreadLimit limit(1);
    EXPECT_EQ(1, omp_get_max_threads());
    EXPECT_EQ(1, threads_in_a_parallel_region()); // a loop without num_threads runs on one
    {
      const coupling::ThreadLimit nested(3);
      EXPECT_EQ(3, omp_get_max_threads());
    }
    EXPECT_EQ(1, omp_get_max_threads()); // the inner run's end restores the outer one's
  }
  EXPECT_EQ(before, omp_get_max_threads());
  {
    const coupling::ThreadLimit all(0); // 0: all cores, i.e. what the caller had
    EXPECT_EQ(before, omp_get_max_threads());
  }
  EXPECT_EQ(before, omp_get_max_threads());
}
