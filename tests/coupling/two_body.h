#pragma once
// Test fixture: one SPH rock body and one FEM body (fem::SteelBody) coupled through PenaltyContact
// (penalty or kinematic),
// stepped exactly as the UCS/BTS/CTCS driver steps them (coupling/src/specimen_driver.cc): contact
// forces at the start of the step, SPH integrated with dt, the FEM body sub-cycled with dt/n and
// the platen force held over the sub-steps, so that both sides receive the same impulse f dt.
#include "../../coupling/src/driver_common.h"

#include <coupling/contact.h>

#include <fem/steel_body.h>
#include <sph/body.h>
#include <sph/lattice.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <memory>
#include <vector>

namespace coupling::testing
{
  /// Sum of the 3-vectors of a flat array.
  inline std::array<double, 3> vector_sum(const std::vector<double> &f)
  {
    std::array<double, 3> s{{0, 0, 0}};
    for (std::size_t i = 0; i < f.size(); ++i)
      s[i % 3] += f[i];
    return s;
  }

  class TwoBody
  {
  public:
    /// contact_scale: the penalty stiffness as a fraction of its central-difference bound at the
    /// rock's stable step for the lightest particle against the lightest contact node (rigid: the
    /// particle alone), the step shortened by coupled_time_step(), as in the driver.
    TwoBody(std::unique_ptr<sph::Body<3>> rock, std::unique_ptr<fem::SteelBody> platen,
            double contact_scale, double friction_static = 0, double friction_dynamic = 0,
            ContactMethod method = ContactMethod::penalty)
        : rock_(std::move(rock))
        , platen_(std::move(platen))
        , method_(method)
    {
      const double dt_rock = rock_->stable_time_step();
      // the kinematic constraint has no stiffness and adds no bound (contact_scale unused)
      dt_ =
        method == ContactMethod::kinematic ? dt_rock : coupled_time_step(dt_rock, contact_scale);
      const double dt_fem = platen_->stable_time_step();
      // as the specimen driver: the kinematic constraint steps both bodies at the smaller step
      // (its prediction of the face is exact over one platen step); the penalty one sub-cycles
      if (method == ContactMethod::kinematic && std::isfinite(dt_fem))
        dt_ = std::min(dt_, dt_fem);
      n_sub_ = std::isfinite(dt_fem) ? std::max(1, int(std::ceil(dt_ / dt_fem))) : 1;
      const auto &m       = rock_->masses();
      const double m_p    = *std::min_element(m.begin(), m.end());
      double m_n          = 0;
      if (!platen_->is_rigid())
      {
        const auto mn = platen_->contact_masses();
        m_n           = *std::min_element(mn.begin(), mn.end());
      }
      ContactParameters cp;
      cp.stiffness        = contact_scale * stable_contact_stiffness(m_p, m_n, dt_rock);
      cp.friction_static  = friction_static;
      cp.friction_dynamic = friction_dynamic;
      cp.radius           = 0.5 * rock_->parameters().spacing;
      cp.method           = method;
      if (method == ContactMethod::kinematic)
        cp.stiffness = 0;
      stiffness_ = cp.stiffness;
      contact_   = std::make_unique<PenaltyContact>(cp, rock_->n_particles());
      f_rock_.assign(3 * rock_->n_particles(), 0.0);
      f_platen_.assign(3 * platen_->n_contact_nodes(), 0.0);
    }

    /// One coupled step. `extra` may add forces [N] to the rock's external forces (loads,
    /// damping); they act before the contact, so that the kinematic method predicts with them.
    void step(const std::function<void(sph::Body<3> &)> &extra = {})
    {
      rock_->compute_forces();
      if (extra)
        extra(*rock_);
      const bool kinematic = method_ == ContactMethod::kinematic;
      surface_ =
        kinematic ? predicted_contact_surface(*platen_, dt_) : contact_surface(*platen_);
      const auto &x = rock_->positions();
      const auto &v = rock_->velocities();
      ContactParticles particles{x.front().data(), v.front().data(), rock_->masses().data(),
                                 rock_->n_particles()};
      if (kinematic) // the force of the step before contact, as the driver predicts with it
      {
        const auto &fi = rock_->internal_forces(), &fp = rock_->pressure_forces();
        const auto &fe = rock_->external_forces();
        force_before_.resize(3 * rock_->n_particles());
        for (unsigned int i = 0; i < rock_->n_particles(); ++i)
          for (int d = 0; d < 3; ++d)
            force_before_[3 * i + d] = fi[i][d] + fp[i][d] + fe[i][d];
        particles.force = force_before_.data();
      }
      std::fill(f_rock_.begin(), f_rock_.end(), 0.0);
      std::fill(f_platen_.begin(), f_platen_.end(), 0.0);
      n_contact_  = contact_->apply(particles, surface_, dt_, f_rock_, f_platen_);
      auto &f_ext = rock_->external_forces();
      for (unsigned int i = 0; i < rock_->n_particles(); ++i)
        for (int d = 0; d < 3; ++d)
          f_ext[i][d] += f_rock_[3 * i + d];
      rock_->integrate(dt_);
      const double h = dt_ / n_sub_;
      for (int k = 0; k < n_sub_; ++k)
      {
        platen_->add_contact_forces(f_platen_);
        platen_->step(time_ + k * h, h);
      }
      time_ += dt_;
    }

    sph::Body<3> &rock() { return *rock_; }
    fem::SteelBody &platen() { return *platen_; }
    const PenaltyContact &contact() const { return *contact_; }
    const std::vector<double> &force_on_rock() const { return f_rock_; }
    const std::vector<double> &force_on_platen() const { return f_platen_; }
    std::size_t n_contact() const { return n_contact_; }
    double dt() const { return dt_; }
    int n_substeps() const { return n_sub_; }
    double time() const { return time_; }
    double stiffness() const { return stiffness_; }

    /// Momentum of the FEM body [kg m/s] (v at the last half step).
    std::array<double, 3> platen_momentum() const
    {
      const auto m = platen_->nodal_masses();
      const auto v = platen_->mesh_snapshot().velocity;
      std::array<double, 3> p{{0, 0, 0}};
      for (std::size_t i = 0; i < v.size(); ++i)
        p[i % 3] += m[i / 3] * v[i];
      return p;
    }

  private:
    std::unique_ptr<sph::Body<3>> rock_;
    std::unique_ptr<fem::SteelBody> platen_;
    std::unique_ptr<PenaltyContact> contact_;
    ContactSurface surface_;
    std::vector<double> f_rock_, f_platen_, force_before_;
    ContactMethod method_ = ContactMethod::penalty;
    double dt_ = 0, time_ = 0, stiffness_ = 0;
    int n_sub_             = 1;
    std::size_t n_contact_ = 0;
  };

  /// An elastic rock body on a block lattice.
  inline std::unique_ptr<sph::Body<3>> rock_block(const sph::Vector<3> &lower,
                                                  const sph::Vector<3> &upper, double dx,
                                                  double youngs_modulus, double poissons_ratio,
                                                  double density)
  {
    sph::Parameters p;
    p.spacing   = dx;
    p.n_threads = 1; // small bodies: threads cost more than they give on a loaded CI machine
    sph::MaterialParameters m;
    m.model            = sph::RockModel::elastic;
    m.youngs_modulus   = youngs_modulus;
    m.poissons_ratio   = poissons_ratio;
    m.density          = density;
    const auto lattice = sph::make_block<3>(lower, upper, dx);
    return std::make_unique<sph::Body<3>>(p, m, lattice.positions, lattice.volumes);
  }
} // namespace coupling::testing
