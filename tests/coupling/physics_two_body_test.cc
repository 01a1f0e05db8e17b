// Coupling checks on an SPH rock body and one FEM body: conservation in an impact, wave
// transmission across the steel/rock interface, and Coulomb friction onset and sliding.
#include "two_body.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

using namespace coupling;
using namespace coupling::testing;

namespace
{
  constexpr double pi = 3.14159265358979323846;

  // materials: basalt group M1 (Table 3) and steel
  constexpr double rock_E = 97.07e9, rock_rho = 2900.0;
  constexpr double steel_E = 200e9, steel_rho = 7850.0;

  std::unique_ptr<fem::SteelBody> steel_box(double size_xy, double thickness, double element,
                                            double poissons_ratio, bool free_body)
  {
    fem::BodyGeometry g;
    g.shape     = fem::BodyShape::box;
    g.size_x    = size_xy;
    g.size_y    = size_xy;
    g.thickness = thickness;
    g.side      = fem::BodySide::below; // contact face z = 0 on top, body below
    g.contact_z = 0.0;
    fem::Parameters p;
    p.youngs_modulus = steel_E;
    p.density        = steel_rho;
    p.poissons_ratio = poissons_ratio;
    p.element_size   = element;
    p.free_body      = free_body;
    return std::make_unique<fem::SteelBody>(g, p);
  }

  double norm(const std::array<double, 3> &a)
  {
    return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
  }
} // namespace

TEST(CoupledImpact, FreeBodiesKeepMomentumAndEnergy)
{
  // A 12 mm rock cube at 1 m/s strikes a free 16 x 16 x 8 mm steel block (no prescribed motion,
  // no support) and bounces off. Nothing outside acts on the pair.
  const double dx = 2e-3, v0 = 1.0;
  auto rock =
    rock_block({-6e-3, -6e-3, 2e-5}, {6e-3, 6e-3, 12e-3 + 2e-5}, dx, rock_E, 0.28, rock_rho);
  auto steel = steel_box(16e-3, 8e-3, 2e-3, 0.3, true);
  for (unsigned int i = 0; i < rock->n_particles(); ++i)
    rock->set_velocity(i, {0.0, 0.0, -v0});
  TwoBody pair(std::move(rock), std::move(steel), 0.1);

  const auto p_rock0 = pair.rock().momentum();
  const std::array<double, 3> p0{{p_rock0[0], p_rock0[1], p_rock0[2]}};
  const double e0 = pair.rock().energies().kinetic;
  ASSERT_GT(e0, 0.0);
  // kinetic energies live at half steps (v after integrate is v(t + dt/2)); the stored energies
  // (rock stress, penalty springs) at the step's positions x(t). The total at t therefore takes
  // the mean of the kinetic energies before and after the step.
  auto kinetic = [&] { return pair.rock().energies().kinetic + pair.platen().kinetic_energy(); };
  auto stored  = [&] {
    const sph::Energies e = pair.rock().energies();
    return e.internal + e.dissipated() + pair.platen().strain_energy() +
           pair.contact().penalty_energy();
  };
  double max_momentum_error = 0, max_energy_error = 0, max_exchange = 0;
  std::size_t steps_in_contact = 0;
  const int n_steps = 400; // about 130 us: contact and separation, ~ 40 us after first touch
  double final_energy_error = 0;
  for (int n = 0; n < n_steps; ++n)
  {
    const double kinetic_before = kinetic();
    pair.step();
    const double total = 0.5 * (kinetic_before + kinetic()) + stored();
    if (pair.n_contact() > 0)
    {
      ++steps_in_contact;
      double scale = 0;
      for (std::size_t i = 0; i < pair.force_on_rock().size(); i += 3)
        scale += std::hypot(pair.force_on_rock()[i], pair.force_on_rock()[i + 1],
                            pair.force_on_rock()[i + 2]);
      const auto a = vector_sum(pair.force_on_rock()), b = vector_sum(pair.force_on_platen());
      max_exchange =
        std::max(max_exchange, norm({{a[0] + b[0], a[1] + b[1], a[2] + b[2]}}) / scale);
    }
    const auto pr = pair.rock().momentum();
    const auto pf = pair.platen_momentum();
    const std::array<double, 3> dp{
      {pr[0] + pf[0] - p0[0], pr[1] + pf[1] - p0[1], pr[2] + pf[2] - p0[2]}};
    max_momentum_error = std::max(max_momentum_error, norm(dp) / norm(p0));
    max_energy_error   = std::max(max_energy_error, std::abs(total - e0) / e0);
    final_energy_error = (kinetic() + stored() - e0) / e0; // out of contact: no staggering
  }
  ASSERT_GT(steps_in_contact, 5u) << "the bodies must collide, or the test proves nothing";
  EXPECT_EQ(pair.n_contact(), 0u) << "the rock should have bounced off by the end";
  // the steel block took up momentum: the exchange really happened
  EXPECT_LT(pair.platen_momentum()[2], -0.1 * norm(p0));
  // forces cancel to round-off in every step (each pair force applied once to each side)
  EXPECT_LT(max_exchange, 1e-12);
  // 1e-10: internal forces of SPH (pairwise antisymmetric) and FEM (K has the rigid translations
  // in its null space) sum to zero, the contact impulse f dt is the same on both sides with the
  // sub-cycling, so only round-off of ~1e3 steps remains
  EXPECT_LT(max_momentum_error, 1e-10);
  // 2 % (the target's tolerance): kinetic + internal + dissipated (artificial viscosity, hourglass)
  // + FEM kinetic + strain + penalty energy, kinetic centred on the step. Measured 1.9 % at the
  // worst instant and 1.6 % after separation: the explicit penalty gains energy at the onset of
  // contact (which falls inside a step), the known error of explicit penalty impact; a stiffer
  // penalty gains more (0.2 of the bound: 2.5 %)
  EXPECT_LT(max_energy_error, 0.02);
  EXPECT_LT(std::abs(final_energy_error), 0.02);
  std::cout << "[impact] steps in contact " << steps_in_contact << ", n_substeps "
            << pair.n_substeps() << ", max momentum error " << max_momentum_error
            << ", max energy error " << max_energy_error << ", final energy error "
            << final_energy_error << ", max exchange " << max_exchange << "\n";
}

namespace
{
  /// Transmission T and reflection R of a stress pulse at a steel -> rock interface, the incident
  /// stress and the impedance theory's values.
  struct Pulse
  {
    double incident, incident_theory, T, R, T_theory, R_theory;
  };

  /// rock_gauge_layers: where the rock's stress is read, in spacings from the interface; 0 = three
  /// quarters of the pulse length in (clear of the interface's near field)
  Pulse pulse_through_interface(const double tau, const double scale, const ContactMethod method,
                                const int rock_gauge_layers = 0)
  {
    // A 4 x 4 mm steel bar (FEM) on a 4 x 4 mm rock bar (SPH), end to end at z = 0. Poisson's ratio
    // 0 in both makes the bars exactly one-dimensional (no lateral inertia, no dispersion from
    // it): the 1-D theory holds without a bar correction. A sin^2 velocity pulse of duration tau
    // enters at the steel's far end and is measured in both bars, clear of all other reflections.
    const double dx = 1e-3, a = 4e-3, v0 = 0.1;
    const double Z1 = std::sqrt(steel_E * steel_rho), Z2 = std::sqrt(rock_E * rock_rho);
    const double c1 = std::sqrt(steel_E / steel_rho), c2 = std::sqrt(rock_E / rock_rho);
    const double T_theory = 2 * Z2 / (Z1 + Z2), R_theory = (Z2 - Z1) / (Z1 + Z2);
    // steel gauge d_s before the interface, steel bar 2 d_s; rock gauge d_r into the rock, rock bar
    // long enough that the reflection from its free end comes back after the window
    const double d_s = dx * std::ceil(1.25 * c1 * tau / dx);
    const double d_r =
      rock_gauge_layers > 0 ? dx * rock_gauge_layers : dx * std::ceil(0.75 * c2 * tau / dx);
    const double L_r = d_r + dx * std::ceil(c2 * tau / dx);
    auto rock =
      rock_block({-0.5 * a, -0.5 * a, 0.0}, {0.5 * a, 0.5 * a, L_r}, dx, rock_E, 0.0, rock_rho);
    auto steel = steel_box(a, 2 * d_s, dx, 0.0, false);
    steel->set_loaded_face_velocity([&](double t) {
      // pushes the loaded face (z = -2 d_s) up into the bar: compression
      if (t <= 0 || t >= tau)
        return 0.0;
      const double s = std::sin(pi * t / tau);
      return v0 * s * s;
    });
    TwoBody pair(std::move(rock), std::move(steel), scale, 0, 0, method);

    // gauges: steel stress at z = -d_s from the node layers one element either side; rock stress
    // at z = d_r from the two particle layers either side
    const auto x0 = pair.platen().reference_positions();
    std::vector<unsigned int> s_hi, s_lo, r_gauge;
    for (unsigned int n = 0; n < x0.size() / 3; ++n)
    {
      if (std::abs(x0[3 * n + 2] + d_s - dx) < 1e-3 * dx)
        s_hi.push_back(n);
      if (std::abs(x0[3 * n + 2] + d_s + dx) < 1e-3 * dx)
        s_lo.push_back(n);
    }
    const auto &xr = pair.rock().reference_positions();
    for (unsigned int i = 0; i < xr.size(); ++i)
      if (std::abs(xr[i][2] - d_r) < 0.6 * dx)
        r_gauge.push_back(i);
    EXPECT_EQ(s_hi.size(), 25u);
    EXPECT_EQ(s_lo.size(), 25u);
    EXPECT_EQ(r_gauge.size(), 32u);

    auto steel_stress = [&] { // tension +
      const auto u = pair.platen().mesh_snapshot().displacement;
      double hi = 0, lo = 0;
      for (unsigned int n : s_hi)
        hi += u[3 * n + 2] / s_hi.size();
      for (unsigned int n : s_lo)
        lo += u[3 * n + 2] / s_lo.size();
      return steel_E * (hi - lo) / (2 * dx);
    };
    auto rock_stress = [&] {
      double s = 0;
      for (unsigned int i : r_gauge)
        s += pair.rock().stress3(i)(2, 2) / r_gauge.size();
      return s;
    };

    // windows (arrival of the pulse's front to its tail, with a margin): incident at the steel
    // gauge, reflected back at it, transmitted at the rock gauge
    const double margin = 0.25 * tau;
    const double t_inc0 = d_s / c1, t_ref0 = 3 * d_s / c1, t_tr0 = 2 * d_s / c1 + d_r / c2;
    const double t_end = t_ref0 + tau + margin;
    EXPECT_LT(t_end, 5 * d_s / c1) << "the reflection from the loaded end must not reach the gauge";
    double incident = 0, reflected = 0, transmitted = 0;
    while (pair.time() < t_end)
    {
      pair.step();
      const double t = pair.time();
      if (t > t_inc0 && t < t_inc0 + tau + margin)
        incident = std::min(incident, steel_stress()); // compression: negative
      if (t > t_ref0 && t < t_ref0 + tau + margin)
      {
        const double s = steel_stress();
        reflected      = std::abs(s) > std::abs(reflected) ? s : reflected;
      }
      if (t > t_tr0 && t < t_tr0 + tau + margin)
        transmitted = std::min(transmitted, rock_stress());
    }
    const double T = transmitted / incident, R = reflected / incident;
    std::cout << "[pulse] tau " << tau
              << (method == ContactMethod::kinematic ? " kinematic" : " penalty") << " scale "
              << scale << " sigma_I " << incident << " Pa (theory " << -Z1 * v0 << "), T " << T
              << " (theory " << T_theory << "), R " << R << " (theory " << R_theory
              << "), n_substeps " << pair.n_substeps() << ", k " << pair.stiffness() << " N/m\n";
    return {incident, -Z1 * v0, T, R, T_theory, R_theory};
  }
} // namespace

TEST(CoupledWave, PulseCrossesSteelRockInterfaceAsImpedanceTheorySays)
{
  // The penalty layer is a spring of stiffness kappa per area between the bars: transparent
  // for pulses much longer than its time constant Z1 Z2 / ((Z1 + Z2) kappa). At the driver's
  // default stiffness (0.1 of the bound, limited by the lightest corner node) that constant is
  // about 1.4 us and a 4 us pulse comes through at T = 0.38, R = -0.73 (measured); at 0.5 of the
  // bound (0.28 us) an 8 us pulse gives T, R within 4 % and 2 % of the theory.
  const Pulse p = pulse_through_interface(8e-6, 0.5, ContactMethod::penalty);
  // the incident pulse itself: rho c v0 in a 1-D bar. 2 %: the lumped-mass Q1 mesh has 20 or
  // more elements per pulse length, its dispersion lowers the peak by under 1 %
  EXPECT_NEAR(p.incident / p.incident_theory, 1.0, 0.02);
  // 5 %: the tolerance for a penalty interface. Error sources: the penalty layer (a spring in
  // series with the interface, which a pulse much longer than its time constant sees as rigid),
  // SPH and FEM dispersion
  EXPECT_NEAR(p.T / p.T_theory, 1.0, 0.05);
  EXPECT_NEAR(p.R / p.R_theory, 1.0, 0.05);
}

TEST(CoupledWave, KinematicInterfaceTransmitsAsImpedanceTheorySays)
{
  // The kinematic constraint has no spring: the interface itself is rigid, so a pulse half as
  // long as the penalty test's (4 us, which the default penalty layer passes at T = 0.38) must
  // cross as the impedances say. The rock's stress is read three spacings from the interface: the
  // artificial viscosity of SPH attenuates a 4 us pulse by several per cent over the penalty
  // test's 17 mm, which is the rock's property, not the interface's (at 8 us and 34 mm: T 0.575,
  // -3.4 %, while 1 + R = 0.598 holds continuity). 3 %: the interface's tolerance; measured T
  // -0.08 %, R -1.1 % (FEM dispersion of the 4 us pulse, about 20 steel elements per length;
  // with the steel sub-cycled twice under the rock's step, as before the constraint took the
  // smaller step: T -0.2 %, R -2.0 %)
  const Pulse p = pulse_through_interface(4e-6, 0.0, ContactMethod::kinematic, 3);
  EXPECT_NEAR(p.incident / p.incident_theory, 1.0, 0.02);
  EXPECT_NEAR(p.T / p.T_theory, 1.0, 0.03);
  EXPECT_NEAR(p.R / p.R_theory, 1.0, 0.03);
}
