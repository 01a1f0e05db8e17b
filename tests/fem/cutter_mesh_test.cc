// Cutter and indenter meshes (wedge, cone, CCS disc cutter) against their closed-form volumes and
// tip profiles, and the prescribed translation of a cutter along x with its load cell.
#include <fem/steel_body.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace
{
  constexpr double pi = 3.14159265358979323846;

  fem::Parameters steel(const double h)
  {
    fem::Parameters prm;
    prm.element_size = h;
    return prm;
  }

  /// The lowest contact-node z [m] and its (x, y).
  std::array<double, 3> lowest_node(const fem::SteelBody &p)
  {
    const auto x = p.contact_positions();
    std::array<double, 3> best{{0, 0, 1e300}};
    for (std::size_t i = 0; i < x.size(); i += 3)
      if (x[i + 2] < best[2])
        best = {{x[i], x[i + 1], x[i + 2]}};
    return best;
  }
} // namespace

TEST(CutterMesh, WedgeFollowsItsFlanksAndHoldsItsVolume)
{
  // 90-degree wedge (half-angle 45 deg), 20 mm wide, 30 mm long, tip at z = 0.01
  fem::BodyGeometry g;
  g.shape          = fem::BodyShape::wedge;
  g.size_x         = 0.02;
  g.size_y         = 0.03;
  g.thickness      = 0.025;
  g.tip_half_angle = pi / 4;
  g.contact_z      = 0.01;
  g.center_x       = 0.005;
  const fem::SteelBody wedge(g, steel(0.0025));
  const auto x = wedge.contact_positions();
  ASSERT_GT(x.size(), 3u * 20);
  // every contact node lies on z = z_tip + |x - x_c| / tan(alpha): placed there, round-off only
  for (std::size_t i = 0; i < x.size(); i += 3)
    EXPECT_NEAR(x[i + 2], g.contact_z + std::abs(x[i] - g.center_x) / std::tan(g.tip_half_angle),
                1e-12);
  // the tip is a vertex line at x = x_c, z = contact_z (even cell count across x)
  const auto tip = lowest_node(wedge);
  EXPECT_NEAR(tip[0], g.center_x, 1e-12);
  EXPECT_NEAR(tip[2], g.contact_z, 1e-12);
  // volume: box less the two triangular prisms under the flanks, a^2 / tan(alpha) per unit length;
  // the bending is bilinear in each cell, so the trilinear mesh is exact: round-off only
  const double a = 0.5 * g.size_x;
  const double V =
    g.size_x * g.size_y * g.thickness - a * a / std::tan(g.tip_half_angle) * g.size_y;
  EXPECT_NEAR(wedge.mesh_volume() / V, 1.0, 1e-10);
  EXPECT_LT(wedge.contact_normal_z(), 0.0);
}

TEST(CutterMesh, ConeHasItsApexOnTheAxisAndItsVolume)
{
  // 120-degree cone (half-angle 60 deg), 16 mm diameter, tip at the origin
  fem::BodyGeometry g;
  g.shape          = fem::BodyShape::cone;
  g.diameter       = 0.016;
  g.thickness      = 0.015;
  g.tip_half_angle = pi / 3;
  const fem::SteelBody cone(g, steel(0.001));
  const auto x = cone.contact_positions();
  for (std::size_t i = 0; i < x.size(); i += 3)
    EXPECT_NEAR(x[i + 2], std::hypot(x[i], x[i + 1]) / std::tan(g.tip_half_angle), 1e-12);
  const auto tip = lowest_node(cone);
  EXPECT_NEAR(std::hypot(tip[0], tip[1]), 0.0, 1e-12);
  EXPECT_NEAR(tip[2], 0.0, 1e-12);
  // volume: the cylinder less the ring around the cone, int_0^R 2 pi r (r / tan(alpha)) dr =
  // 2 pi R^3 / (3 tan(alpha)). The mesh's polygonal hull and piecewise-bilinear cone lose a little
  // (0.6 % is the hull's share at 1 mm cells on an 8 mm radius, 0.7 % in all): 2 %
  const double R = 0.5 * g.diameter;
  const double V =
    pi * R * R * g.thickness - 2.0 * pi * R * R * R / std::tan(g.tip_half_angle) / 3.0;
  EXPECT_NEAR(cone.mesh_volume() / V, 1.0, 0.02);
}

TEST(CutterMesh, RoundedConeTipIsTangentToItsFlanks)
{
  // 90-degree cone with a 3 mm tip radius: the circle up to r_t = rho cos(alpha), then the flank
  fem::BodyGeometry g;
  g.shape          = fem::BodyShape::cone;
  g.diameter       = 0.016;
  g.thickness      = 0.015;
  g.tip_half_angle = pi / 4;
  g.tip_radius     = 0.003;
  const fem::SteelBody cone(g, steel(0.001));
  const double rho = g.tip_radius, a = g.tip_half_angle, r_t = rho * std::cos(a);
  const auto x         = cone.contact_positions();
  std::size_t n_on_cap = 0;
  for (std::size_t i = 0; i < x.size(); i += 3)
  {
    const double r = std::hypot(x[i], x[i + 1]);
    // independent of fem's branch: the lower of the sphere cap and the flank shifted to be tangent
    const double cap   = rho - std::sqrt(std::max(0.0, rho * rho - r * r));
    const double flank = r / std::tan(a) - rho * (1.0 / std::sin(a) - 1.0);
    const double z     = r <= r_t ? cap : flank;
    n_on_cap += r <= r_t;
    EXPECT_NEAR(x[i + 2], z, 1e-12);
    EXPECT_GE(x[i + 2], flank - 1e-12); // the cap lies above the shifted flank (tangent from above)
  }
  EXPECT_GE(n_on_cap, 5u) << "the cap must be resolved by several nodes";
  EXPECT_NEAR(lowest_node(cone)[2], 0.0, 1e-12);
}

TEST(CutterMesh, DiscCutterRimIsItsArc)
{
  // 17-inch CCS disc (R = 215.9 mm), tip 12.7 mm wide, a 60 mm chord of the rim
  fem::BodyGeometry g;
  g.shape         = fem::BodyShape::disc_cutter;
  g.size_x        = 0.06;
  g.size_y        = 0.0127;
  g.thickness     = 0.02;
  g.cutter_radius = 0.2159;
  g.contact_z     = 0.0;
  const fem::SteelBody disc(g, steel(0.003));
  const auto x   = disc.contact_positions();
  const double R = g.cutter_radius;
  for (std::size_t i = 0; i < x.size(); i += 3)
    EXPECT_NEAR(x[i + 2], R - std::sqrt(R * R - x[i] * x[i]), 1e-12);
  EXPECT_NEAR(lowest_node(disc)[2], 0.0, 1e-12);
  // volume: the box less the circular segment below the chord; the mesh chords the arc, an error
  // of about h^2 / (12 R T) of the volume (1e-4 here): 1e-3
  const double a       = 0.5 * g.size_x;
  const double segment = 2.0 * a * R - (a * std::sqrt(R * R - a * a) + R * R * std::asin(a / R));
  const double V       = g.size_x * g.size_y * g.thickness - segment * g.size_y;
  EXPECT_NEAR(disc.mesh_volume() / V, 1.0, 1e-3);
  // too thin a body for the rim's rise is refused with a message
  g.thickness = 0.001;
  EXPECT_THROW(fem::SteelBody(g, steel(0.003)), std::invalid_argument);
}

TEST(CutterMotion, RigidCutterTranslatesAndItsLoadCellBalancesTheContactForce)
{
  fem::BodyGeometry g;
  g.shape             = fem::BodyShape::wedge;
  g.size_x            = 0.02;
  g.size_y            = 0.02;
  g.thickness         = 0.02;
  g.tip_half_angle    = pi / 4;
  fem::Parameters prm = steel(0.005);
  prm.model           = fem::SteelModel::rigid;
  fem::SteelBody wedge(g, prm);
  const double vx = 0.5, vz = -0.1;
  wedge.set_loaded_face_velocity_x([&](double) { return vx; });
  wedge.set_loaded_face_velocity([&](double) { return vz; });
  // start at speed (no impulsive start): every node at (vx, 0, vz)
  std::vector<double> u0(3 * wedge.n_nodes(), 0.0), v0(3 * wedge.n_nodes(), 0.0);
  for (std::size_t k = 0; k < wedge.n_nodes(); ++k)
    v0[3 * k] = vx, v0[3 * k + 2] = vz;
  wedge.set_state(u0, v0);
  const auto x0       = wedge.contact_positions();
  const double dt     = 1e-6;
  const std::size_t n = wedge.n_contact_nodes();
  // a constant contact force: 10 N per node along +x and +z (the rock pushing back)
  std::vector<double> f(3 * n, 0.0);
  for (std::size_t k = 0; k < n; ++k)
    f[3 * k] = f[3 * k + 2] = 10.0;
  for (int s = 0; s < 100; ++s)
  {
    wedge.add_contact_forces(f);
    wedge.step(s * dt, dt);
  }
  const auto x = wedge.contact_positions();
  // at constant velocity the body moved by v t (round-off)
  EXPECT_NEAR(x[0] - x0[0], vx * 100 * dt, 1e-15);
  EXPECT_NEAR(x[2] - x0[2], vz * 100 * dt, 1e-15);
  // no acceleration: the frame holds exactly the contact force, R = -F (relative round-off)
  const auto r = wedge.reaction_force_vector();
  EXPECT_NEAR(r[0] / (10.0 * n), -1.0, 1e-12);
  EXPECT_NEAR(r[1], 0.0, 1e-9);
  EXPECT_NEAR(r[2] / (10.0 * n), -1.0, 1e-12);
  // the frame's work cancels that of the contact forces (no kinetic energy change)
  EXPECT_NEAR(wedge.external_work() / (10.0 * n * (std::abs(vx) + std::abs(vz)) * 100 * dt), 0.0,
              1e-9);
}
