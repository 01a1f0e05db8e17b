#include "failure_pattern.h"

#include <sph/body.h>
#include <sph/domain.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace coupling
{
  namespace
  {
    // damage at which a particle counts as failed in the end-of-run pattern (half its strength
    // lost to softening: clearly in a crack or band, not just touched by yield)
    constexpr double damaged = 0.5;
  } // namespace

  FailureWatch::FailureWatch(const sph::Body<3> &body, const bool disc)
    : FailureWatch(body.reference_positions(), body.volumes(), disc)
  {}

  FailureWatch::FailureWatch(const std::vector<sph::Vector<3>> &x0, const std::vector<double> &v0,
                             const bool disc)
    : disc_(disc)
  {
    double volume  = 0;
    for (std::size_t i = 0; i < x0.size(); ++i)
    {
      for (int d = 0; d < 3; ++d)
        centre_[d] += v0[i] * x0[i][d];
      volume += v0[i];
    }
    for (double &c : centre_)
      c /= volume;
    for (const auto &p : x0)
    {
      const double r = disc_ ? std::hypot(p[0] - centre_[0], p[2] - centre_[2])
                             : std::hypot(p[0] - centre_[0], p[1] - centre_[1]);
      radius_        = std::max(radius_, r);
      half_length_   = std::max(half_length_, std::abs(p[2] - centre_[2]));
    }
  }

  void FailureWatch::observe(const sph::Body<3> &body, const double stress,
                             const sph::Domain *domain)
  {
    if (started_)
      return;
    const auto &x0 = body.reference_positions();
    double r = 0, z = 0, n = 0;
    const std::uint8_t *owned = domain ? domain->owned().data() : nullptr;
    for (unsigned int i = 0; i < body.n_particles(); ++i)
    {
      if (body.damage(i) <= 0 || (owned && !owned[i]))
        continue;
      const auto &p = x0[i];
      r += disc_ ? std::hypot(p[0] - centre_[0], p[2] - centre_[2])
                 : std::hypot(p[0] - centre_[0], p[1] - centre_[1]);
      z += std::abs(p[2] - centre_[2]);
      n += 1;
    }
    if (domain)
    {
      const std::vector<double> all = domain->sum({r, z, n});
      r = all[0], z = all[1], n = all[2];
    }
    if (n == 0)
      return;
    started_      = true;
    onset_stress_ = stress;
    onset_radius_ = r / n / radius_;
    onset_height_ = z / n / half_length_;
  }

  void FailureWatch::report(const sph::Body<3> &body, Summary &s, const sph::Domain *domain) const
  {
    const std::uint8_t *owned = domain ? domain->owned().data() : nullptr;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    s.extra.emplace_back("failure_onset_stress_MPa", started_ ? onset_stress_ / 1e6 : nan);
    s.extra.emplace_back("failure_onset_radius_ratio", started_ ? onset_radius_ : nan);
    if (!disc_)
      s.extra.emplace_back("failure_onset_height_ratio", started_ ? onset_height_ : nan);
    const auto &x0 = body.reference_positions();
    const auto &v0 = body.volumes();
    double v_all = 0, v_failed = 0;
    // second moments of the failed particles in the disc plane: along the load (z), across (x);
    // sw: their own widths' variance, cell^2 / 12 with cell = V^(1/3)
    double n = 0, sx = 0, sz = 0, sxx = 0, szz = 0, sw = 0;
    for (unsigned int i = 0; i < body.n_particles(); ++i)
    {
      if (owned && !owned[i])
        continue;
      v_all += v0[i];
      if (body.damage(i) < damaged)
        continue;
      v_failed += v0[i];
      const double x = x0[i][0] - centre_[0], z = x0[i][2] - centre_[2];
      n += 1;
      sx += x;
      sz += z;
      sxx += x * x;
      szz += z * z;
      sw += std::cbrt(v0[i] * v0[i]) / 12.0;
    }
    if (domain)
    {
      const std::vector<double> all = domain->sum({v_all, v_failed, n, sx, sz, sxx, szz, sw});
      v_all = all[0], v_failed = all[1], n = all[2], sx = all[3], sz = all[4], sxx = all[5],
      szz = all[6], sw = all[7];
    }
    s.extra.emplace_back("damaged_volume_fraction", v_failed / v_all);
    // particles per failure mode (sph::FailureMode)
    double count[4] = {0, 0, 0, 0};
    for (unsigned int i = 0; i < body.n_particles(); ++i)
      if (!owned || owned[i])
        count[static_cast<int>(body.history(i).failure_mode)] += 1;
    if (domain)
    {
      const std::vector<double> all = domain->sum({count[0], count[1], count[2], count[3]});
      for (int k = 0; k < 4; ++k)
        count[k] = all[k];
    }
    s.extra.emplace_back("failure_mode_none", count[0]);
    s.extra.emplace_back("failure_mode_tensile", count[1]);
    s.extra.emplace_back("failure_mode_shear", count[2]);
    s.extra.emplace_back("failure_mode_crushed", count[3]);
    if (disc_)
    {
      // across, a crack is at least a particle wide: a split one column wide (the body-fitted
      // disc's particles on the loaded diameter, x = 0 to round-off) is resolved no finer, and
      // its centres' variance alone, round-off of 1e-35 m^2, gave alignments of 1e16
      const double var_x = n > 1 ? std::max(sxx / n - (sx / n) * (sx / n), sw / n) : 0.0;
      const double var_z = n > 1 ? szz / n - (sz / n) * (sz / n) : 0.0;
      s.extra.emplace_back("crack_alignment",
                           var_x > 0 ? std::sqrt(var_z / var_x) : nan);
    }
  }

  std::vector<double> FailureWatch::state() const
  {
    return {started_ ? 1.0 : 0.0, onset_stress_, onset_radius_, onset_height_};
  }

  void FailureWatch::set_state(const std::vector<double> &state)
  {
    if (state.size() != 4)
      throw std::invalid_argument("failure watch state: expected 4 values");
    started_      = state[0] != 0.0;
    onset_stress_ = state[1];
    onset_radius_ = state[2];
    onset_height_ = state[3];
  }
} // namespace coupling
