// Up-front cost of a case (app/resource_estimate.h).
#include <app/resource_estimate.h>
#include <coupling/errors.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace app
{
  using coupling::InputError;

  namespace
  {
    constexpr double pi = 3.14159265358979323846;

    std::string format_number(const double v)
    {
      char buffer[32];
      std::snprintf(buffer, sizeof buffer, "%.3g", v);
      return buffer;
    }
  } // namespace

  std::string format_bytes(const double bytes)
  {
    char buffer[32];
    if (bytes >= 1024.0 * 1024 * 1024)
      std::snprintf(buffer, sizeof buffer, "%.3g GiB", bytes / (1024.0 * 1024 * 1024));
    else
      std::snprintf(buffer, sizeof buffer, "%.3g MiB", bytes / (1024.0 * 1024));
    return buffer;
  }

  ResourceEstimate estimate_for_volume(const double volume, const double dx)
  {
    ResourceEstimate e;
    e.volume      = volume;
    e.n_particles = volume / (dx * dx * dx);
    e.bytes       = base_bytes + bytes_per_particle * e.n_particles;
    return e;
  }

  ResourceEstimate estimate_resources(const coupling::CaseParameters &p)
  {
    const bool cutting  = p.test == "indentation" || p.test == "linear-cutting";
    const double volume = cutting ? p.cutter.block_length * p.cutter.block_width * p.cutter.block_height
                                  : pi / 4 * p.diameter * p.diameter * p.length;
    ResourceEstimate e = estimate_for_volume(volume, p.sph.spacing);
    // time steps: dt = TSSFAC CSLH dx / c with the bar speed c; the loading time as the drivers
    // plan it (derived rate: Loading/Transit times wave transits to the failure strain)
    const auto &r       = p.rock;
    const double c      = std::sqrt(std::max(r.youngs_modulus, 1.0) / std::max(r.density, 1.0));
    const double dt     = std::max(p.sph.tssfac * p.sph.cslh * p.sph.spacing / c, 1e-300);
    double loading_time = 0;
    if (cutting)
      loading_time = (p.test == "indentation" ? p.cutter.penetration : p.cutter.cut_length) / std::max(p.cutter.speed, 1e-12);
    else
    {
      const double length = p.test == "BTS" ? p.diameter : p.length;
      loading_time        = p.loading.strain_rate > 0 ? p.loading.end_strain / p.loading.strain_rate
                                                      : p.loading.transit_times * length / c * 1.5;
    }
    e.n_steps = loading_time / dt;
    return e;
  }

  std::optional<double> available_memory()
  {
    std::optional<double> available;
    std::ifstream meminfo("/proc/meminfo");
    std::string key;
    double value = 0;
    std::string unit;
    while (meminfo >> key >> value)
    {
      std::getline(meminfo, unit);
      if (key == "MemAvailable:")
        available = value * 1024;
    }
    std::ifstream cgroup("/sys/fs/cgroup/memory.max");
    std::string limit;
    if (cgroup >> limit && limit != "max")
    {
      std::istringstream in(limit);
      double bytes = 0;
      if (in >> bytes && bytes > 0)
        available = available ? std::min(*available, bytes) : bytes;
    }
    return available;
  }

  double finest_spacing_within(const double volume, const double bytes)
  {
    const double n = std::max((bytes - base_bytes) / bytes_per_particle, 1.0);
    return std::cbrt(volume / n);
  }

  void check_resources(const ResourceEstimate &e, const std::string &what, std::optional<double> limit_bytes,
                       const std::string &allow_option)
  {
    std::string source;
    if (!limit_bytes)
    {
      const auto available = available_memory();
      if (!available)
        return; // nothing to compare with
      limit_bytes = 0.9 * *available;
      source      = "90 % of the " + format_bytes(*available) + " available on this machine";
    }
    else
      source = "the limit of " + format_bytes(*limit_bytes);
    if (e.bytes <= *limit_bytes)
      return;
    if (*limit_bytes < 1.1 * base_bytes)
      throw InputError(what + " needs about " + format_bytes(e.bytes) + " of memory; " + source +
                       " is below the " + format_bytes(base_bytes) +
                       " the program needs without particles (raise it with " + allow_option + ")");
    // rounded up so that the spacing named fits
    const double finest = 1.005 * finest_spacing_within(e.volume, *limit_bytes);
    const std::string steps = e.n_steps > 0 ? format_number(e.n_steps) + " time steps and " : std::string("and ");
    throw InputError(what + " needs about " + format_number(e.n_particles) + " particles, " + steps +
                     format_bytes(e.bytes) + " of memory, more than " +
                     source + "; the finest spacing that fits is " + format_number(finest) +
                     " m (or allow more with " + allow_option + ")");
  }
} // namespace app
