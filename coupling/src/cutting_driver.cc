#include "cutting_driver.h"

#include "driver_common.h"
#include "specimen_driver.h"

#include <coupling/references.h>
#include <coupling/run_case.h>

#include <fem/steel_body.h>
#include <sph/body.h>
#include <sph/domain.h>
#include <sph/lattice.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

namespace coupling
{
  namespace
  {
    constexpr double pi = 3.14159265358979323846;

    /// Velocity scale of a move of `duration` [s] that starts and stops smoothly: sin^2 ramps of
    /// `ramp` [s] at both ends, 1 between, 0 outside [0, duration]. The distance it covers at
    /// speed v is v (duration - ramp).
    double trapezoid(const double t, const double duration, const double ramp)
    {
      if (t <= 0 || t >= duration)
        return 0.0;
      const double edge = std::min(t, duration - t);
      if (edge >= ramp)
        return 1.0;
      const double s = std::sin(0.5 * pi * edge / ramp);
      return s * s;
    }

    double mean(const std::vector<double> &v)
    {
      if (v.empty())
        return std::numeric_limits<double>::quiet_NaN();
      double s = 0;
      for (const double x : v)
        s += x;
      return s / v.size();
    }

    double peak(const std::vector<double> &v)
    {
      if (v.empty())
        return std::numeric_limits<double>::quiet_NaN();
      return *std::max_element(v.begin(), v.end());
    }
  } // namespace

  CuttingDriver::CuttingDriver(const CaseParameters &parameters)
      : prm_(parameters)
  {
    cutting_ = prm_.test == "linear-cutting";
    if (!cutting_ && prm_.test != "indentation")
      throw InputError("Test/Type: '" + prm_.test + "' is not indentation or linear-cutting");
    const CutterParameters &c = prm_.cutter;
    if (cutting_ != (c.shape == "disc"))
      throw InputError("Cutter/Shape: " + c.shape + " does not fit Test/Type = " + prm_.test +
                       "; linear-cutting takes disc, indentation wedge, cone or flat");
    if (prm_.particle_arrangement != sph::ParticleArrangement::lattice)
      throw InputError("SPH/Particle arrangement: body-fitted is for the UCS/CTCS cylinder and the BTS disc; "
                       "the rock block of " + prm_.test + " is a lattice: set it to lattice");
    build_block();
    build_cutter();
    choose_time_step();

    // indentation: down to the penetration from the depth where the tip meets the first particle
    // (first contact falls in the start-up ramp). Cutting: the disc starts outside the block's
    // free entry face x = 0 with its tip already at the penetration depth and moves along +x at
    // that depth (no plunge), as a linear cutting machine takes a cut across a block.
    const double v = c.speed;
    if (cutting_)
    {
      ramp_cut_ = 0.1 * c.cut_length / v;
      t_end_    = c.cut_length / v + ramp_cut_;
    }
    else
    {
      const double down = c.penetration - depth_;
      ramp_down_        = 0.25 * down / v;
      t_down_           = down / v + ramp_down_;
      t_end_            = t_down_;
    }
  }

  CuttingDriver::~CuttingDriver() = default;

  void CuttingDriver::build_block()
  {
    const CutterParameters &c = prm_.cutter;
    const double dx           = prm_.sph.spacing;
    const sph::Vector<3> lower(0.0, -0.5 * c.block_width, -c.block_height);
    const sph::Vector<3> upper(c.block_length, 0.5 * c.block_width, 0.0);
    const sph::Lattice<3> lattice = sph::make_block<3>(lower, upper, dx);
    x0_global_                    = lattice.positions;
    if (mpi_ranks() > 1)
    {
      // this rank's part of the block (make_rock_part)
      RockPart part   = make_rock_part(prm_, lattice);
      domain_         = std::move(part.domain);
      body_           = std::move(part.body);
      n_global_pairs_ = part.n_global_pairs;
      body_->restrict_to_owned(*domain_); // each step's work: what the owned particles need
      owned_.reset(*body_, *domain_);
      for (const std::int32_t g : domain_->global_ids())
        volume0_.push_back(lattice.volumes[g]);
    }
    else
    {
      body_    = make_rock_body(prm_, lattice);
      volume0_ = lattice.volumes;
    }
    contact_radius_ = 0.5 * lattice.cell_size[2];
    // held: the bottom layer and the outermost layer of each side (x and y), all components (a
    // block clamped in the rig); the top face is free, and so is the entry face x = 0 of a cut
    auto held = [&](const sph::Vector<3> &p) {
      const bool entry = !cutting_ && p[0] < lower[0] + dx;
      return p[2] < lower[2] + dx || entry || p[0] > upper[0] - dx || p[1] < lower[1] + dx ||
             p[1] > upper[1] - dx;
    };
    const auto &x0 = body_->reference_positions();
    for (unsigned int i = 0; i < body_->n_particles(); ++i)
    {
      if (!held(x0[i]))
        continue;
      for (unsigned int d = 0; d < 3; ++d)
        body_->constrain(i, d, 0.0);
      ++n_fixed_;
    }
    if (domain_) // counted over the whole block
      n_fixed_ =
        static_cast<std::size_t>(std::count_if(x0_global_.begin(), x0_global_.end(), held));
    const std::size_t n_contact = domain_ ? domain_->owned_indices().size() : body_->n_particles();
    force_on_particles_.assign(3 * n_contact, 0.0);
    released_.assign(n_contact, 0);
    domain_size_ = 3.0 * std::max({c.block_length, c.block_width, c.block_height});
  }

  void CuttingDriver::build_cutter()
  {
    const CutterParameters &c = prm_.cutter;
    const double dx           = prm_.sph.spacing;
    // cutters are small: one particle spacing resolves the tip profile
    fem::Parameters fp = fem_parameters(prm_.platens, dx);

    fem::BodyGeometry g;
    g.side           = fem::BodySide::above;
    g.contact_z      = 0.0;
    g.thickness      = prm_.platens.thickness;
    g.tip_half_angle = 0.5 * c.tip_angle * pi / 180.0;
    g.tip_radius     = c.tip_radius;
    double rim_rise  = 0;
    if (c.shape == "wedge")
    {
      g.shape  = fem::BodyShape::wedge;
      g.size_x = c.indenter_width;
      g.size_y = c.wedge_length;
      rim_rise = 0.5 * g.size_x / std::tan(g.tip_half_angle);
    }
    else if (c.shape == "cone")
    {
      g.shape    = fem::BodyShape::cone;
      g.diameter = c.indenter_width;
      rim_rise   = 0.5 * g.diameter / std::tan(g.tip_half_angle);
    }
    else if (c.shape == "flat")
    {
      g.shape    = fem::BodyShape::cylinder;
      g.diameter = c.indenter_width;
    }
    else
    {
      // the rim segment of the disc: its chord reaches past the contact arc sqrt(2 R p) by a
      // fifth and a particle spacing, so the rock never meets the segment's ends
      g.shape         = fem::BodyShape::disc_cutter;
      g.cutter_radius = 0.5 * c.disc_diameter;
      g.size_y        = c.tip_width;
      const double R  = g.cutter_radius;
      const double a  = std::min(0.9 * R, 1.2 * std::sqrt(2.0 * R * (c.penetration + dx)));
      g.size_x        = 2.0 * a;
      rim_rise        = R - std::sqrt(R * R - a * a);
    }
    // the body must be thicker than the rise of its tip profile (fem's check): Platens/Thickness,
    // or 1.6 x the rise where that is more
    g.thickness = std::max(g.thickness, 1.6 * rim_rise);
    g.center_x  = 0.5 * c.block_length;
    g.center_y  = 0.0;
    if (cutting_)
    {
      // the disc's lowest point at the penetration depth, the front of its contact arc (sqrt(2 R
      // p) ahead of that point) one particle spacing outside the entry face x = 0
      const double R    = 0.5 * c.disc_diameter;
      const double half = 0.5 * g.size_x;
      g.center_x        = -std::sqrt(2.0 * R * c.penetration) - dx;
      g.contact_z       = -c.penetration;
      depth_            = c.penetration;
      // the segment's front end must stay clear of the held far face at the end of the cut
      const double front_end = g.center_x + c.cut_length + half;
      if (!(front_end < c.block_length - 2.0 * dx))
        throw InputError("Cutter/Cut length: the cutter's rim segment would reach " +
                         std::to_string(front_end * 1e3) + " mm, into the held far end of the " +
                         std::to_string(c.block_length * 1e3) +
                         " mm block: lengthen the block or shorten the cut");
      if (!(c.cut_length > 1.5 * (std::sqrt(2.0 * R * c.penetration) + dx)))
        throw InputError("Cutter/Cut length: too short for the disc to enter the rock fully and "
                         "cut on (at least 1.5 x (sqrt(2 R p) + spacing) = " +
                         std::to_string(1.5e3 * (std::sqrt(2.0 * R * c.penetration) + dx)) +
                         " mm)");
    }
    start_x_ = g.center_x;
    if (c.shape == "wedge" || c.shape == "cone")
    {
      // a sharp tip between lattice columns first meets a particle (contact radius r, half the
      // layer distance; centre at z = -r) at the tip depth d = r + (rho cos(alpha) - r) / sin(alpha), rho the particle's
      // lateral distance from the tip: the tip starts there instead of at z = 0 (no contact yet)
      const double r = contact_radius_, a = g.tip_half_angle;
      double rho_min = std::numeric_limits<double>::max();
      for (const auto &p : x0_global_)
        if (p[2] > -dx)
          rho_min = std::min(rho_min, c.shape == "cone" ? std::hypot(p[0] - g.center_x, p[1])
                                                        : std::abs(p[0] - g.center_x));
      // (a rounded tip: its lowest point is lower by rho (1/sin(alpha) - 1) than the sharp
      // flanks' apex, so this start is conservative: the tip meets no particle before it)
      depth_      = std::clamp(r + (rho_min * std::cos(a) - r) / std::sin(a) -
                                 c.tip_radius * (1.0 / std::sin(a) - 1.0),
                               0.0, 0.5 * c.penetration);
      g.contact_z = -depth_;
    }
    fp.loaded_face_lateral = fem::LoadedFaceLateral::fixed;
    try
    {
      cutter_ = std::make_unique<fem::SteelBody>(g, fp);
    }
    catch (const std::invalid_argument &e)
    {
      throw InputError(std::string("Cutter: ") + e.what());
    }
    cutter_->set_loaded_face_velocity([this](double t) { return cutter_velocity(t)[1]; });
    cutter_->set_loaded_face_velocity_x([this](double t) { return cutter_velocity(t)[0]; });
    force_on_cutter_.assign(3 * cutter_->n_contact_nodes(), 0.0);
  }

  std::array<double, 2> CuttingDriver::cutter_velocity(const double t) const
  {
    const double v  = prm_.cutter.speed;
    const double vz = -v * trapezoid(t, t_down_, ramp_down_);
    const double vx =
      cutting_ ? v * trapezoid(t - t_cut_start_, t_end_ - t_cut_start_, ramp_cut_) : 0.0;
    return {{vx, vz}};
  }

  void CuttingDriver::choose_time_step()
  {
    // penalty stiffness and time step as in the laboratory driver: a fraction s of the
    // central-difference bound at the rock's own step, the step shortened to count the contact
    time_step_scale_    = prm_.sph.tssfac / std::min(prm_.sph.tssfac, 1.0);
    const double dt_sph =
      (domain_ ? domain_->min(body_->stable_time_step()) : body_->stable_time_step()) *
      time_step_scale_;
    dt_                 = coupled_time_step(dt_sph, prm_.platens.contact_stiffness_scale);
    const double dt_fem = cutter_->stable_time_step();
    n_substeps_         = std::isfinite(dt_fem) ? std::max(1, int(std::ceil(dt_ / dt_fem))) : 1;
    const auto &m           = body_->masses();
    const double m_particle = domain_ ? domain_->min(*std::min_element(m.begin(), m.end()))
                                      : *std::min_element(m.begin(), m.end());
    double m_node           = 0.0;
    if (!cutter_->is_rigid())
    {
      const auto a = cutter_->contact_masses();
      m_node       = *std::min_element(a.begin(), a.end());
    }
    ContactParameters cp;
    cp.stiffness =
      prm_.platens.contact_stiffness_scale * stable_contact_stiffness(m_particle, m_node, dt_sph);
    contact_stiffness_ = cp.stiffness;
    cp.friction_static  = prm_.platens.friction;
    cp.friction_dynamic = prm_.platens.dynamic_friction < 0 ? prm_.platens.friction : prm_.platens.dynamic_friction;
    cp.radius                                = contact_radius_;
    // every cutter is convex towards the rock (flat punch: flat, where both rules agree)
    cp.convex_master = true;
    contact_         = std::make_unique<PenaltyContact>(cp, released_.size());
  }

  void CuttingDriver::release_failed_particles()
  {
    // k: the contact's particle (distributed: the k-th owned one), i: the body's
    bool changed = false;
    for (std::size_t k = 0; k < released_.size(); ++k)
    {
      const unsigned int i = domain_ ? domain_->owned_indices()[k] : static_cast<unsigned int>(k);
      if (released_[k] || body_->damage(i) < 1.0)
        continue;
      // crushed but confined rock (mean stress compressive) still carries the cutter, as the
      // crushed zone of the CSM model does; a failed particle that is no longer compressed has
      // broken out: chip
      const auto &sig = body_->stress3(i);
      if ((sig(0, 0) + sig(1, 1) + sig(2, 2)) / 3.0 < 0.0)
        continue;
      released_[k] = 1;
      changed      = true;
      ++n_released_;
      // force_on_particles_ still holds this particle's contact force of the last step: its
      // penalty (and stick-spring) energy |f|^2 / (2 k) leaves with the chip
      double f2 = 0;
      for (int d = 0; d < 3; ++d)
        f2 += force_on_particles_[3 * k + d] * force_on_particles_[3 * k + d];
      released_energy_ += 0.5 * f2 / contact_stiffness_;
    }
    if (changed)
      exclude_released();
  }

  void CuttingDriver::exclude_released()
  {
    std::vector<double> factor(released_.size());
    for (std::size_t k = 0; k < factor.size(); ++k)
      factor[k] = released_[k] ? 0.0 : 1.0;
    contact_->set_stiffness_factors(std::move(factor));
  }

  void CuttingDriver::step()
  {
    body_->compute_forces(domain_.get());
    const ContactSurface s = contact_surface(*cutter_);

    const auto &x = body_->positions();
    const auto &v = body_->velocities();
    ContactParticles particles{x.front().data(), v.front().data(), body_->masses().data(),
                               body_->n_particles()};
    if (domain_) // the owned particles only, packed
      particles = owned_.pack(*body_, *domain_);
    if (cutting_)
      release_failed_particles();
    std::fill(force_on_particles_.begin(), force_on_particles_.end(), 0.0);
    std::fill(force_on_cutter_.begin(), force_on_cutter_.end(), 0.0);
    n_in_contact_ = contact_->apply(particles, s, dt_, force_on_particles_, force_on_cutter_);
    // distributed: the cutter's nodal forces of all ranks, summed in rank order (one collective),
    // so that every rank steps the same cutter
    if (domain_)
      force_on_cutter_ = domain_->sum(force_on_cutter_);

    add_contact_forces(*body_, domain_.get(), force_on_particles_);
    body_->integrate(dt_);
    if (domain_) // the ghosts' positions and velocities from their owners
      body_->exchange_ghosts(*domain_);

    // the contact force on the cutter (what a three-axis load cell on its axle reads, less the
    // cutter's inertia) and the supports' force on the block, integrated over the step
    std::array<double, 3> f_cutter{{0, 0, 0}};
    for (std::size_t k = 0; k < force_on_cutter_.size(); ++k)
      f_cutter[k % 3] += force_on_cutter_[k];
    double support_z = 0; // (distributed: of the owned particles; summed per row)
    if (domain_)
      for (const std::int32_t i : domain_->owned_indices())
        support_z += body_->reaction_force(i)[2];
    else
      for (unsigned int i = 0; i < body_->n_particles(); ++i)
        support_z += body_->reaction_force(i)[2];
    for (int d = 0; d < 3; ++d)
      impulse_[d] += f_cutter[d] * dt_;
    support_impulse_z_ += support_z * dt_;
    impulse_time_ += dt_;

    const double h = dt_ / n_substeps_;
    for (int k = 0; k < n_substeps_; ++k)
    {
      cutter_->add_contact_forces(force_on_cutter_);
      const double t = time_ + k * h;
      cutter_->step(t, h);
      // frame work: the load cell's force times the prescribed velocity (x and z)
      const auto r   = cutter_->reaction_force_vector();
      const auto vel = cutter_velocity(t + 0.5 * h);
      frame_work_ += (r[0] * vel[0] + r[2] * vel[1]) * h;
      travel_ += vel[0] * h;
      depth_ -= vel[1] * h;
    }
    time_ += dt_;
    ++n_steps_;
  }

  HistoryRow CuttingDriver::history_row(sph::Energies &e)
  {
    e                        = body_->energies();
    double support_impulse_z = support_impulse_z_;
    double penalty           = contact_->penalty_energy();
    double friction          = contact_->friction_dissipation();
    double released_energy   = released_energy_;
    double n_failed          = 0;
    if (domain_) // the owned particles' shares of every rank (one collective)
    {
      for (const std::int32_t i : domain_->owned_indices())
        n_failed += body_->damage(i) >= 1.0 ? 1.0 : 0.0;
      const std::vector<double> all =
        domain_->sum({support_impulse_z, e.kinetic, e.internal, e.plastic, e.viscous, e.hourglass,
                      e.external, penalty, friction, released_energy, n_failed});
      support_impulse_z = all[0];
      e.kinetic = all[1], e.internal = all[2], e.plastic = all[3], e.viscous = all[4];
      e.hourglass = all[5], e.external = all[6];
      penalty = all[7], friction = all[8], released_energy = all[9], n_failed = all[10];
    }
    else
      n_failed = n_failed_particles(*body_);
    HistoryRow r;
    r.time = time_;
    // displacement: the cutter's travel (cutting) or the tip's depth (indentation)
    r.displacement = cutting_ ? travel_ : depth_;
    const double T = impulse_time_ > 0 ? impulse_time_ : 1.0;
    // normal force: the rock pushes the cutter up (+z); rolling force: it holds the cutter back
    // against its +x travel; side force: along +y
    r.force            = impulse_[2] / T;
    r.rolling_force    = -impulse_[0] / T;
    r.side_force       = impulse_[1] / T;
    r.force_bottom     = support_impulse_z / T; // the supports push the block up: + in compression
    impulse_           = {{0, 0, 0}};
    support_impulse_z_ = impulse_time_ = 0;
    // mean contact pressure on the tip's projected footprint is not defined for a sliding disc
    r.strain = depth_ / prm_.cutter.block_height;

    r.kinetic_energy      = e.kinetic + cutter_->kinetic_energy();
    r.internal_energy     = e.internal + cutter_->strain_energy() + penalty;
    r.dissipated_energy =
      e.dissipated() + friction + cutter_->damping_dissipation() + released_energy;
    r.external_work = frame_work_;
    r.n_failed      = n_failed;
    return r;
  }

  Measurement CuttingDriver::measure()
  {
    Measurement m;
    sph::Energies rock;
    m.row           = history_row(rock);
    m.rock_kinetic  = rock.kinetic;
    m.rock_internal = rock.internal;
    return m;
  }

  ParticleSnapshot CuttingDriver::particle_snapshot() const
  {
    return coupling::particle_snapshot(*body_, domain_.get());
  }

  std::vector<MeshSnapshot> CuttingDriver::mesh_snapshots() const
  {
    return {mesh_snapshot("cutter", *cutter_)};
  }

  Summary CuttingDriver::run(RunObserver &observer, const StateArrays *resume)
  {
    const auto wall_start      = std::chrono::steady_clock::now();
    const double wait_start    = domain_ ? domain_->wait_seconds() : 0.0;
    const double row_interval  = t_end_ / std::max(1, prm_.output.n_history_rows);
    const double snap_interval = t_end_ / std::max(1, prm_.output.n_snapshots);
    RunSchedule schedule;
    schedule.end_time          = t_end_;
    schedule.progress_time     = t_end_;
    schedule.row_interval      = row_interval;
    schedule.snapshot_interval = snap_interval;
    schedule.first_row         = row_interval;
    // the first snapshot: the undeformed block and the cutter in place
    schedule.snapshot_at_start = true;
    schedule.first_snapshot    = snap_interval;
    schedule.end_reason        = "end of path";
    // kinetic-energy allowance of the stability check at the start, when the cutter's work is
    // still tiny: the whole block moving at the cutter's speed
    double block_mass = 0;
    if (domain_)
    {
      for (const std::int32_t i : domain_->owned_indices())
        block_mass += body_->masses()[i];
      block_mass = domain_->sum(block_mass);
    }
    else
      for (const double m : body_->masses())
        block_mass += m;
    StabilityWatch watch;
    watch.rock         = body_.get();
    watch.domain       = domain_.get();
    watch.steel        = {{"cutter", cutter_.get()}};
    watch.domain_size  = domain_size_;
    watch.energy_floor = 0.5 * block_mass * prm_.cutter.speed * prm_.cutter.speed;
    watch.time_step    = dt_;
    watch.tssfac       = prm_.sph.tssfac;
    watch.likely_cause =
      "a time step above the stable limit (SPH/TSSFAC above 1, Platens/Contact stiffness scale "
      "near 1) or Cutter/Speed far above quasi-static";
    RunLoop loop(*this, schedule, std::move(watch), prm_.output);
    const std::string reason                 = loop.run(observer, resume);
    const std::vector<HistoryRow> &rows      = loop.rows();
    const std::vector<double> &rock_kinetic  = loop.rock_kinetic();
    const std::vector<double> &rock_internal = loop.rock_internal();

    const CutterParameters &c = prm_.cutter;
    Summary s;
    s.test         = prm_.test;
    s.n_particles  = domain_ ? domain_->n_global() : body_->n_particles();
    s.n_steps      = n_steps_;
    s.time_step    = dt_;
    s.stop_reason  = reason;
    s.true_area    = 0;
    s.lattice_area = 0;

    // the window the means are taken over: cutting, from one contact length sqrt(2 R p) of
    // travel (the cutter then meets only uncut rock; at most half the cut) to the start of the
    // stop ramp; indentation, the whole descent
    const double R          = 0.5 * c.disc_diameter;
    const double fresh_from = std::sqrt(2.0 * R * c.penetration) + prm_.sph.spacing;
    std::vector<double> normal, rolling, side, all_normal, all_rolling;
    for (const auto &r : rows)
    {
      const bool in_window = cutting_ ? (r.time > t_cut_start_ && r.displacement >= fresh_from &&
                                         r.time <= t_end_ - ramp_cut_)
                                      : r.time <= t_down_;
      if (cutting_ ? r.time > t_cut_start_ : true)
      {
        all_normal.push_back(r.force);
        all_rolling.push_back(r.rolling_force);
      }
      if (!in_window)
        continue;
      normal.push_back(r.force);
      rolling.push_back(r.rolling_force);
      side.push_back(r.side_force);
    }
    s.peak_force     = peak(all_normal);
    double max_ratio = 0, max_imbalance = 0;
    for (std::size_t k = 0; k < rows.size(); ++k)
    {
      const HistoryRow &r = rows[k];
      s.max_displacement = std::max(s.max_displacement, r.displacement);
      if (!(s.peak_force > 0) || r.force < 0.1 * s.peak_force)
        continue;
      if (rock_internal[k] > 0)
        max_ratio = std::max(max_ratio, rock_kinetic[k] / rock_internal[k]);
      max_imbalance = std::max(max_imbalance, std::abs(r.force - r.force_bottom) / s.peak_force);
    }
    s.max_kinetic_to_internal_energy = max_ratio;
    s.max_force_imbalance            = max_imbalance;
    if (!rows.empty())
    {
      const auto &r       = rows.back();
      const double stored = r.kinetic_energy + r.internal_energy + r.dissipated_energy;
      s.energy_balance_error =
        r.external_work > 0 ? std::abs(stored - r.external_work) / r.external_work : 0.0;
    }
    s.quasi_static = max_ratio <= prm_.loading.max_kinetic_ratio;

    // chip: the particles that failed (damage 1, fully softened), at their initial volume
    double chip = 0;
    double n_released = static_cast<double>(n_released_), released_energy = released_energy_;
    double n_contact = static_cast<double>(n_in_contact_);
    if (domain_)
    {
      for (const std::int32_t i : domain_->owned_indices())
        if (body_->damage(i) >= 1.0)
          chip += volume0_[i];
      const std::vector<double> all = domain_->sum({chip, n_released, released_energy, n_contact});
      chip = all[0], n_released = all[1], released_energy = all[2], n_contact = all[3];
      report_split(*domain_, force_on_cutter_.size(), wait_start, s);
    }
    else
    {
      for (unsigned int i = 0; i < body_->n_particles(); ++i)
        if (body_->damage(i) >= 1.0)
          chip += volume0_[i];
      s.particles_per_rank = {s.n_particles};
    }
    const double nan = std::numeric_limits<double>::quiet_NaN();
    auto &x          = s.extra;
    x.push_back({"mean_normal_force_kN", mean(normal) * 1e-3});
    x.push_back({"peak_normal_force_kN", peak(all_normal) * 1e-3});
    x.push_back({"mean_rolling_force_kN", mean(rolling) * 1e-3});
    x.push_back({"peak_rolling_force_kN", peak(all_rolling) * 1e-3});
    x.push_back({"mean_side_force_kN", mean(side) * 1e-3});
    x.push_back({"chip_volume_cm3", chip * 1e6});
    x.push_back({"n_chip_particles_released", n_released});
    x.push_back({"chip_release_energy_J", released_energy});
    // specific energy: the work the cutter did on the rock over the volume it broke out
    x.push_back({"cutter_work_J", frame_work_});
    x.push_back({"specific_energy_MJ_m3", chip > 0 ? frame_work_ / chip * 1e-6 : nan});
    x.push_back({"penetration_mm", depth_ * 1e3});
    x.push_back({"travel_mm", travel_ * 1e3});
    x.push_back({"cutter_speed_m_s", c.speed});
    x.push_back({"n_fixed_particles", double(n_fixed_)});
    x.push_back({"n_cutter_nodes", double(cutter_->n_nodes())});
    x.push_back({"n_contact_particles", n_contact}); // at the end
    x.push_back({"contact_stiffness_N_m", contact_stiffness_});
    x.push_back({"n_sph_pairs",
                 double(domain_ ? n_global_pairs_ : body_->n_pairs())}); // at the end (tools/bench)

    // independent estimates (closed forms) for the same geometry and rock
    const sph::MaterialParameters &rock = prm_.rock;
    const double ucs = prm_.rock_case.ucs > 0 ? prm_.rock_case.ucs : model_ucs(rock);
    const double bts = prm_.rock_case.bts > 0 ? prm_.rock_case.bts : model_tensile_strength(rock);
    x.push_back({"rock_ucs_MPa", ucs * 1e-6});
    x.push_back({"rock_bts_MPa", bts * 1e-6});
    if (cutting_)
    {
      const CsmEstimate e =
        csm_cutter_force(ucs, bts, R, c.tip_width, c.penetration, c.line_spacing);
      x.push_back({"csm_normal_force_kN", e.normal * 1e-3});
      x.push_back({"csm_rolling_force_kN", e.rolling * 1e-3});
      x.push_back({"csm_contact_angle_deg", e.contact_angle * 180.0 / pi});
      x.push_back({"csm_base_pressure_MPa", e.base_pressure * 1e-6});
    }
    else
    {
      const double alpha = 0.5 * c.tip_angle * pi / 180.0;
      const double h     = depth_;
      double elastic = nan, cavity = nan;
      const double pm = cavity_expansion_pressure(rock.youngs_modulus, ucs, alpha);
      if (c.shape == "cone")
      {
        elastic = sneddon_cone_force(rock.youngs_modulus, rock.poissons_ratio, alpha, h);
        cavity  = pm * pi * std::pow(h * std::tan(alpha), 2);
      }
      else if (c.shape == "flat")
        elastic =
          flat_punch_force(rock.youngs_modulus, rock.poissons_ratio, 0.5 * c.indenter_width, h);
      else
        cavity = pm * 2.0 * h * std::tan(alpha) * c.wedge_length;
      x.push_back({"elastic_closed_form_force_kN", elastic * 1e-3});
      x.push_back({"cavity_expansion_force_kN", cavity * 1e-3});
      x.push_back({"final_normal_force_kN", rows.empty() ? nan : rows.back().force * 1e-3});
    }
    s.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    return s;
  }

} // namespace coupling
