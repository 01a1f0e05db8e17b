#include <app/progress.h>

#include <algorithm>
#include <cmath>
#include <unistd.h>

namespace app
{
  namespace
  {
    std::string clock_text(double seconds)
    {
      if (!std::isfinite(seconds) || seconds < 0)
        return "--:--";
      const long s = std::lround(seconds);
      char buffer[32];
      if (s >= 3600)
        std::snprintf(buffer, sizeof buffer, "%ld:%02ld:%02ld", s / 3600, (s / 60) % 60, s % 60);
      else
        std::snprintf(buffer, sizeof buffer, "%02ld:%02ld", s / 60, s % 60);
      return buffer;
    }
  } // namespace

  ProgressDisplay::ProgressDisplay(bool enabled, std::FILE *stream)
    : ProgressDisplay(enabled, stream, isatty(fileno(stream)) != 0, 10.0)
  {}

  ProgressDisplay::ProgressDisplay(bool enabled, std::FILE *stream, bool terminal, double line_interval_s)
    : enabled_(enabled)
    , stream_(stream)
    , terminal_(terminal)
    , interval_s_(terminal ? 0.2 : line_interval_s)
    , start_(std::chrono::steady_clock::now())
    , last_print_(start_)
  {}

  std::string ProgressDisplay::format(std::size_t step, double time, double fraction, double wall_s)
  {
    fraction = std::clamp(fraction, 0.0, 1.0);
    const double left = fraction > 1e-6 ? wall_s * (1 - fraction) / fraction : -1;
    char buffer[160];
    std::snprintf(buffer, sizeof buffer, "step %zu  t = %.4g s  load path %5.1f %%  wall %s  left %s", step, time,
                  100 * fraction, clock_text(wall_s).c_str(), clock_text(left).c_str());
    return buffer;
  }

  void ProgressDisplay::update(std::size_t step, double time, double fraction)
  {
    step_ = step, time_ = time, fraction_ = fraction;
    if (!enabled_)
      return;
    const auto now = std::chrono::steady_clock::now();
    if (std::chrono::duration<double>(now - last_print_).count() >= interval_s_)
    {
      last_print_ = now;
      print(false);
    }
  }

  void ProgressDisplay::print(bool final)
  {
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    std::string text = format(step_, time_, fraction_, wall);
    if (terminal_)
    {
      const std::size_t width = text.size();
      if (width < last_width_)
        text += std::string(last_width_ - width, ' ');
      last_width_ = width;
      std::fprintf(stream_, "\r%s%s", text.c_str(), final ? "\n" : "");
    }
    else
      std::fprintf(stream_, "%s\n", text.c_str());
    std::fflush(stream_);
    printed_ = true;
  }

  void ProgressDisplay::finish()
  {
    if (enabled_ && (printed_ || terminal_))
      print(true);
  }
} // namespace app
