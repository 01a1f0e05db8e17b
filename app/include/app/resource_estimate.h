#pragma once
/// @file
/// What a case will cost before anything is allocated: particles from the specimen (or block)
/// volume / spacing^3, time steps from the loading time and the CFL step, memory from the
/// measured bytes per particle. `cosim run`, `study` and `diagnose --coupled-spacing` refuse a
/// case whose memory estimate exceeds the machine's available memory (exit 2, naming the
/// estimate and the finest spacing that fits); --memory-limit GIB allows more (or less).

#include <coupling/case_parameters.h>

#include <cstddef>
#include <optional>
#include <string>

namespace app
{
  /// Marginal memory of one rock particle with its share of the FEM platens, neighbour lists,
  /// snapshots and history [bytes]: the peak RSS (/usr/bin/time -v) of the default UCS case, one
  /// thread, at 5, 2.5 and 2 mm spacing (1,600, 12,640, 24,450 particles: 173.4, 207.6, 246.9
  /// MiB) grows by 3,170 and 3,410 B per particle; the larger, rounded up.
  constexpr double bytes_per_particle = 3500;
  /// Memory of a run with (almost) no particles: program, libraries, deal.II, PETSc [bytes].
  constexpr double base_bytes = 175e6;

  /// The cost of one case, before it runs.
  struct ResourceEstimate
  {
    double n_particles = 0; ///< rock particles (volume / dx^3)
    double n_steps     = 0; ///< explicit time steps (loading time / CFL step), order of magnitude
    double bytes       = 0; ///< peak memory [bytes]
    double volume      = 0; ///< rock volume [m^3]
  };

  /// Estimates a case read by read_case_file (UCS, BTS, CTCS, indentation, linear-cutting).
  ResourceEstimate estimate_resources(const coupling::CaseParameters &p);

  /// Estimate for a rock volume [m^3] at spacing `dx` [m] (particles and memory only).
  ResourceEstimate estimate_for_volume(double volume, double dx);

  /// Memory this process may use [bytes]: the smaller of MemAvailable (/proc/meminfo) and the
  /// cgroup limit (memory.max), or nothing when neither can be read.
  std::optional<double> available_memory();

  /// The finest spacing [m] whose estimate fits `bytes` for rock volume `volume` [m^3].
  double finest_spacing_within(double volume, double bytes);

  /// Throws InputError (one line: what, the estimate, the memory available, the finest spacing
  /// that fits and how to allow more) when `e` needs more than `limit_bytes` (default: 90 % of
  /// available_memory()). `what` names the culprit, e.g. "SPH/Particle spacing = 1e-05 m".
  /// `allow_option` is the option that raises the limit, e.g. "--memory-limit GIB".
  void check_resources(const ResourceEstimate &e, const std::string &what, std::optional<double> limit_bytes,
                       const std::string &allow_option);

  /// "12.3 GiB", "850 MiB".
  std::string format_bytes(double bytes);
} // namespace app
