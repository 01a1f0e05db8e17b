#pragma once
/// @file
/// A compliant load frame: a linear spring of stiffness k between the actuator, whose motion is
/// prescribed, and a rigid platen of mass m that the spring drives along the loading axis z, with
/// a dashpot c = 2 zeta sqrt(k m) beside the spring (a frame's own damping: without it the platen
/// and the specimen ring on the spring at their common frequency for the whole test).
/// The platen moves by the actuator's displacement minus the spring's stretch, so a machine
/// that reads the actuator's stroke sees the specimen in series with the frame:
/// 1/k_read = 1/k_specimen + 1/k_frame for the load's increments (quasi-statically; at a steady
/// loading rate the dashpot carries a constant force, which shifts the stroke, not its slope).
///
/// Central differences at the platen's time levels (as fem::SteelBody): step(v_a, f, dt) takes
/// the actuator's velocity at the half step, v_a(t + dt/2), and the z-force f(t) [N] that the
/// rest of the model (the rock, through the contact) applies to the platen, and gives the
/// platen's velocity v(t + dt/2) = v(t - dt/2) + dt (F_frame(t) + f(t)) / m with the frame's force
/// F_frame(t) = k (u_a(t) - u(t)) + c (v_a - v)(t - dt/2) (the dashpot on the last half-step
/// velocities: explicit, stable for c dt / m < 2); the platen body is then moved with that
/// velocity, and its load cell reads F_frame (what a load cell in the frame reads). Plain data,
/// no deal.II.

#include <cmath>
#include <stdexcept>
#include <vector>

namespace fem
{
  /// The spring of a load frame and the rigid platen it drives (z only).
  class LoadFrame
  {
  public:
    /// `stiffness` k > 0 [N/m], `mass` m > 0 of the rigid platen [kg], `damping_ratio` zeta >= 0
    /// of the dashpot c = 2 zeta sqrt(k m) [-].
    LoadFrame(const double stiffness, const double mass, const double damping_ratio)
        : k_(stiffness)
        , m_(mass)
        , c_(2.0 * damping_ratio * std::sqrt(stiffness * mass))
    {
      if (!(k_ > 0) || !(m_ > 0) || !(damping_ratio >= 0))
        throw std::invalid_argument(
          "fem::LoadFrame: stiffness and mass must be > 0 and the damping ratio >= 0");
    }

    /// Largest step [s] at which the frame alone is stable with central differences and the
    /// explicit dashpot: (2 / omega) (sqrt(1 + zeta^2) - zeta), omega = sqrt(k / m).
    double stable_time_step() const
    {
      const double omega = std::sqrt(k_ / m_), zeta = c_ / (2.0 * std::sqrt(k_ * m_));
      return 2.0 / omega * (std::sqrt(1.0 + zeta * zeta) - zeta);
    }

    /// One step from t to t + dt [s]: `actuator_velocity` v_a(t + dt/2) [m/s], `force` f(t) on
    /// the platen along z [N] (besides the frame's). Returns the platen's v(t + dt/2) [m/s].
    double step(const double actuator_velocity, const double force, const double dt)
    {
      const double F = frame_force();
      const double v_old = v_;
      v_ += dt * (F + force) / m_;
      // the dashpot's work over the step, with the mean of the relative velocities around t
      dissipated_ += c_ * (v_a_ - v_old) * (v_a_ - v_old) * dt;
      u_ += dt * v_;
      u_a_ += dt * actuator_velocity;
      v_a_ = actuator_velocity;
      return v_;
    }

    /// The frame's force on the platen along z, k (u_a - u) + c (v_a - v) [N] (a top platen
    /// pushed down: < 0); what a load cell in the frame reads.
    double frame_force() const { return spring_force() + c_ * (v_a_ - v_); }
    /// The spring's part, k (u_a - u) [N].
    double spring_force() const { return k_ * (u_a_ - u_); }
    /// Energy the dashpot has dissipated [J].
    double dissipated_energy() const { return dissipated_; }
    /// Energy stored in the spring, 1/2 k (u_a - u)^2 [J].
    double spring_energy() const { return 0.5 * k_ * (u_a_ - u_) * (u_a_ - u_); }
    double actuator_displacement() const { return u_a_; } ///< u_a along z [m]
    double platen_displacement() const { return u_; }     ///< u along z [m]
    double platen_velocity() const { return v_; }         ///< v at the last half step [m/s]
    double stiffness() const { return k_; }               ///< k [N/m]

    /// The state (u_a, u, v, v_a, dissipated) for checkpoints.
    std::vector<double> state() const { return {u_a_, u_, v_, v_a_, dissipated_}; }
    /// Restores state(); std::invalid_argument on a wrong size.
    void set_state(const std::vector<double> &s)
    {
      if (s.size() != 5)
        throw std::invalid_argument("fem::LoadFrame: the state has 5 values");
      u_a_ = s[0], u_ = s[1], v_ = s[2], v_a_ = s[3], dissipated_ = s[4];
    }

  private:
    double k_, m_, c_;
    double u_a_ = 0, u_ = 0, v_ = 0, v_a_ = 0, dissipated_ = 0;
  };
} // namespace fem
