#pragma once
/// @file
/// A compliant load frame: a linear spring of stiffness k between the actuator, whose motion is
/// prescribed, and a rigid platen of mass m that the spring drives along the loading axis z.
/// The platen moves by the actuator's displacement minus the spring's stretch F / k, so a machine
/// that reads the actuator's stroke sees the specimen in series with the frame:
/// 1/k_read = 1/k_specimen + 1/k_frame (quasi-statically).
///
/// Central differences at the platen's time levels (as fem::SteelBody): step(v_a, f, dt) takes
/// the actuator's velocity at the half step, v_a(t + dt/2), and the z-force f(t) [N] that the
/// rest of the model (the rock, through the contact) applies to the platen, and gives the
/// platen's velocity v(t + dt/2) = v(t - dt/2) + dt (k (u_a(t) - u(t)) + f(t)) / m; the platen
/// body is then moved with that velocity, and its load cell reads the spring force
/// k (u_a - u) (what a frame's load cell in series reads). Plain data, no deal.II.

#include <cmath>
#include <stdexcept>
#include <vector>

namespace fem
{
  /// The spring of a load frame and the rigid platen it drives (z only).
  class LoadFrame
  {
  public:
    /// `stiffness` k > 0 [N/m], `mass` m > 0 of the rigid platen [kg].
    LoadFrame(const double stiffness, const double mass)
        : k_(stiffness)
        , m_(mass)
    {
      if (!(k_ > 0) || !(m_ > 0))
        throw std::invalid_argument("fem::LoadFrame: stiffness and mass must be > 0");
    }

    /// Largest step [s] at which the spring alone is stable with central differences, 2 / omega
    /// (omega = sqrt(k / m)).
    double stable_time_step() const { return 2.0 / std::sqrt(k_ / m_); }

    /// One step from t to t + dt [s]: `actuator_velocity` v_a(t + dt/2) [m/s], `force` f(t) on
    /// the platen along z [N] (besides the spring's). Returns the platen's v(t + dt/2) [m/s].
    double step(const double actuator_velocity, const double force, const double dt)
    {
      const double a = (spring_force() + force) / m_;
      v_ += dt * a;
      u_ += dt * v_;
      u_a_ += dt * actuator_velocity;
      return v_;
    }

    /// Spring force on the platen along z, k (u_a - u) [N] (a top platen pushed down: < 0).
    double spring_force() const { return k_ * (u_a_ - u_); }
    /// Energy stored in the spring, 1/2 k (u_a - u)^2 [J].
    double spring_energy() const { return 0.5 * k_ * (u_a_ - u_) * (u_a_ - u_); }
    double actuator_displacement() const { return u_a_; } ///< u_a along z [m]
    double platen_displacement() const { return u_; }     ///< u along z [m]
    double platen_velocity() const { return v_; }         ///< v at the last half step [m/s]
    double stiffness() const { return k_; }               ///< k [N/m]

    /// The state (u_a, u, v) for checkpoints.
    std::vector<double> state() const { return {u_a_, u_, v_}; }
    /// Restores state(); std::invalid_argument on a wrong size.
    void set_state(const std::vector<double> &s)
    {
      if (s.size() != 3)
        throw std::invalid_argument("fem::LoadFrame: the state has 3 values");
      u_a_ = s[0], u_ = s[1], v_ = s[2];
    }

  private:
    double k_, m_;
    double u_a_ = 0, u_ = 0, v_ = 0;
  };
} // namespace fem
