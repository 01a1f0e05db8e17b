#pragma once
/// @file
/// Helpers of the coupled-run tests: an observer that keeps the history rows, and a further
/// result of a run's summary that the test needs.

#include <coupling/run_output.h>

#include <gtest/gtest.h>

#include <limits>
#include <string>
#include <vector>

namespace coupling::test
{
  /// Keeps every history row of a run.
  struct Keep : RunObserver
  {
    std::vector<HistoryRow> rows;
    void history(const HistoryRow &r) override { rows.push_back(r); }
  };

  /// The further result `key` of a run (summary.json's test-specific entries). A missing one
  /// fails the test and reads NaN, so that no comparison with it can pass.
  inline double extra(const Summary &s, const std::string &key)
  {
    if (const auto value = find_extra(s, key))
      return *value;
    ADD_FAILURE() << "the summary has no " << key;
    return std::numeric_limits<double>::quiet_NaN();
  }
} // namespace coupling::test
