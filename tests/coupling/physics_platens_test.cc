// The coupled driver with elastic steel platens: the forces exchanged each step cancel,
// and the apparent modulus against the series stiffness of rock, contact layers and platens;
// BTS with the ISRM curved jaws.
#include "run_helpers.h"

#include <app/case_file.h>
#include <coupling/contact.h>
#include <coupling/run_case.h>

#include <fem/steel_body.h>
#include <sph/lattice.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iostream>

using namespace coupling;
using namespace coupling::test;

namespace
{
  CaseParameters elastic_ucs_elastic_platens()
  {
    CaseParameters p;
    p.test                = "UCS";
    p.rock.model          = sph::RockModel::elastic;
    p.rock.youngs_modulus = 97.07e9; // group M1, Table 3
    p.rock.poissons_ratio = 0.28;
    // D 25 x 50 mm at 2.5 mm (10 particles across): 1/16 of the cost of the 50 x 100 mm case,
    // enough for a uniform elastic field
    p.diameter              = 0.025;
    p.length                = 0.05;
    p.sph.spacing           = 2.5e-3;
    p.sph.n_threads         = 1; // ctest runs two tests at a time on two cores
    p.platens.steel.model         = fem::SteelModel::elastic;
    // 35 mm (1.4 D): the tolerances below were measured on this width (the default 1.2 D, 30
    // mm, reads +3.3 % on the penalty series)
    p.platens.diameter      = 0.035;
    p.loading.end_strain    = 1e-3;
    p.output.n_history_rows = 200;
    return p;
  }

  /// The platen geometry the driver builds for a UCS case (specimen_driver.cc, build_platens):
  /// a steel disc Platens/Diameter wide (0: 1.2 D), elements of 2 dx; here the bottom one (both
  /// are alike).
  fem::SteelBody bottom_platen(const CaseParameters &c)
  {
    fem::BodyGeometry g;
    g.shape     = fem::BodyShape::cylinder;
    g.diameter  = cylinder_platen_diameter(c);
    g.thickness = c.platens.thickness;
    g.side      = fem::BodySide::below;
    g.contact_z = 0.0;
    fem::Parameters fp;
    fp.youngs_modulus = c.platens.steel.youngs_modulus;
    fp.poissons_ratio = c.platens.steel.poissons_ratio;
    fp.density        = c.platens.steel.density;
    fp.element_size   = 2.0 * c.sph.spacing;
    return fem::SteelBody(g, fp);
  }

  /// FEM only, no SPH: the compliance [m/N] of a platen under the rock's bottom particle layer,
  /// loaded face held, as the mean displacement under the particles per unit force. The load is
  /// the same force on every particle of the layer, spread to the face nodes as the contact
  /// spreads it; then f . u / F^2 is the mean displacement under the particles per unit force.
  /// K u = f is solved statically by conjugate gradients on the platen's own stiffness.
  double platen_compliance(const fem::SteelBody &platen, const std::vector<sph::Vector<3>> &layer,
                           double radius)
  {
    ContactSurface s;
    s.position = platen.contact_positions();
    s.velocity.assign(s.position.size(), 0.0);
    s.mass.assign(platen.n_contact_nodes(), 0.0);
    s.faces = quad_faces(platen.contact_faces());
    std::vector<double> x, v(3 * layer.size(), 0.0), m(layer.size(), 1.0);
    const double depth = 1e-6; // each particle pressed 1e-6 m into the face at k = 1 N/m
    for (const auto &p : layer)
      x.insert(x.end(), {p[0], p[1], radius - depth});
    ContactParameters cp;
    cp.stiffness = 1.0;
    cp.radius    = radius;
    PenaltyContact contact(cp, layer.size());
    std::vector<double> f_particles(x.size(), 0.0), f_nodes(s.position.size(), 0.0);
    const std::size_t n_in =
      contact.apply({x.data(), v.data(), m.data(), layer.size()}, s, 1.0, f_particles, f_nodes);
    EXPECT_EQ(n_in, layer.size()) << "every particle of the layer must load the platen";
    const double F = depth * layer.size();

    // contact node -> mesh vertex (same reference positions), loaded face held
    const auto x0            = platen.reference_positions();
    const std::size_t n_dofs = x0.size();
    std::vector<double> f(n_dofs, 0.0);
    std::vector<bool> free(n_dofs, true);
    double z_min = 1e300;
    for (std::size_t k = 2; k < n_dofs; k += 3)
      z_min = std::min(z_min, x0[k]);
    for (std::size_t n = 0; n < n_dofs / 3; ++n)
      if (std::abs(x0[3 * n + 2] - z_min) < 1e-9)
        free[3 * n] = free[3 * n + 1] = free[3 * n + 2] = false;
    for (std::size_t c = 0; c < platen.n_contact_nodes(); ++c)
    {
      std::size_t match = n_dofs;
      for (std::size_t n = 0; n < n_dofs / 3 && match == n_dofs; ++n)
        if (std::abs(x0[3 * n] - s.position[3 * c]) +
              std::abs(x0[3 * n + 1] - s.position[3 * c + 1]) +
              std::abs(x0[3 * n + 2] - s.position[3 * c + 2]) <
            1e-12)
          match = n;
      EXPECT_LT(match, n_dofs);
      for (int d = 0; d < 3; ++d)
        f[3 * match + d] += f_nodes[3 * c + d];
    }
    auto apply_K = [&](const std::vector<double> &u) {
      std::vector<double> w(u);
      for (std::size_t i = 0; i < n_dofs; ++i)
        if (!free[i])
          w[i] = 0;
      std::vector<double> r = platen.internal_force(w);
      for (std::size_t i = 0; i < n_dofs; ++i)
        if (!free[i])
          r[i] = 0;
      return r;
    };
    auto dot = [](const std::vector<double> &a, const std::vector<double> &b) {
      double s = 0;
      for (std::size_t i = 0; i < a.size(); ++i)
        s += a[i] * b[i];
      return s;
    };
    for (std::size_t i = 0; i < n_dofs; ++i)
      if (!free[i])
        f[i] = 0;
    std::vector<double> u(n_dofs, 0.0), r(f), p(f);
    double rr        = dot(r, r);
    const double rr0 = rr;
    for (int it = 0; it < 20000 && rr > 1e-24 * rr0; ++it)
    {
      const std::vector<double> Kp = apply_K(p);
      const double alpha           = rr / dot(p, Kp);
      for (std::size_t i = 0; i < n_dofs; ++i)
      {
        u[i] += alpha * p[i];
        r[i] -= alpha * Kp[i];
      }
      const double rr_new = dot(r, r);
      for (std::size_t i = 0; i < n_dofs; ++i)
        p[i] = r[i] + (rr_new / rr) * p[i];
      rr = rr_new;
    }
    EXPECT_LT(rr, 1e-20 * rr0) << "CG did not converge";
    return dot(f, u) / (F * F);
  }

  /// The parts of the series stiffness of elastic_ucs_elastic_platens()-like case `c`, each
  /// computed without the coupled run: the true section [m^2], the rock's compliance L / (E A)
  /// [m/N], the particles of the end layer, and one platen's compliance under that layer from a
  /// static FEM-only solve [m/N].
  struct SeriesParts
  {
    double area = 0, rock = 0, platen = 0;
    std::size_t n_layer = 0;
  };
  SeriesParts series_parts(const CaseParameters &c)
  {
    const auto lattice = sph::make_cylinder<3>(c.diameter, c.length, c.sph.spacing);
    double z_min       = 1e300;
    for (const auto &p : lattice.positions)
      z_min = std::min(z_min, p[2]);
    std::vector<sph::Vector<3>> layer;
    for (const auto &p : lattice.positions)
      if (std::abs(p[2] - z_min) < 1e-9)
        layer.push_back(p);
    SeriesParts parts;
    parts.area    = lattice.true_section_area;
    parts.rock    = c.length / (c.rock.youngs_modulus * parts.area);
    parts.platen  = platen_compliance(bottom_platen(c), layer, 0.5 * c.sph.spacing);
    parts.n_layer = layer.size();
    return parts;
  }
} // namespace

TEST(CoupledUcs, ElasticPlatensGiveTheSeriesStiffnessAndForcesCancelEveryStep)
{
  // the penalty interface: its springs are a compliance of their own in the series
  CaseParameters c            = elastic_ucs_elastic_platens();
  c.platens.contact_method    = ContactMethod::penalty;
  Keep rows;
  const Summary s = run_case(c, rows);
  ASSERT_GT(s.peak_force, 0.0) << "the specimen must carry load, or the test proves nothing";

  // (1) the forces exchanged between rock and platens, both platens sub-cycled: every pair force
  // is applied once to each side, so only round-off may remain, in every step
  EXPECT_LT(s.max_exchange_imbalance, 1e-12);

  // (2) the series stiffness, each part computed without the coupled run:
  //  - rock: E A / L on the true section (the gauge modulus of the rigid-platen test is E within
  //    1 % on this section);
  //  - each contact layer: n_c penalty springs of stiffness k in parallel (k as the driver sets
  //    it: the default fraction of the central-difference bound of the lightest particle against
  //    the lightest contact node, at the rock's own time step);
  //  - each platen: its compliance under the particle layer from a static FEM-only solve.
  const SeriesParts parts = series_parts(c);
  // k as the driver sets it (summary.json: contact_stiffness_N_per_m)
  const double k = extra(s, "contact_stiffness_N_per_m");
  ASSERT_GT(k, 0.0);
  const double area          = parts.area;
  const double rock_c        = parts.rock;
  const double contact_c     = 1.0 / (parts.n_layer * k);
  const double platen_c      = parts.platen;
  const double series_c      = rock_c + 2.0 * contact_c + 2.0 * platen_c;
  const double expected      = c.length / (series_c * area);
  const double without_layer = c.length / ((rock_c + 2.0 * platen_c) * area);
  std::cout << "[series] apparent modulus " << s.platen_modulus / 1e9 << " GPa, expected "
            << expected / 1e9 << " GPa (rock " << c.rock.youngs_modulus / 1e9
            << ", compliances rock " << rock_c << ", contact " << contact_c << ", platen "
            << platen_c << " m/N; without the contact layers " << without_layer / 1e9
            << " GPa), gauge modulus " << s.youngs_modulus / 1e9 << " GPa, exchange imbalance "
            << s.max_exchange_imbalance << ", steps " << s.n_steps << "\n";
  // 3 %: the target's tolerance against the series stiffness (measured +2.7 %: 63.16 against
  // 61.51 GPa; the rest is the contact layer, whose springs do not all carry the same load).
  // Before the contact fix of ContactRidge (particles over a platen mesh vertex that sank less
  // than its neighbours lost their contact) it was +4.2 %, and the gauges read 100.89 GPa.
  EXPECT_NEAR(s.platen_modulus / expected, 1.0, 0.03);
  // the platens really are compliant here: the check is not the rigid one in disguise
  EXPECT_GT(2.0 * platen_c / series_c, 0.05);
  // the rock itself reads its modulus on the gauges through elastic platens, within the 1 % of
  // the rigid-platen check (measured 96.88 GPa against 97.07, -0.2 %)
  EXPECT_NEAR(s.youngs_modulus / c.rock.youngs_modulus, 1.0, 0.01);
}

TEST(CoupledBts, CurvedJawsSplitTheDiscAboveTheFlatPlatenStrength)
{
  // cases/bts (M1, D 50 x 25 mm, 2.5 mm spacing) with flat platens and with the ISRM jaws
  // (arc radius 1.5 disc radii, concave: they cradle the disc)
  const std::string bts = std::string(COSIM_SOURCE_DIR) + "/cases/bts/bts-round.prm";
  CaseParameters flat   = app::read_case_file(bts, {}).parameters;
  CaseParameters jaw    = app::read_case_file(bts, {"Platens/Shape=jaw"}).parameters;
  flat.sph.n_threads = jaw.sph.n_threads = 1; // ctest runs two tests at a time on two cores
  Keep rows_flat, rows_jaw;
  const Summary f = run_case(flat, rows_flat);
  const Summary j = run_case(jaw, rows_jaw);
  std::cout << "[jaw] flat " << f.peak_stress / 1e6 << " MPa (" << f.stop_reason << "), jaw "
            << j.peak_stress / 1e6 << " MPa (" << j.stop_reason << "), ratio "
            << j.peak_stress / f.peak_stress << "\n";
  // both split the disc: the load falls past its peak (before the jaws were bent the wrong way,
  // convex, and the run ended at the end displacement at 7.9 MPa without a split)
  EXPECT_EQ(f.stop_reason, "post-peak drop");
  EXPECT_EQ(j.stop_reason, "post-peak drop");
  // Hondros: a load spread over a contact arc 2 alpha lowers the tension at the disc centre by
  // the factor (sin 2 alpha - alpha) / alpha at a given load (0.96 at alpha = 10 deg, 0.91 at
  // 15 deg, the arcs of the ISRM jaw at failure), so the jaw's 2P/(pi D t) at the split lies
  // above the flat platens' (a line contact at this resolution) by up to ~10 %; 15 % allows
  // for the flat platens' own contact flattening (measured 1.121)
  EXPECT_GT(j.peak_stress / f.peak_stress, 1.0);
  EXPECT_LT(j.peak_stress / f.peak_stress, 1.15);
  EXPECT_LT(j.max_exchange_imbalance, 1e-12);
}

TEST(CoupledKinematic, ElasticPlatensGiveTheSeriesStiffnessWithoutAnInterfaceLayer)
{
  // the default (kinematic) interface on the same case: no contact layer in the series, the end
  // particles' half cells straining with them (CoupledKinematic.ElasticUcsShowsNoInterfaceCompliance)
  const CaseParameters c = elastic_ucs_elastic_platens();
  Keep rows;
  const Summary s = run_case(c, rows);
  ASSERT_GT(s.peak_force, 0.0) << "the specimen must carry load, or the test proves nothing";
  // every pair force applied once to each side, the Jacobi sweeps included
  EXPECT_LT(s.max_exchange_imbalance, 1e-12);
  const SeriesParts parts = series_parts(c);
  const double rock_c     = parts.rock, platen_c = parts.platen;
  const double expected   = c.length / ((rock_c + 2.0 * platen_c) * parts.area);
  std::cout << "[series, kinematic] apparent modulus " << s.platen_modulus / 1e9 << " GPa, expected "
            << expected / 1e9 << " GPa, gauge modulus " << s.youngs_modulus / 1e9 << " GPa, energy error "
            << s.energy_balance_error << "\n";
  // 3 %: the tolerance of the penalty test above, whose series has the same rock and platens
  EXPECT_NEAR(s.platen_modulus / expected, 1.0, 0.03);
  EXPECT_GT(2.0 * platen_c / (rock_c + 2.0 * platen_c), 0.05);
  EXPECT_NEAR(s.youngs_modulus / c.rock.youngs_modulus, 1.0, 0.01);
  // 1 %: the interface's energy target (an elastic face predicted without its own acceleration
  // booked 15 % of the work as the interface's)
  EXPECT_LT(s.energy_balance_error, 0.01);
}
