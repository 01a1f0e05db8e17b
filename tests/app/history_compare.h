#pragma once
// Bitwise comparison of two run histories, and what the restart tests of the laboratory and
// cutting drivers record of a run.
#include <coupling/run_output.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
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

  /// Keeps a run's history rows and its last checkpoint.
  struct Recorder : coupling::RunObserver
  {
    std::vector<coupling::HistoryRow> rows;
    coupling::StateArrays last_checkpoint;
    std::size_t checkpoint_step = 0, n_checkpoints = 0;
    void history(const coupling::HistoryRow &r) override { rows.push_back(r); }
    void checkpoint(std::size_t step, const coupling::StateArrays &state, const coupling::StateRows *) override
    {
      last_checkpoint = state;
      checkpoint_step = step;
      ++n_checkpoints;
    }
  };

  /// Largest |value| of one array of a checkpoint (throws if it has no such array).
  inline double max_abs(const coupling::StateArrays &s, const std::string &name)
  {
    double m = 0;
    for (const double v : s.at(name))
      m = std::max(m, std::abs(v));
    return m;
  }
} // namespace cosim_test
