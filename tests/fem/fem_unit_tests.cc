// Unit tests of fem::SteelBody: mesh and boundary ids, lumped mass, the kernel of the stiffness
// (rigid motion), patch test, lambda_max against a dense eigen-solve, rigid mode, API errors.

#include <fem/steel_body.h>

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace
{
  constexpr double pi = 3.14159265358979323846;

  fem::BodyGeometry box_geometry(double sx, double sy, double t, double contact_z,
                                   fem::BodySide side)
  {
    fem::BodyGeometry g;
    g.shape     = fem::BodyShape::box;
    g.size_x    = sx;
    g.size_y    = sy;
    g.thickness = t;
    g.contact_z = contact_z;
    g.side      = side;
    return g;
  }

  fem::BodyGeometry cylinder_geometry(double d, double t, double contact_z, fem::BodySide side)
  {
    fem::BodyGeometry g;
    g.shape     = fem::BodyShape::cylinder;
    g.diameter  = d;
    g.thickness = t;
    g.contact_z = contact_z;
    g.side      = side;
    return g;
  }

  double max_abs(const std::vector<double> &a)
  {
    double m = 0.0;
    for (const double x : a)
      m = std::max(m, std::abs(x));
    return m;
  }

  /// Smooth ramp 0 -> 1 over [0, t_ramp]: (1 - cos(pi t / t_ramp)) / 2, then 1.
  double ramp(double t, double t_ramp)
  {
    return t >= t_ramp ? 1.0 : 0.5 * (1.0 - std::cos(pi * t / t_ramp));
  }
} // namespace

TEST(FemMesh, BoxLumpedMassSumsToRhoV)
{
  fem::Parameters prm;
  prm.element_size = 0.005;
  const fem::SteelBody platen(box_geometry(0.07, 0.04, 0.02, 0.0, fem::BodySide::above), prm);
  const double V = 0.07 * 0.04 * 0.02; // a box is meshed exactly
  // the row-sum mass integrates N_i with Gauss 2x2x2, exact for trilinear cells: round-off only,
  // so 1e-4 (the brief's bound) is loose by many orders
  EXPECT_NEAR(platen.total_mass() / (prm.density * V), 1.0, 1e-4);
  EXPECT_NEAR(platen.mesh_volume() / V, 1.0, 1e-12);
  double sum = 0.0;
  for (const double m : platen.nodal_masses())
  {
    EXPECT_GT(m, 0.0);
    sum += m;
  }
  EXPECT_NEAR(sum / platen.total_mass(), 1.0, 1e-12); // same numbers summed in another order
}

TEST(FemMesh, CylinderLumpedMassSumsToRhoTimesMeshVolume)
{
  fem::Parameters prm;
  prm.element_size = 0.005;
  const double d = 0.07, t = 0.02;
  const fem::SteelBody platen(cylinder_geometry(d, t, 0.1, fem::BodySide::above), prm);
  // mass vs the mesh's own volume: exact up to round-off (see the box test)
  EXPECT_NEAR(platen.total_mass() / (prm.density * platen.mesh_volume()), 1.0, 1e-4);
  // The trilinear mesh is a prism over an inscribed polygon: its volume is below pi r^2 t by
  // about (2 pi / N)^2 / 6 for N rim vertices; N >= 32 here, so the deficit is under 0.7 %.
  const double V_exact = pi * 0.25 * d * d * t;
  EXPECT_LT(platen.mesh_volume(), V_exact);
  EXPECT_GT(platen.mesh_volume(), 0.993 * V_exact);
}

TEST(FemMesh, FacesSitOnTheirSideAndContactNormalsPointOut)
{
  fem::Parameters prm;
  prm.element_size = 0.005;
  for (const auto side : {fem::BodySide::above, fem::BodySide::below})
    for (const bool cylinder : {false, true})
    {
      const double cz = 0.05, t = 0.02;
      const fem::SteelBody platen(cylinder ? cylinder_geometry(0.05, t, cz, side)
                                        : box_geometry(0.06, 0.03, t, cz, side),
                               prm);
      const double n_z = (side == fem::BodySide::above) ? -1.0 : 1.0;
      EXPECT_DOUBLE_EQ(platen.contact_normal_z(), n_z);

      const auto x = platen.contact_positions();
      ASSERT_EQ(x.size(), 3 * platen.n_contact_nodes());
      for (std::size_t i = 0; i < platen.n_contact_nodes(); ++i)
        EXPECT_NEAR(x[3 * i + 2], cz, 1e-12); // mesh vertices placed by a shift: round-off

      // the body lies on its side of the contact plane
      const auto x0 = platen.reference_positions();
      double zmin = 1e9, zmax = -1e9;
      for (std::size_t i = 2; i < x0.size(); i += 3)
      {
        zmin = std::min(zmin, x0[i]);
        zmax = std::max(zmax, x0[i]);
      }
      EXPECT_NEAR(zmin, n_z < 0 ? cz : cz - t, 1e-12);
      EXPECT_NEAR(zmax, n_z < 0 ? cz + t : cz, 1e-12);

      // every face normal (p1-p0)x(p3-p0) points out of the platen, and the faces tile the
      // contact face: their areas (each quad as two triangles) sum to the face area
      const auto &faces = platen.contact_faces();
      ASSERT_EQ(faces.size() % 4, 0u);
      double area = 0.0;
      for (std::size_t f = 0; f < faces.size(); f += 4)
      {
        auto p          = [&](unsigned int k, unsigned int d) { return x[3 * faces[f + k] + d]; };
        const double ax = p(1, 0) - p(0, 0), ay = p(1, 1) - p(0, 1);
        const double bx = p(3, 0) - p(0, 0), by = p(3, 1) - p(0, 1);
        EXPECT_GT((ax * by - ay * bx) * n_z, 0.0);
        const double cx = p(2, 0) - p(0, 0), cy = p(2, 1) - p(0, 1);
        area += 0.5 * std::abs(ax * cy - ay * cx) + 0.5 * std::abs(cx * by - cy * bx);
      }
      double trib = 0.0;
      for (const double a : platen.contact_areas())
        trib += a;
      // planar quads: the tributary areas integrate the same face, exact up to round-off
      EXPECT_NEAR(trib / area, 1.0, 1e-10);
      if (!cylinder)
      {
        EXPECT_NEAR(area / (0.06 * 0.03), 1.0, 1e-10);
      }
    }
}

TEST(FemStiffness, RigidTranslationAndSmallRotationGiveNoInternalForce)
{
  fem::Parameters prm;
  prm.element_size = 0.006;
  const fem::SteelBody platen(cylinder_geometry(0.05, 0.02, 0.0, fem::BodySide::below), prm);
  const auto x0       = platen.reference_positions();
  const std::size_t n = x0.size();

  // translation by 1 mm in each direction
  std::vector<double> u(n);
  for (std::size_t i = 0; i < n; ++i)
    u[i] = 1e-3 * (1.0 + (i % 3));
  // force scale: E h |u| per node, the size of a force that one element's strain would give
  const double scale = prm.youngs_modulus * prm.element_size * 3e-3;
  EXPECT_LT(max_abs(platen.internal_force(u)), 1e-10 * scale); // round-off of K's row sums

  // infinitesimal rotation u = theta x (x - c): zero strain, so K u = 0 in linear elasticity
  const double theta[3] = {1e-3, -2e-3, 3e-3}, c[3] = {0.01, -0.02, 0.005};
  for (std::size_t v = 0; v < n / 3; ++v)
  {
    const double r[3] = {x0[3 * v] - c[0], x0[3 * v + 1] - c[1], x0[3 * v + 2] - c[2]};
    u[3 * v]          = theta[1] * r[2] - theta[2] * r[1];
    u[3 * v + 1]      = theta[2] * r[0] - theta[0] * r[2];
    u[3 * v + 2]      = theta[0] * r[1] - theta[1] * r[0];
  }
  const double rot_scale = prm.youngs_modulus * prm.element_size * max_abs(u);
  ASSERT_GT(max_abs(u), 0.0);
  EXPECT_LT(max_abs(platen.internal_force(u)), 1e-10 * rot_scale); // round-off only
}

TEST(FemStiffness, LinearFieldLeavesInteriorNodesInEquilibrium)
{
  // patch test: u linear in x gives a uniform stress, whose nodal forces cancel at every node
  // not on the boundary; the resultant over the whole body is zero as well
  fem::Parameters prm;
  prm.element_size = 0.005;
  const fem::SteelBody platen(box_geometry(0.02, 0.02, 0.02, 0.0, fem::BodySide::above), prm);
  const auto x0 = platen.reference_positions();
  std::vector<double> u(x0.size());
  for (std::size_t v = 0; v < x0.size() / 3; ++v)
  {
    u[3 * v]     = 1e-4 * x0[3 * v] + 2e-4 * x0[3 * v + 1];
    u[3 * v + 1] = -3e-4 * x0[3 * v + 2];
    u[3 * v + 2] = 5e-4 * x0[3 * v + 2] + 1e-4 * x0[3 * v];
  }
  const auto f           = platen.internal_force(u);
  const double scale     = prm.youngs_modulus * 5e-4 * 0.005 * 0.005; // sigma * element face area
  double resultant[3]    = {0, 0, 0};
  std::size_t n_interior = 0;
  for (std::size_t v = 0; v < x0.size() / 3; ++v)
  {
    bool interior = true;
    for (unsigned int d = 0; d < 3; ++d)
    {
      const double lo = d < 2 ? -0.01 : 0.0, hi = d < 2 ? 0.01 : 0.02;
      interior = interior && x0[3 * v + d] > lo + 1e-9 && x0[3 * v + d] < hi - 1e-9;
      resultant[d] += f[3 * v + d];
    }
    if (interior)
    {
      ++n_interior;
      for (unsigned int d = 0; d < 3; ++d)
        EXPECT_LT(std::abs(f[3 * v + d]), 1e-9 * scale); // round-off only
    }
  }
  EXPECT_EQ(n_interior, 27u);
  for (unsigned int d = 0; d < 3; ++d)
    EXPECT_LT(std::abs(resultant[d]), 1e-9 * scale);
}

TEST(FemTimeStep, PowerIterationMatchesDenseEigenvalue)
{
  // lambda_max(M^-1 K) of a 2x2x2 mesh (81 dofs) from a dense symmetric eigen-solve
  fem::Parameters prm;
  prm.element_size = 0.005;
  const fem::SteelBody platen(box_geometry(0.01, 0.01, 0.01, 0.0, fem::BodySide::above), prm);
  const std::size_t n = 3 * platen.n_nodes();
  ASSERT_EQ(n, 81u);
  const auto m = platen.nodal_masses();
  Eigen::MatrixXd A(n, n);
  for (std::size_t j = 0; j < n; ++j)
  {
    std::vector<double> e(n, 0.0);
    e[j]         = 1.0;
    const auto k = platen.internal_force(e);
    for (std::size_t i = 0; i < n; ++i)
      A(i, j) = k[i] / std::sqrt(m[i / 3] * m[j / 3]);
  }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(A);
  const double lambda_dense = eig.eigenvalues().maxCoeff();
  // the estimate is Rayleigh quotient + residual norm with residual < 1e-4 of it: an upper
  // bound within about 2e-4; 1e-3 leaves room for a cluster of top eigenvalues
  EXPECT_GE(platen.max_eigenvalue(), lambda_dense * (1.0 - 1e-9));
  EXPECT_LT(platen.max_eigenvalue(), lambda_dense * (1.0 + 1e-3));
  EXPECT_NEAR(platen.stable_time_step(),
              prm.time_step_safety * 2.0 / std::sqrt(platen.max_eigenvalue()),
              1e-12 * platen.stable_time_step());
}

TEST(FemTimeStep, DampingShortensTheStableStep)
{
  fem::Parameters prm;
  prm.element_size = 0.005;
  const auto g     = box_geometry(0.02, 0.02, 0.01, 0.0, fem::BodySide::above);
  const fem::SteelBody undamped(g, prm);
  const double omega    = std::sqrt(undamped.max_eigenvalue());
  prm.stiffness_damping = 0.2 / omega; // xi = 0.1 at the highest mode
  const fem::SteelBody damped(g, prm);
  const double expected = undamped.stable_time_step() * (std::sqrt(1.0 + 0.01) - 0.1);
  EXPECT_NEAR(damped.stable_time_step() / expected, 1.0, 1e-9); // same lambda, closed form
}

TEST(FemRigid, ReactionBalancesContactForcesAndEnergyCloses)
{
  fem::Parameters prm;
  prm.model        = fem::SteelModel::rigid;
  prm.element_size = 0.005;
  fem::SteelBody platen(cylinder_geometry(0.05, 0.02, 0.1, fem::BodySide::above), prm);
  EXPECT_TRUE(std::isinf(platen.stable_time_step()));
  EXPECT_DOUBLE_EQ(platen.strain_energy(), 0.0);

  const double v0 = -0.05, t_ramp = 1e-3, dt = 1e-5, F = 2000.0; // F: rock pushes up [N]
  platen.set_loaded_face_velocity([&](double t) { return v0 * ramp(t, t_ramp); });
  const std::size_t nc = platen.n_contact_nodes();
  const auto z0        = platen.contact_positions();
  double t             = 0.0;
  for (int n = 0; n < 200; ++n, t += dt)
  {
    std::vector<double> f(3 * nc, 0.0);
    for (std::size_t i = 0; i < nc; ++i)
      f[3 * i + 2] = F / nc;
    platen.add_contact_forces(f);
    platen.step(t, dt);
  }
  // after the ramp the body moves uniformly: the frame holds exactly the contact force
  // (inertia M a is zero at constant velocity; the rest is round-off of a 2000 N sum)
  EXPECT_NEAR(platen.reaction_force(), -F, 1e-9 * F);
  EXPECT_NEAR(platen.compressive_force(), F, 1e-9 * F);

  // every contact node moved by the integral of the ramped velocity: v0 (t - t_ramp / 2)
  const auto z = platen.contact_positions();
  for (std::size_t i = 0; i < nc; ++i)
    EXPECT_NEAR(z[3 * i + 2] - z0[3 * i + 2], v0 * (t - 0.5 * t_ramp), 1e-3 * std::abs(v0) * t);
  // 1e-3: the midpoint rule of the cosine ramp errs by O(dt^2 / t_ramp^2) = 1e-4 of it

  // kinetic energy = frame work + contact work; the discrete sum is second order in
  // dt / t_ramp = 1e-2, so 1e-3 of the kinetic energy is a fair bound
  const double ke = platen.kinetic_energy();
  EXPECT_NEAR(ke, 0.5 * platen.total_mass() * v0 * v0, 1e-12 * ke);
  EXPECT_NEAR(platen.external_work(), ke, 1e-3 * ke);
}

TEST(FemApi, RejectsBadInput)
{
  fem::Parameters prm;
  prm.element_size = -1.0;
  EXPECT_THROW(fem::SteelBody(fem::BodyGeometry(), prm), std::invalid_argument);
  prm.element_size   = 0.01;
  prm.poissons_ratio = 0.5;
  EXPECT_THROW(fem::SteelBody(fem::BodyGeometry(), prm), std::invalid_argument);
  prm.poissons_ratio = 0.3;
  fem::SteelBody platen(fem::BodyGeometry(), prm);
  EXPECT_THROW(platen.add_contact_forces(std::vector<double>(5, 0.0)), std::invalid_argument);
  EXPECT_THROW(platen.step(0.0, 0.0), std::invalid_argument);
}

TEST(FemOutput, SnapshotUsesVtkHexahedraWithPositiveVolume)
{
  fem::Parameters prm;
  prm.element_size = 0.01;
  const fem::SteelBody platen(cylinder_geometry(0.05, 0.02, 0.0, fem::BodySide::above), prm);
  const auto s = platen.mesh_snapshot();
  ASSERT_EQ(s.n_cells(), platen.n_cells());
  ASSERT_EQ(s.n_vertices(), platen.n_nodes());
  // VTK order: 0-1-2-3 counter-clockwise seen from 4-5-6-7's side, so the corner tetrahedron
  // (0, 1, 3, 4) has a positive volume for every cell
  for (std::size_t c = 0; c < s.n_cells(); ++c)
  {
    auto p = [&](unsigned int k, unsigned int d) {
      return s.position[3 * s.hexahedra[8 * c + k] + d];
    };
    double a[3], b[3], e[3];
    for (unsigned int d = 0; d < 3; ++d)
    {
      a[d] = p(1, d) - p(0, d);
      b[d] = p(3, d) - p(0, d);
      e[d] = p(4, d) - p(0, d);
    }
    const double vol = a[0] * (b[1] * e[2] - b[2] * e[1]) - a[1] * (b[0] * e[2] - b[2] * e[0]) +
                       a[2] * (b[0] * e[1] - b[1] * e[0]);
    EXPECT_GT(vol, 0.0) << "cell " << c;
  }
  const std::string file = std::string(COSIM_BINARY_DIR) + "/fem_snapshot_test.vtu";
  EXPECT_NO_THROW(platen.write_vtu(file));
  EXPECT_THROW(platen.write_vtu("/nonexistent-folder/x.vtu"), std::runtime_error);
}

TEST(FemMesh, JawContactFaceFollowsItsArc)
{
  // ISRM jaw for a 50 mm disc: arc radius 1.5 x 25 mm, 30 mm wide, top jaw touching at z = 0.05
  fem::BodyGeometry g;
  g.shape      = fem::BodyShape::jaw;
  g.size_x     = 0.03;
  g.size_y     = 0.03;
  g.thickness  = 0.02;
  g.jaw_radius = 0.0375;
  g.contact_z  = 0.05;
  g.side       = fem::BodySide::above;
  fem::Parameters prm;
  prm.element_size = 0.0025;
  const fem::SteelBody jaw(g, prm);
  // the jaw is concave, it cradles the disc: every contact node lies on the arc
  // z = contact_z - (R - sqrt(R^2 - x^2)), bending down towards the disc away from the apex; the
  // transform places them there exactly, so only round-off remains
  const auto x = jaw.contact_positions();
  ASSERT_GT(x.size(), 3u * 20);
  for (std::size_t i = 0; i < x.size(); i += 3)
  {
    const double R = g.jaw_radius;
    EXPECT_NEAR(x[i + 2], g.contact_z - (R - std::sqrt(R * R - x[i] * x[i])), 1e-12);
  }
  // volume: the box plus the region between the flat face and the arc, swept along y; the mesh
  // chords the arc: 1e-3 covers the chord error at 2.5 mm cells
  const double a = 0.5 * g.size_x, R = g.jaw_radius;
  const double bend_area = 2.0 * a * R - (a * std::sqrt(R * R - a * a) + R * R * std::asin(a / R));
  const double V         = g.size_x * g.size_y * g.thickness + bend_area * g.size_y;
  EXPECT_NEAR(jaw.mesh_volume() / V, 1.0, 1e-3);
  // and the lumped mass keeps the mesh's mass exactly (round-off)
  EXPECT_NEAR(jaw.total_mass() / (prm.density * jaw.mesh_volume()), 1.0, 1e-10);
  // the contact normals still point out of the jaw, towards the rock (down)
  EXPECT_LT(jaw.contact_normal_z(), 0.0);
}

TEST(FemCoupling, ContactFreeAccelerationIsWhatTheNextStepAddsToTheVelocity)
{
  // the acceleration a constraint contact predicts the face with must be the one the body's own
  // step applies: after a step of dt (so that the next one's mid-step interval is dt), a strained
  // and moving platen with stiffness damping, stepped once more without contact forces, changes
  // its contact-node velocities by dt times contact_free_accelerations(). Round-off only.
  fem::Parameters prm;
  prm.model             = fem::SteelModel::elastic;
  prm.element_size      = 0.006;
  prm.stiffness_damping = 1e-8;
  fem::SteelBody platen(cylinder_geometry(0.05, 0.02, 0.0, fem::BodySide::below), prm);
  const auto x0       = platen.reference_positions();
  const std::size_t n = x0.size();
  std::vector<double> u(n), v(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    const double x = x0[3 * (i / 3)], y = x0[3 * (i / 3) + 1], z = x0[3 * (i / 3) + 2];
    u[i] = 1e-6 * (std::sin(40 * x + i % 3) + y * z * 1e3);
    v[i] = 1e-3 * std::cos(30 * y - i % 3);
  }
  platen.set_state(u, v);
  const double dt = 0.5 * platen.stable_time_step();
  platen.step(0.0, dt);
  const std::vector<double> a = platen.contact_free_accelerations(), v0 = platen.contact_velocities();
  platen.step(dt, dt);
  const std::vector<double> v1 = platen.contact_velocities();
  ASSERT_GT(max_abs(a), 0.0) << "the state must load the contact nodes";
  double worst = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    worst = std::max(worst, std::abs((v1[i] - v0[i]) / dt - a[i]));
  EXPECT_LT(worst, 1e-9 * max_abs(a));
}
