#pragma once
/// @file
/// Where and how a specimen fails, as numbers a test can check and summary.json reports: where
/// the first particles yield (BTS: at the disc centre?), how much of the specimen is damaged at
/// the end and, for BTS, whether the damage lies along the loaded diameter. Internal to the
/// coupling library.

#include <coupling/run_output.h>

#include <sph/types.h>

#include <vector>

namespace sph
{
  template <int dim>
  class Body;
  class Domain;
}

namespace coupling
{
  /// Watches the damage of a UCS / CTCS cylinder (axis z) or a BTS disc (axis y, loaded along z).
  class FailureWatch
  {
  public:
    /// `disc`: BTS (distances in the disc's x-z plane); else a cylinder (radial distances in x-y).
    /// The centre and radius are taken from the body's reference positions.
    FailureWatch(const sph::Body<3> &body, bool disc);
    /// The same from the whole body's reference positions [m] and volumes [m^3] (a distributed
    /// body, whose parts hold only some of the particles).
    FailureWatch(const std::vector<sph::Vector<3>> &x0, const std::vector<double> &v0, bool disc);

    /// Call at every history row: the first call that finds a damaged particle (damage > 0)
    /// records where the damage started and the specimen stress then [Pa]. With `domain` (a
    /// distributed body): over the owned particles of every rank (collective); also report.
    void observe(const sph::Body<3> &body, double stress, const sph::Domain *domain = nullptr);

    /// Adds to s.extra: failure_onset_stress_MPa, failure_onset_radius_ratio (mean distance of
    /// the first damaged particles from the centre / radius: disc plane for BTS, from the axis
    /// for a cylinder), failure_onset_height_ratio (cylinder: mean |z - centre| / half length),
    /// damaged_volume_fraction (damage >= 0.5 at the end) and, for BTS, crack_alignment (standard
    /// deviation along the loaded diameter / across it, of the particles with damage >= 0.5;
    /// across at least the particles' own width, V^(1/3) / sqrt(12), a crack's resolution).
    /// NaN where nothing was damaged. Then failure_mode_none, _tensile, _shear and _crushed:
    /// the number of particles that failed each way (sph::FailureMode) at the end.
    void report(const sph::Body<3> &body, Summary &s, const sph::Domain *domain = nullptr) const;

    /// The watch's state, for checkpoints.
    std::vector<double> state() const;
    void set_state(const std::vector<double> &state);

  private:
    bool disc_;
    double centre_[3] = {0, 0, 0};
    double radius_ = 0, half_length_ = 0;
    bool started_ = false;
    double onset_stress_ = 0, onset_radius_ = 0, onset_height_ = 0;
  };
} // namespace coupling
