#pragma once
// Bitwise comparison of two run histories (the restart tests of the laboratory and cutting
// drivers).
#include <coupling/run_output.h>

#include <gtest/gtest.h>

#include <cstring>
#include <vector>

namespace cosim_test
{
  /// Bitwise equality of two histories (HistoryRow is 15 doubles, no padding).
  inline ::testing::AssertionResult identical(const std::vector<coupling::HistoryRow> &a,
                                              const std::vector<coupling::HistoryRow> &b)
  {
    static_assert(sizeof(coupling::HistoryRow) == 15 * sizeof(double));
    if (a.size() != b.size())
      return ::testing::AssertionFailure() << a.size() << " rows against " << b.size();
    for (std::size_t k = 0; k < a.size(); ++k)
      if (std::memcmp(&a[k], &b[k], sizeof(coupling::HistoryRow)) != 0)
        return ::testing::AssertionFailure()
               << "row " << k << " differs (t = " << a[k].time << " / " << b[k].time << " s, force "
               << a[k].force << " / " << b[k].force << " N)";
    return ::testing::AssertionSuccess();
  }
} // namespace cosim_test
