#include "specimen_driver.h"

#include "driver_common.h"
#include "failure_pattern.h"

#include <coupling/curve_analysis.h>
#include <coupling/run_case.h>

#include <fem/load_frame.h>
#include <fem/steel_body.h>
#include <sph/body.h>
#include <sph/domain.h>
#include <sph/fitted_bodies.h>
#include <sph/lattice.h>


#include <algorithm>
#include <chrono>
#include <cmath>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace coupling
{
  namespace
  {
    constexpr double pi = 3.14159265358979323846;
    /// Smooth start of the platen: 0 at t = 0, 1 from t = ramp on, C1 (sin^2 ramp).
    double ramp(double t, double t_ramp)
    {
      if (t >= t_ramp)
        return 1.0;
      if (t <= 0)
        return 0.0;
      const double s = std::sin(0.5 * pi * t / t_ramp);
      return s * s;
    }
  } // namespace


  double model_ucs(const sph::MaterialParameters &r)
  {
    if (r.model == sph::RockModel::elastic)
      return 0.0;
    if (r.model == sph::RockModel::hoek_brown)
      return r.hb_sigma_ci; // s = 1: sigma_1 = sigma_ci at sigma_3 = 0
    const double s = std::sin(r.friction_angle), c = std::cos(r.friction_angle);
    return 2.0 * r.cohesion * c / (1.0 - s);
  }

  double model_tensile_strength(const sph::MaterialParameters &r)
  {
    if (r.model == sph::RockModel::elastic)
      return 0.0;
    if (r.model == sph::RockModel::hoek_brown)
      return r.hb_mb > 0 ? r.hb_sigma_ci / r.hb_mb : 0.0;
    const double s = std::sin(r.friction_angle), c = std::cos(r.friction_angle);
    const double mc = 2.0 * r.cohesion * c / (1.0 + s);
    if (r.model == sph::RockModel::mohr_coulomb_cutoff && r.tensile_strength > 0)
      return std::min(mc, r.tensile_strength);
    return mc;
  }

  LoadingPlan make_loading_plan(const CaseParameters &p)
  {
    LoadingPlan plan;
    const bool bts          = p.test == "BTS";
    const sph::MaterialParameters &r = p.rock;
    plan.reference_length   = bts ? p.diameter : p.length;
    const double bar_speed  = std::sqrt(r.youngs_modulus / r.density);
    plan.transit_time       = plan.reference_length / bar_speed;
    // strain at which the specimen is expected to fail: it sets the rate, not the result
    double eps_f = p.loading.end_strain;
    if (r.model != sph::RockModel::elastic)
    {
      if (bts)
        // Hondros: the diametral strain at splitting is a few times sigma_t / E for a disc
        // loaded over a narrow contact; 4 sigma_t / E is the order of the reference study's
        // 0.014-0.020 mm on 50 mm discs
        eps_f = 4.0 * model_tensile_strength(r) / r.youngs_modulus;
      else
      {
        const double sn = std::sin(r.friction_angle);
        const double q  = r.model == sph::RockModel::hoek_brown ? 1.0 : (1 + sn) / (1 - sn);
        eps_f           = (model_ucs(r) + (q - 1.0) * p.confining_pressure) / r.youngs_modulus;
      }
      eps_f = std::min(eps_f, p.loading.end_strain);
    }
    plan.expected_failure_strain = eps_f;
    plan.strain_rate             = p.loading.strain_rate > 0
                                     ? p.loading.strain_rate
                                     : eps_f / (p.loading.transit_times * plan.transit_time);
    plan.platen_speed            = plan.strain_rate * plan.reference_length;
    // the platen reaches its speed smoothly over a few transit times (no impact wave)
    plan.ramp_time = std::min(4.0 * plan.transit_time, 0.25 * eps_f / plan.strain_rate);
    if (p.test == "CTCS")
      plan.confinement_time = 10.0 * plan.transit_time;
    plan.planned_strain =
      r.model == sph::RockModel::elastic ? p.loading.end_strain : std::min(p.loading.end_strain, 1.5 * eps_f);
    return plan;
  }

  SpecimenDriver::SpecimenDriver(const CaseParameters &parameters)
      : prm_(parameters)
  {
    bts_  = prm_.test == "BTS";
    ctcs_ = prm_.test == "CTCS";
    if (!bts_ && !ctcs_ && prm_.test != "UCS")
      throw InputError("Test/Type: unknown test '" + prm_.test + "'; accepted: UCS, BTS, CTCS");
    const double smallest = std::min(prm_.diameter, prm_.length);
    if (!(prm_.sph.spacing > 0) || prm_.sph.spacing > smallest / 6.0)
      throw InputError("SPH/Particle spacing: " + std::to_string(prm_.sph.spacing) +
                       " m must be positive and at most a sixth of the smallest specimen size (" +
                       std::to_string(smallest / 6.0) + " m)");
    plan_ = make_loading_plan(prm_);
    build_specimen();
    build_platens();
    choose_time_step();
    select_gauges();
  }

  SpecimenDriver::~SpecimenDriver() = default;

  void SpecimenDriver::build_specimen()
  {
    const double dx   = prm_.sph.spacing;
    const bool fitted = prm_.particle_arrangement == sph::ParticleArrangement::body_fitted;
    // body-fitted: the inner volumes consistent with the body's kernel (sph::SummedWith)
    const sph::SummedWith kernel = sph::summed_with(prm_.sph);
    const sph::Lattice<3> lattice = [&] {
      try
      {
        return bts_ ? (fitted ? sph::make_fitted_disc(prm_.diameter, prm_.length, dx,
                                                      prm_.flat_angle, kernel)
                              : sph::make_disc<3>(prm_.diameter, prm_.length, dx, prm_.flat_angle))
                    : (fitted ? sph::make_fitted_cylinder(prm_.diameter, prm_.length, dx, kernel)
                              : sph::make_cylinder<3>(prm_.diameter, prm_.length, dx));
      }
      catch (const std::domain_error &e)
      {
        // a smoothing length too wide for the body-fitted centre (measured: from CSLH 1.9 on the
        // default disc)
        throw InputError("SPH/CSLH = " + std::to_string(prm_.sph.cslh) + ": " + e.what() +
                         "; use a smaller CSLH or SPH/Particle arrangement = lattice");
      }
    }();
    true_area_                    = lattice.true_section_area;
    lattice_area_                 = lattice.lattice_section_area;
    // half the particle extent along the load: the cylinder's layer distance L / round(L / dx),
    // the disc's lattice cell or (body-fitted) ring spacing, so that the contact surface of the
    // outer particles is the specimen's true face (the fitted disc's outer ring lies half a ring
    // spacing inside r = R, with a particle on the loaded diameter at the top and the bottom)
    contact_radius_               = 0.5 * lattice.cell_size[2];
    x0_global_                    = lattice.positions;
    cell_area_global_.clear();
    for (const double v : lattice.volumes)
      cell_area_global_.push_back(v / lattice.cell_size[2]);
    const int n_ranks             = mpi_ranks();
    if (n_ranks > 1)
    {
      // this rank's subdomain (make_rock_part)
      RockPart part   = make_rock_part(prm_, lattice, plan_.strain_rate);
      domain_         = std::move(part.domain);
      body_           = std::move(part.body);
      n_global_pairs_ = part.n_global_pairs;
      failure_ = std::make_unique<FailureWatch>(lattice.positions, lattice.volumes, bts_);
      if (!bts_ && prm_.loaded_face_correction)
      {
        double top = -1e300, bottom = -1e300;
        for (const auto &p : lattice.positions)
        {
          top    = std::max(top, p[2]);
          bottom = std::max(bottom, -p[2]);
        }
        body_->add_loaded_face(sph::Vector<3>(0, 0, 1), top);
        body_->add_loaded_face(sph::Vector<3>(0, 0, -1), bottom);
      }
      body_->restrict_to_owned(*domain_); // each step's work: what the owned particles need
      owned_.reset(*body_, *domain_);
    }
    else
    {
      body_    = make_rock_body(prm_, lattice, plan_.strain_rate);
      failure_ = std::make_unique<FailureWatch>(*body_, bts_);
      // UCS/CTCS: the platens load the flat end faces (see sph::Body::add_loaded_face)
      if (!bts_ && prm_.loaded_face_correction)
      {
        body_->add_loaded_face(sph::Vector<3>(0, 0, 1));
        body_->add_loaded_face(sph::Vector<3>(0, 0, -1));
      }
    }
    const std::size_t n = domain_ ? domain_->owned_indices().size() : body_->n_particles();
    force_on_particles_.assign(3 * n, 0.0);
    domain_size_ = 3.0 * std::max(prm_.diameter, prm_.length);
    // kinetic-energy bound of the stability check: a stable run never holds more kinetic energy
    // than the work done on it (energy balance); the floor covers the start, when that work is
    // still tiny: the whole rock moving at the final platen speed
    double rock_mass = 0;
    if (domain_) // the masses of the whole body, as sph::Body computes them
      for (const double v : lattice.volumes)
        rock_mass += prm_.rock.density * v;
    else
      for (const double m : body_->masses())
        rock_mass += m;
    energy_floor_ = 0.5 * rock_mass * plan_.platen_speed * plan_.platen_speed;
  }

  void SpecimenDriver::build_platens()
  {
    const double dx = prm_.sph.spacing;
    fem::Parameters fp = specimen_platen_parameters(prm_);

    fem::BodyGeometry g;
    g.thickness = prm_.platens.thickness;
    if (bts_)
    {
      g.size_x = prm_.platens.diameter > 0 ? prm_.platens.diameter : 0.6 * prm_.diameter;
      // 5 mm past each face of the disc, whatever the spacing (a platen's size, not the mesh's)
      g.size_y = prm_.length + 0.01;
      if (prm_.platens.shape == "jaw")
      {
        // ISRM curved jaw: contact arc of 1.5 disc radii unless given
        g.shape      = fem::BodyShape::jaw;
        g.jaw_radius = prm_.platens.jaw_radius > 0 ? prm_.platens.jaw_radius : 0.75 * prm_.diameter;
      }
      else if (prm_.platens.shape == "flat")
        g.shape = fem::BodyShape::box;
      else
        throw InputError("Platens/Shape: unknown shape '" + prm_.platens.shape +
                         "'; accepted: flat, jaw");
    }
    else
    {
      if (prm_.platens.shape != "flat")
        throw InputError("Platens/Shape: " + prm_.test + " uses flat platens; jaw is for BTS only");
      g.shape    = fem::BodyShape::cylinder;
      g.diameter = cylinder_platen_diameter(prm_);
    }
    double top_z = bts_ ? prm_.diameter : prm_.length, bottom_z = 0.0;
    if (g.shape == fem::BodyShape::jaw)
    {
      // the concave jaw bends towards the disc away from its apex, and its mesh chords the arc
      // (the faces between nodes lie nearer the disc than the arc); the lattice's outer particles
      // do not lie on the circle either. So place each jaw where its meshed face just touches the
      // nearest particle (contact radius dx / 2), not at the disc's top and bottom, which would
      // start with particles pressed into the jaw. The face height over x is read off a probe
      // jaw with its apex at z = 0 (piecewise linear between the node columns; the arc runs
      // along y unchanged).
      g.side      = fem::BodySide::above;
      g.contact_z = 0.0;
      std::vector<std::pair<double, double>> profile; // (x, z) of the contact nodes, by x
      try
      {
        const std::vector<double> xc = fem::SteelBody(g, fp).contact_positions();
        for (std::size_t k = 0; k < xc.size(); k += 3)
          profile.emplace_back(xc[k], xc[k + 2]);
      }
      catch (const std::invalid_argument &e)
      {
        throw InputError(std::string("Platens: ") + e.what());
      }
      std::sort(profile.begin(), profile.end());
      // face height relative to the apex (<= 0) and the slope dz/dx of the face at x
      auto face_at = [&](double x) -> std::pair<double, double> {
        x       = std::clamp(x, profile.front().first, profile.back().first);
        auto hi = std::lower_bound(profile.begin(), profile.end(), std::make_pair(x, -1e300));
        if (hi == profile.begin())
          ++hi;
        auto lo = std::prev(hi);
        while (lo != profile.begin() && lo->first >= hi->first)
          --lo;
        const double run   = hi->first - lo->first;
        const double slope = run > 0 ? (hi->second - lo->second) / run : 0.0;
        return {lo->second + slope * (x - lo->first), slope};
      };
      // the contact radius is measured along the face normal: a particle under a face of slope m
      // needs a vertical clearance r_c sqrt(1 + m^2)
      const double r_c = contact_radius_;
      top_z = -1e300, bottom_z = 1e300;
      for (const auto &p : x0_global_) // (the particles are at their reference positions)
      {
        const auto [z, m]     = face_at(p[0]);
        const double clearance = r_c * std::sqrt(1.0 + m * m);
        top_z                  = std::max(top_z, p[2] + clearance - z);
        bottom_z               = std::min(bottom_z, p[2] - clearance + z);
      }
    }
    else
    {
      // flat platens at the specimen's faces, unless a particle reaches past them: a disc whose
      // diameter the spacing does not divide has round(D / dx) cells, up to dx / 2 more than D,
      // and would start pressed into both platens (an impulse at the first step). The cylinder's
      // layers fit its length exactly (cells of L / round(L / dx) along z and a contact radius
      // of half of that), so its platens stay at 0 and L; slack: round-off of the coordinates.
      // A flattened disc's flats lie inside 0 and D: its platens go onto them.
      const double slack = 1e-9 * dx;
      double       hi = -1e300, lo = 1e300;
      for (const auto &p : x0_global_)
      {
        hi = std::max(hi, p[2] + contact_radius_);
        lo = std::min(lo, p[2] - contact_radius_);
      }
      const bool flats = bts_ && prm_.flat_angle > 0;
      if (hi > top_z + slack || flats)
        top_z = hi;
      if (lo < bottom_z - slack || flats)
        bottom_z = lo;
    }
    try
    {
      g.side      = fem::BodySide::above;
      g.contact_z = top_z;
      top_        = std::make_unique<fem::SteelBody>(g, fp);
      g.side      = fem::BodySide::below;
      g.contact_z = bottom_z;
      bottom_     = std::make_unique<fem::SteelBody>(g, fp);
    }
    catch (const std::invalid_argument &e)
    {
      throw InputError(std::string("Platens: ") + e.what());
    }
    if (prm_.platens.frame_stiffness > 0)
    {
      // the frame's spring drives the rigid top platen (fem/load_frame.h); the platen moves with
      // the velocity the frame's step gives, and the actuator with top_velocity
      if (!top_->is_rigid())
        throw InputError("Platens/Frame stiffness: drives a rigid platen; set Platens/Model = rigid or Frame stiffness = 0");
      frame_ = std::make_unique<fem::LoadFrame>(prm_.platens.frame_stiffness, top_->total_mass(),
                                                prm_.platens.frame_damping_ratio);
      top_->set_loaded_face_velocity([this](double) { return frame_->platen_velocity(); });
    }
    else
      top_->set_loaded_face_velocity([this](double t) { return top_velocity(t); });
    force_on_top_.assign(3 * top_->n_contact_nodes(), 0.0);
    force_on_bottom_.assign(3 * bottom_->n_contact_nodes(), 0.0);
  }

  double SpecimenDriver::top_velocity(double t) const
  {
    if (ctcs_ && t < plan_.confinement_time)
    {
      // follow the hydrostatic compression of the rock while the pressure ramps up, so that the
      // axial stress stays equal to the confining pressure: d(eps)/dt = (1 - 2 nu)/E_t dp/dt,
      // E_t the tangent modulus at the pressure p(t) of the ramp (E without crack closure; with
      // it, the rock's moduli are scaled by E_t / E at p, the most compressive principal stress,
      // sph/crack_closure.h: a platen that followed the intact E would leave a gap that the
      // loading then closes as a spurious toe)
      const double dp_dt = prm_.confining_pressure / plan_.confinement_time;
      const sph::MaterialParameters &r = prm_.rock;
      const double E_t =
        r.closure_modulus_ratio < 1
          ? sph::rock::crack_closure_tangent_modulus(dp_dt * t, r.youngs_modulus,
                                                     r.closure_modulus_ratio * r.youngs_modulus,
                                                     r.closure_stress)
          : r.youngs_modulus;
      const double rate = (1.0 - 2.0 * r.poissons_ratio) / E_t * dp_dt;
      return -rate * prm_.length;
    }
    const double t_load = t - plan_.confinement_time;
    return -plan_.platen_speed * ramp(t_load, plan_.ramp_time);
  }

  void SpecimenDriver::choose_time_step()
  {
    time_step_scale_    = prm_.sph.tssfac / std::min(prm_.sph.tssfac, 1.0);
    const double dt_sph = (domain_ ? domain_->min(body_->stable_time_step()) :
                                     body_->stable_time_step()) *
                          time_step_scale_;
    // loaded faces: each outer particle is pressed in proportion to the area it carries, so a
    // uniform platen displacement gives a uniform stress (see sph::Body::loaded_face_areas);
    // distributed: the owned particles' areas of all ranks in global order (the same sum)
    const std::vector<double> area =
      domain_ && !body_->loaded_face_areas().empty() ?
        domain_->gather(body_->loaded_face_areas().data(), 1) :
        body_->loaded_face_areas();
    std::vector<double> factor;
    double largest_factor = 1.0;
    if (!area.empty())
    {
      double sum = 0;
      int count  = 0;
      for (const double a : area)
        if (a > 0)
          sum += a, ++count;
      factor.assign(area.size(), 1.0);
      for (std::size_t i = 0; i < area.size(); ++i)
        if (area[i] > 0)
          factor[i] = area[i] * count / sum;
      largest_factor = *std::max_element(factor.begin(), factor.end());
    }

    // Penalty stiffness: a fraction s of the central-difference bound 4 m_eff / dt^2 at the rock's
    // own step, for the lightest particle against the lightest contact node (rigid: the particle
    // alone). The coupled step is dt_sph / sqrt(1 + s f), f the largest stiffness factor of the
    // loaded faces, so that the rock's stiffness and the stiffest contact spring together stay
    // inside the bound (coupled_time_step() gives the proof).
    // The kinematic constraint has no stiffness and adds no bound: the coupled step is the
    // rock's own.
    const bool kinematic = contact_method(prm_) == ContactMethod::kinematic;
    const double s       = prm_.platens.contact_stiffness_scale;
    dt_                  = kinematic ? dt_sph : coupled_time_step(dt_sph, s * largest_factor);
    const double dt_fem = std::min(top_->stable_time_step(), bottom_->stable_time_step());
    // The kinematic constraint predicts where an elastic face ends the step from its nodes' free
    // accelerations held over the step (predicted_contact_surface): exact over one platen step,
    // not over sub-steps, between which the face's internal force changes (2.5 mm elements
    // under 2.5 mm particles took 2 sub-steps: the end faces bumpy, the energy balance 1.7 % to
    // 9 % off). So the kinematic contact steps both bodies at the smaller stable step.
    if (kinematic && std::isfinite(dt_fem))
      dt_ = std::min(dt_, dt_fem);
    // the platens sub-cycle when their stable step is the smaller one; the contact force is held
    // over the sub-steps so the impulse exchanged, f dt, is the same on both sides
    n_substeps_ = std::isfinite(dt_fem) ? std::max(1, int(std::ceil(dt_ / dt_fem))) : 1;
    if (frame_ && !(dt_ < 0.5 * frame_->stable_time_step()))
      throw InputError("Platens/Frame stiffness: " + std::to_string(prm_.platens.frame_stiffness) +
                       " N/m is too stiff for the explicit step (" + std::to_string(dt_) +
                       " s) with the platen's mass; use a smaller stiffness (laboratory frames: about 1e8-1e10 N/m)");

    const auto &m           = body_->masses();
    const double m_particle = domain_ ? domain_->min(*std::min_element(m.begin(), m.end())) :
                                        *std::min_element(m.begin(), m.end());
    double m_node           = 0.0;
    if (!top_->is_rigid())
    {
      const auto a = top_->contact_masses(), b = bottom_->contact_masses();
      m_node =
        std::min(*std::min_element(a.begin(), a.end()), *std::min_element(b.begin(), b.end()));
    }
    ContactParameters cp;
    cp.stiffness = kinematic ? 0.0 : s * stable_contact_stiffness(m_particle, m_node, dt_sph);
    cp.friction_static  = prm_.platens.friction;
    cp.friction_dynamic = prm_.platens.dynamic_friction < 0 ? prm_.platens.friction : prm_.platens.dynamic_friction;
    cp.radius           = contact_radius_;
    cp.method           = contact_method(prm_);
    cp.bonded           = prm_.platens.bonded;
    cp.tolerance        = prm_.platens.contact_tolerance;
    cp.patch_points     = contact_patch_points(prm_);
    cp.flat_master      = !bts_; // the cylinder platens' flat faces (the BTS jaws may be concave)
    if (!bts_) // the cylinder platens' rim polygons: inside their circle by the chords' sagitta
      cp.rim_reach = std::max(rim_sagitta(*top_), rim_sagitta(*bottom_));
    // Elastic cylinder platens: the particles' forces land on the steel where a uniform stress
    // would put them (the loaded ends' discrete areas, ContactParameters::face_radius_mapped; the
    // circle onto the mesh's rim polygon, rim_angles). Without them the steel under a specimen
    // of its own diameter bent by a micrometre under a uniform stress, and the end layer of a
    // softening rock failed early (M1, 2.5 mm, body-fitted: 272.7 MPa against 282.3 with them).
    if (!bts_ && kinematic && !top_->is_rigid())
    {
      if (!area.empty())
        set_face_remap(cp, x0_global_, area, cell_area_global_, prm_.sph.spacing);
      set_rim_polygon(cp, *top_, 0.5 * prm_.diameter);
    }
    const std::size_t n_contact = domain_ ? domain_->owned_indices().size() : body_->n_particles();
    contact_top_    = std::make_unique<PenaltyContact>(cp, n_contact);
    contact_bottom_ = std::make_unique<PenaltyContact>(cp, n_contact);
    if (domain_) // the kinematic contacts on an elastic platen's nodes, solved across the ranks
      for (PenaltyContact *c : {contact_top_.get(), contact_bottom_.get()})
        c->set_reduction([d = domain_.get()](double *v, int n) { d->sum_in_place(v, n); },
                         [d = domain_.get()](double v) { return d->max(v); });
    if (!factor.empty() && domain_) // the owned particles' factors
    {
      std::vector<double> mine;
      for (const std::int32_t i : domain_->owned_indices())
        mine.push_back(factor[domain_->global_ids()[i]]);
      factor.swap(mine);
    }
    if (!factor.empty())
    {
      contact_top_->set_stiffness_factors(factor);
      contact_bottom_->set_stiffness_factors(factor);
    }
  }

  void SpecimenDriver::select_gauges()
  {
    const auto &x0  = x0_global_; // (global indices; distributed: made local below)
    const double dx = prm_.sph.spacing;
    if (bts_)
      return;
    // axial gauges: the particle layers nearest to L/4 and 3L/4 (middle half of the specimen,
    // away from the end effects, as strain gauges on a specimen); radial: the outermost ring at
    // mid-height
    auto nearest_layer = [&](double z) {
      double best = 1e300;
      for (const auto &p : x0)
        best = std::min(best, std::abs(p[2] - z));
      std::vector<unsigned int> set;
      for (unsigned int i = 0; i < x0.size(); ++i)
        if (std::abs(std::abs(x0[i][2] - z) - best) < 1e-9 * prm_.length &&
            std::abs(x0[i][2] - z) <= best + 1e-12)
          set.push_back(i);
      return set;
    };
    gauge_low_     = nearest_layer(0.25 * prm_.length);
    gauge_high_    = nearest_layer(0.75 * prm_.length);
    gauge_length0_ = x0[gauge_high_[0]][2] - x0[gauge_low_[0]][2];
    const auto mid = nearest_layer(0.5 * prm_.length);
    double r_max   = 0;
    for (unsigned int i : mid)
      r_max = std::max(r_max, std::hypot(x0[i][0], x0[i][1]));
    for (unsigned int i : mid)
      if (std::hypot(x0[i][0], x0[i][1]) > r_max - 0.75 * dx)
        gauge_ring_.push_back(i);
    gauge_counts_[0] = static_cast<double>(gauge_low_.size());
    gauge_counts_[1] = static_cast<double>(gauge_high_.size());
    gauge_counts_[2] = static_cast<double>(gauge_ring_.size());
    if (domain_) // the owned members, as local indices
    {
      std::vector<std::int32_t> local_of(x0.size(), -1);
      for (const std::int32_t i : domain_->owned_indices())
        local_of[domain_->global_ids()[i]] = i;
      for (auto *set : {&gauge_low_, &gauge_high_, &gauge_ring_})
      {
        std::vector<unsigned int> mine;
        for (const unsigned int g : *set)
          if (local_of[g] >= 0)
            mine.push_back(static_cast<unsigned int>(local_of[g]));
        set->swap(mine);
      }
    }
  }

  void SpecimenDriver::step()
  {
    body_->compute_forces(domain_.get());
    if (ctcs_)
      body_->set_surface_pressure(prm_.confining_pressure *
                                  std::min(1.0, time_ / plan_.confinement_time));

    // FEM -> SPH: the contact-face nodes are the background particles, mirrored unchanged (the
    // kinematic contact takes their velocities over the coming step, predicted_contact_surface)
    const bool kinematic = contact_method(prm_) == ContactMethod::kinematic;
    const ContactSurface s_top =
      kinematic ? predicted_contact_surface(*top_, dt_) : contact_surface(*top_);
    const ContactSurface s_bottom =
      kinematic ? predicted_contact_surface(*bottom_, dt_) : contact_surface(*bottom_);
    const auto &x = body_->positions();
    const auto &v = body_->velocities();
    ContactParticles particles{x.front().data(), v.front().data(), body_->masses().data(),
                               body_->n_particles()};
    if (kinematic)
    {
      // the force of this step before contact, to predict where the step ends
      const auto &fi = body_->internal_forces(), &fp = body_->pressure_forces();
      auto &fe       = body_->external_forces();
      force_before_contact_.resize(3 * body_->n_particles());
      for (unsigned int i = 0; i < body_->n_particles(); ++i)
        for (int d = 0; d < 3; ++d)
          force_before_contact_[3 * i + d] = fi[i][d] + fp[i][d] + fe[i][d];
      particles.force = force_before_contact_.data();
      // the half cells at the faces strain with their particles
      deformation_.resize(9 * body_->n_particles());
      for (unsigned int i = 0; i < body_->n_particles(); ++i)
      {
        const auto &F = body_->deformation_gradient(i);
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b)
            deformation_[9 * i + 3 * a + b] = F(a, b);
      }
      particles.deformation = deformation_.data();
      // the reference kernel gradients do not change: once
      if (self_gradient_.empty())
        for (const auto &g : body_->self_gradients())
          self_gradient_.insert(self_gradient_.end(), {g[0], g[1], g[2]});
      particles.self_gradient = self_gradient_.data();
    }
    if (domain_) // the owned particles only, packed
      particles = kinematic ? owned_.pack(*body_, *domain_, &force_before_contact_, &deformation_, &self_gradient_)
                            : owned_.pack(*body_, *domain_);
    std::fill(force_on_particles_.begin(), force_on_particles_.end(), 0.0);
    std::fill(force_on_top_.begin(), force_on_top_.end(), 0.0);
    std::fill(force_on_bottom_.begin(), force_on_bottom_.end(), 0.0);
    contact_top_->apply(particles, s_top, dt_, force_on_particles_, force_on_top_);
    contact_bottom_->apply(particles, s_bottom, dt_, force_on_particles_, force_on_bottom_);
    max_exchange_imbalance_ =
      std::max(max_exchange_imbalance_, domain_ ? reduce_contact_forces() : exchange_imbalance());

    // SPH <- contact forces; FEM <- their reactions (the sums cancel to round-off)
    add_contact_forces(*body_, domain_.get(), force_on_particles_);
    body_->integrate(dt_);

    // work of the boundary loads (confining pressure, loaded-face correction) over this step,
    // with the half-step velocities
    if (domain_)
    {
      const auto &fp = body_->pressure_forces();
      double w       = 0;
      for (const std::int32_t i : domain_->owned_indices())
        w += fp[i].dot(v[i]);
      pressure_work_pending_ += w * dt_; // summed over the ranks at the next step
      // the ghosts' positions and velocities from their owners
      body_->exchange_ghosts(*domain_);
    }
    else
    {
      const auto &fp = body_->pressure_forces();
      double w       = 0;
      for (unsigned int i = 0; i < body_->n_particles(); ++i)
        w += fp[i].dot(v[i]);
      pressure_work_ += w * dt_;
    }

    const double h = dt_ / n_substeps_;
    double rock_on_top = 0; // z-force of the rock on the top platen [N]
    if (frame_)
      for (std::size_t i = 2; i < force_on_top_.size(); i += 3)
        rock_on_top += force_on_top_[i];
    for (int k = 0; k < n_substeps_; ++k)
    {
      top_->add_contact_forces(force_on_top_);
      bottom_->add_contact_forces(force_on_bottom_);
      const double t = time_ + k * h;
      if (frame_) // the platen's velocity for the step: spring and rock forces at t
        frame_->step(top_velocity(t + 0.5 * h), rock_on_top, h);
      top_->step(t, h);
      bottom_->step(t, h);
      // frame work: load-cell reaction times the loaded face's prescribed velocity (bottom fixed)
      frame_work_ += top_->reaction_force() * top_velocity(t + 0.5 * h) * h;
    }
    time_ += dt_;
    ++n_steps_;
  }

  double SpecimenDriver::exchange_imbalance() const
  {
    // what the rock receives and what the platens receive, each pair force counted on both sides
    double total[3] = {0, 0, 0}, scale = 0;
    for (std::size_t i = 0; i < force_on_particles_.size(); i += 3)
    {
      const double *f = &force_on_particles_[i];
      scale += std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
      for (int d = 0; d < 3; ++d)
        total[d] += f[d];
    }
    for (const auto *platen : {&force_on_top_, &force_on_bottom_})
      for (std::size_t i = 0; i < platen->size(); ++i)
        total[i % 3] += (*platen)[i];
    if (!(scale > 0))
      return 0.0;
    return std::sqrt(total[0] * total[0] + total[1] * total[1] + total[2] * total[2]) / scale;
  }

  double SpecimenDriver::reduce_contact_forces()
  {
    // one buffer: both platens' nodal forces, the particles' force sum and magnitude sum, the
    // normal forces; summed over the ranks by one MPI_Allreduce, so every rank steps the same
    // platens
    const std::size_t nt = force_on_top_.size(), nb = force_on_bottom_.size();
    std::vector<double> buffer(nt + nb + 7, 0.0);
    std::copy(force_on_top_.begin(), force_on_top_.end(), buffer.begin());
    std::copy(force_on_bottom_.begin(), force_on_bottom_.end(), buffer.begin() + nt);
    double *tail = buffer.data() + nt + nb;
    for (std::size_t i = 0; i < force_on_particles_.size(); i += 3)
    {
      const double *f = &force_on_particles_[i];
      tail[3] += std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
      for (int d = 0; d < 3; ++d)
        tail[d] += f[d];
    }
    tail[4] = contact_top_->normal_force();
    tail[5] = contact_bottom_->normal_force();
    tail[6] = pressure_work_pending_;
    domain_->sum_in_place(buffer.data(), static_cast<int>(buffer.size()));
    std::copy(buffer.begin(), buffer.begin() + nt, force_on_top_.begin());
    std::copy(buffer.begin() + nt, buffer.begin() + nt + nb, force_on_bottom_.begin());
    normal_top_    = tail[4];
    normal_bottom_ = tail[5];
    pressure_work_ += tail[6];
    pressure_work_pending_ = 0;
    double total[3] = {tail[0], tail[1], tail[2]};
    for (const auto *platen : {&force_on_top_, &force_on_bottom_})
      for (std::size_t i = 0; i < platen->size(); ++i)
        total[i % 3] += (*platen)[i];
    if (!(tail[3] > 0))
      return 0.0;
    return std::sqrt(total[0] * total[0] + total[1] * total[1] + total[2] * total[2]) / tail[3];
  }

  HistoryRow SpecimenDriver::history_row() const
  {
    HistoryRow r;
    r.time            = time_;
    // the platens' approach; with a load frame the actuator's stroke, which includes the frame's
    // stretch, as a machine that reads its crosshead does
    r.displacement    = bottom_->loaded_face_displacement() -
                     (frame_ ? frame_->actuator_displacement() : top_->loaded_face_displacement());
    r.force           = top_->compressive_force();
    r.force_bottom    = bottom_->compressive_force();
    const double load = 0.5 * (r.force + r.force_bottom);
    if (bts_)
    {
      r.stress = 2.0 * load / (pi * prm_.diameter * prm_.length);
      r.strain = r.displacement / prm_.diameter;
    }
    else
    {
      // CTCS: the pressure acts on the ends too, so the frame carries sigma_1 - p (a balanced
      // piston); the axial stress is the load over the true area plus the pressure
      const double p = ctcs_ ? body_->surface_pressure() : 0.0;
      r.stress       = load / true_area_ + p;
      r.strain       = r.displacement / prm_.length;
    }
    const auto &x  = body_->positions();
    const auto &x0 = body_->reference_positions();
    double z_lo = 0, z_hi = 0, er = 0;
    if (!bts_)
    {
      for (unsigned int i : gauge_low_)
        z_lo += x[i][2];
      for (unsigned int i : gauge_high_)
        z_hi += x[i][2];
      for (unsigned int i : gauge_ring_)
        er += std::hypot(x[i][0], x[i][1]) / std::hypot(x0[i][0], x0[i][1]) - 1.0;
    }
    sph::Energies e = body_->energies();
    double pen      = contact_top_->penalty_energy() + contact_bottom_->penalty_energy();
    double friction_top    = contact_top_->friction_dissipation();
    double friction_bottom = contact_bottom_->friction_dissipation();
    if (domain_) // the owned particles' shares of every rank (one collective)
    {
      double n_failed = 0;
      for (const std::int32_t i : domain_->owned_indices())
        n_failed += body_->damage(i) >= 1.0 ? 1.0 : 0.0;
      const std::vector<double> all =
        domain_->sum({z_lo, z_hi, er, e.kinetic, e.internal, e.plastic, e.viscous, e.hourglass,
                      e.external, pen, friction_top, friction_bottom, n_failed,
                      pressure_work_pending_});
      z_lo = all[0], z_hi = all[1], er = all[2];
      e.kinetic = all[3], e.internal = all[4], e.plastic = all[5], e.viscous = all[6];
      e.hourglass = all[7], e.external = all[8];
      pen = all[9], friction_top = all[10], friction_bottom = all[11];
      r.n_failed = all[12];
      r.external_work = frame_work_ + (pressure_work_ + all[13]);
    }
    else
      r.n_failed = n_failed_particles(*body_);
    if (!bts_)
    {
      z_lo /= gauge_counts_[0];
      z_hi /= gauge_counts_[1];
      r.axial_gauge_strain = 1.0 - (z_hi - z_lo) / gauge_length0_;
      r.radial_strain = er / gauge_counts_[2];
    }
    r.kinetic_energy      = e.kinetic + top_->kinetic_energy() + bottom_->kinetic_energy();
    r.internal_energy     = e.internal + top_->strain_energy() + bottom_->strain_energy() + pen;
    r.dissipated_energy   = e.dissipated() + friction_top + friction_bottom +
                          top_->damping_dissipation() + bottom_->damping_dissipation();
    if (frame_) // the frame's spring and dashpot
    {
      r.internal_energy += frame_->spring_energy();
      r.dissipated_energy += frame_->dissipated_energy();
    }
    if (!domain_)
      r.external_work = frame_work_ + pressure_work_;
    return r;
  }

  Measurement SpecimenDriver::measure()
  {
    Measurement m;
    m.row = history_row();
    // the rock's own energies, and of its kinetic energy only the part that is not a homogeneous
    // deformation (see the quasi-static check in run())
    m.rock_kinetic  = non_affine_kinetic_energy(*body_, domain_.get());
    m.rock_internal = domain_ ? domain_->sum(body_->energies().internal) : body_->energies().internal;
    return m;
  }

  std::string SpecimenDriver::stop_reason(const HistoryRow &r)
  {
    failure_->observe(*body_, r.stress, domain_.get());
    const bool loading = time_ > plan_.confinement_time;
    // the load the specimen carries: mean of both load cells (the stress wave that crosses
    // the specimen at the start makes each one oscillate on its own)
    const double load = 0.5 * (r.force + r.force_bottom);
    peak_force_       = loading ? std::max(peak_force_, load) : peak_force_;
    // the failure criterion is armed once the specimen yields somewhere or has passed half of
    // its expected failure strain, so that the start-up transient cannot end the run
    // strain counts from the first contact on both sides: curved jaws start with a gap
    // (the arc over the lattice's discrete top), which the platen closes first
    const double normal_top    = domain_ ? normal_top_ : contact_top_->normal_force();
    const double normal_bottom = domain_ ? normal_bottom_ : contact_bottom_->normal_force();
    if (!touching_ && normal_top > 0 && normal_bottom > 0)
    {
      touching_     = true;
      touch_strain_ = r.strain;
    }
    armed_ = armed_ || r.n_failed > 0 ||
             (touching_ && r.strain - touch_strain_ > 0.5 * plan_.expected_failure_strain);
    // the load has fallen past the post-peak drop: the specimen has failed
    if (loading && armed_ && peak_force_ > 0 &&
        load < (1.0 - prm_.loading.post_peak_drop) * peak_force_)
      return "post-peak drop";
    return "";
  }

  namespace
  {
    /// driver.scalars: time, steps, frame and pressure work, peak, armed, dt, sub-steps,
    /// particles, touching, touch strain
    constexpr std::size_t n_scalars = 11;
  } // namespace

  void SpecimenDriver::save_state(StateArrays &out) const
  {
    save_rock_state(
      *body_, domain_.get(),
      {{"contact_top.", contact_top_.get()}, {"contact_bottom.", contact_bottom_.get()}}, out,
      &state_rows_);
    top_->save_state(out, "platen_top.");
    bottom_->save_state(out, "platen_bottom.");
    out["driver.scalars"] = {time_,
                             static_cast<double>(n_steps_),
                             frame_work_,
                             domain_ ? pressure_work_ + domain_->sum(pressure_work_pending_) :
                                       pressure_work_,
                             peak_force_,
                             armed_ ? 1.0 : 0.0,
                             dt_,
                             static_cast<double>(n_substeps_),
                             static_cast<double>(domain_ ? domain_->n_global() : body_->n_particles()),
                             touching_ ? 1.0 : 0.0,
                             touch_strain_};
    out["driver.failure"] = failure_->state();
    if (frame_)
      out["driver.frame"] = frame_->state();
  }

  void SpecimenDriver::load_state(const StateArrays &in)
  {
    const auto s = in.find("driver.scalars");
    if (s == in.end() || s->second.size() != n_scalars)
      throw InputError("checkpoint: no driver.scalars of a laboratory test; not a checkpoint of "
                       "a UCS, BTS or CTCS run of this cosim");
    const auto &d = s->second;
    // the same case gives the same particle count, time step and sub-cycling, bit for bit
    const std::size_t n_all = domain_ ? domain_->n_global() : body_->n_particles();
    if (d[8] != n_all || d[6] != dt_ || d[7] != n_substeps_)
    {
      std::ostringstream os;
      os << "checkpoint: it holds " << d[8] << " particles at dt = " << d[6]
         << " s, this case has " << n_all << " at dt = " << dt_
         << " s; restart with the case's own used_parameters.prm";
      throw InputError(os.str());
    }
    try
    {
      load_rock_state(
        *body_, domain_.get(),
        {{"contact_top.", contact_top_.get()}, {"contact_bottom.", contact_bottom_.get()}}, in);
      top_->load_state(in, "platen_top.");
      bottom_->load_state(in, "platen_bottom.");
    }
    catch (const std::invalid_argument &e)
    {
      throw InputError(std::string("checkpoint: ") + e.what());
    }
    time_          = d[0];
    n_steps_       = static_cast<std::size_t>(d[1]);
    frame_work_    = d[2];
    pressure_work_ = d[3];
    pressure_work_pending_ = 0;
    peak_force_    = d[4];
    armed_         = d[5] != 0.0;
    touching_      = d[9] != 0.0;
    touch_strain_  = d[10];
    const auto f = in.find("driver.failure");
    if (f == in.end() || f->second.size() != failure_->state().size())
      throw InputError("checkpoint: no driver.failure array; a checkpoint of an older cosim?");
    failure_->set_state(f->second);
    if (frame_)
    {
      const auto fr = in.find("driver.frame");
      if (fr == in.end() || fr->second.size() != frame_->state().size())
        throw InputError("checkpoint: no driver.frame array; not a checkpoint of a run with Platens/Frame stiffness");
      frame_->set_state(fr->second);
    }
  }

  ParticleSnapshot SpecimenDriver::particle_snapshot() const
  {
    return coupling::particle_snapshot(*body_, domain_.get());
  }

  std::vector<MeshSnapshot> SpecimenDriver::mesh_snapshots() const
  {
    return {mesh_snapshot("platen_top", *top_), mesh_snapshot("platen_bottom", *bottom_)};
  }

  Summary SpecimenDriver::run(RunObserver &observer, const StateArrays *resume)
  {
    const auto wall_start  = std::chrono::steady_clock::now();
    const double wait_start = domain_ ? domain_->wait_seconds() : 0.0;
    const double t_plan =
      plan_.confinement_time + plan_.ramp_time * 0.5 + plan_.planned_strain / plan_.strain_rate;
    const double t_end =
      plan_.confinement_time + plan_.ramp_time * 0.5 + prm_.loading.end_strain / plan_.strain_rate;
    const double row_interval  = t_plan / std::max(1, prm_.output.n_history_rows);
    const double snap_interval = t_plan / std::max(1, prm_.output.n_snapshots);

    RunSchedule schedule;
    schedule.end_time          = t_end;
    schedule.progress_time     = t_plan;
    schedule.row_interval      = row_interval;
    schedule.snapshot_interval = snap_interval;
    schedule.end_reason        = "end strain";
    StabilityWatch watch;
    watch.rock         = body_.get();
    watch.domain       = domain_.get();
    watch.steel        = {{"top platen", top_.get()}, {"bottom platen", bottom_.get()}};
    watch.domain_size  = domain_size_;
    watch.energy_floor = energy_floor_;
    watch.time_step    = dt_;
    watch.tssfac       = prm_.sph.tssfac;
    watch.likely_cause =
      "a time step above the stable limit (SPH/TSSFAC above 1, Platens/Contact stiffness scale "
      "near 1) or a loading rate far above quasi-static";
    RunLoop loop(*this, schedule, std::move(watch), prm_.output);
    const std::string reason                 = loop.run(observer, resume);
    const std::vector<HistoryRow> &rows      = loop.rows();
    const std::vector<double> &rock_kinetic  = loop.rock_kinetic();
    const std::vector<double> &rock_internal = loop.rock_internal();

    // ---- what the laboratory reads off the curves
    Summary s;
    s.test         = prm_.test;
    s.n_particles  = domain_ ? domain_->n_global() : body_->n_particles();
    if (!domain_)
      s.particles_per_rank = {s.n_particles};
    s.n_steps      = n_steps_;
    s.true_area    = true_area_;
    s.lattice_area = lattice_area_;
    s.strain_rate  = plan_.strain_rate;
    s.time_step    = dt_;
    s.stop_reason  = reason;
    std::vector<double> stress, strain, gauge, radial;
    for (const auto &r : rows)
    {
      // the axial phase only (CTCS: after the confinement ramp)
      if (r.time <= plan_.confinement_time)
        continue;
      stress.push_back(r.stress);
      strain.push_back(r.strain);
      gauge.push_back(r.axial_gauge_strain);
      radial.push_back(r.radial_strain);
    }
    if (!stress.empty())
    {
      const std::size_t k = peak_index(stress);
      s.peak_stress       = stress[k];
      s.strain_at_peak    = strain[k];
      double f_peak       = 0;
      for (const auto &r : rows)
        f_peak = std::max(f_peak, 0.5 * (r.force + r.force_bottom));
      s.peak_force = f_peak;
      if (!bts_)
      {
        // deviatoric stress for the moduli: CTCS loads from the hydrostatic state
        std::vector<double> dev(stress);
        const double p = ctcs_ ? prm_.confining_pressure : 0.0;
        std::vector<double> g0(gauge), r0(radial);
        for (std::size_t i = 0; i < dev.size(); ++i)
        {
          dev[i] -= p;
          g0[i] -= gauge.front();
          r0[i] -= radial.front();
        }
        s.youngs_modulus = secant_modulus(g0, dev);
        // the gauge strain is compression +, the radial one extension +: nu = -d(lat)/d(ax)
        // with both extension +
        std::vector<double> ax(g0);
        for (double &e : ax)
          e = -e;
        s.poissons_ratio = secant_poissons_ratio(ax, r0, dev);
        s.platen_modulus = secant_modulus(strain, dev);
      }
      else
        s.platen_modulus = secant_modulus(strain, stress);
    }
    // judged over the loading up to the peak, where the measurement is made: after it the
    // failure releases stored energy dynamically, as in a laboratory test
    double max_ratio = 0, max_imbalance = 0;
    for (std::size_t k = 0; k < rows.size(); ++k)
    {
      const HistoryRow &r = rows[k];
      if (r.time <= plan_.confinement_time || s.peak_force <= 0)
        continue;
      if (r.strain > s.strain_at_peak)
        break;
      const double load = 0.5 * (r.force + r.force_bottom);
      // judged once the specimen carries a tenth of its peak: before that both energies are tiny
      if (load < 0.1 * s.peak_force)
        continue;
      // the rock's own energies, and of its kinetic energy only the part that is not a
      // homogeneous deformation: a specimen loaded at a constant rate moves affinely (at 10 %
      // of the peak that motion alone holds 1.5 % of the elastic energy at the derived rate);
      // the platens' motion is the frame's
      if (rock_internal[k] > 0)
        max_ratio = std::max(max_ratio, rock_kinetic[k] / rock_internal[k]);
      max_imbalance = std::max(max_imbalance, std::abs(r.force - r.force_bottom) / s.peak_force);
    }
    s.max_kinetic_to_internal_energy = max_ratio;
    s.max_force_imbalance            = max_imbalance;
    s.max_exchange_imbalance         = max_exchange_imbalance_;
    // the penalty stiffness per particle before the loaded-face factors, for the series checks
    if (contact_method(prm_) == ContactMethod::penalty) // the kinematic contact has no stiffness
      s.extra.push_back({"contact_stiffness_N_per_m", contact_top_->stiffness()});
    // the SPH pairs (fixed in total Lagrangian; at the end in updated Lagrangian): with n_steps
    // and wall_seconds the pair interactions per second (tools/bench)
    s.extra.push_back({"n_sph_pairs", static_cast<double>(domain_ ? n_global_pairs_ : body_->n_pairs())});
    if (frame_)
      s.extra.push_back({"frame_stiffness_N_per_m", frame_->stiffness()});
    if (prm_.rock_case.rate_sensitivity != 0)
      s.extra.push_back({"rate_strength_factor",
                         sph::rock::rate_strength_factor(plan_.strain_rate,
                                                         prm_.rock_case.reference_strain_rate,
                                                         prm_.rock_case.rate_sensitivity)});
    s.max_displacement               = 0;
    for (const auto &r : rows)
      s.max_displacement = std::max(s.max_displacement, r.displacement);
    if (!rows.empty())
    {
      const auto &r       = rows.back();
      const double stored = r.kinetic_energy + r.internal_energy + r.dissipated_energy;
      s.energy_balance_error =
        r.external_work > 0 ? std::abs(stored - r.external_work) / r.external_work : 0.0;
    }
    failure_->report(*body_, s, domain_.get());
    if (domain_) // (the sum of the contact forces: both platens' and 7 more)
      report_split(*domain_, force_on_top_.size() + force_on_bottom_.size() + 7, wait_start, s);
    s.quasi_static = max_ratio <= prm_.loading.max_kinetic_ratio &&
                     max_imbalance <= prm_.loading.max_force_imbalance;
    s.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    return s;
  }

} // namespace coupling
