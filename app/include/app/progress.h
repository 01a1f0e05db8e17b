#pragma once
/// @file
/// Progress of a run on stderr: step, simulated time, percent of the load path, wall time and
/// time left. Rewritten in place (\r) on a terminal; plain lines every ~10 s otherwise.

#include <chrono>
#include <cstddef>
#include <cstdio>
#include <string>

namespace app
{
  /// Prints progress lines; silent when disabled.
  class ProgressDisplay
  {
  public:
    /// `enabled` false: prints nothing. `terminal` decides in-place updates (default: isatty).
    explicit ProgressDisplay(bool enabled, std::FILE *stream = stderr);
    ProgressDisplay(bool enabled, std::FILE *stream, bool terminal, double line_interval_s);

    /// Reports the state; prints when due. fraction in [0, 1] of the planned load path.
    void update(std::size_t step, double time, double fraction);
    /// Ends the in-place line (prints the last state).
    void finish();

    /// The text of one progress line (no newline), e.g. for tests.
    static std::string format(std::size_t step, double time, double fraction, double wall_s);

  private:
    void print(bool final);

    bool enabled_;
    std::FILE *stream_;
    bool terminal_;
    double interval_s_;
    std::chrono::steady_clock::time_point start_;
    std::chrono::steady_clock::time_point last_print_;
    bool printed_ = false;
    std::size_t step_ = 0;
    double time_ = 0, fraction_ = 0;
    std::size_t last_width_ = 0;
  };
} // namespace app
