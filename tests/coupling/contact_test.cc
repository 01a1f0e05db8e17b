// Unit tests of the penalty contact between rock particles and a platen surface.
#include "../../coupling/src/driver_common.h"

#include <coupling/contact.h>
#include <coupling/curve_analysis.h>

#include <fem/steel_body.h>

#include <gtest/gtest.h>

#include <omp.h>

#include <array>
#include <cmath>

using namespace coupling;

namespace
{
  /// A flat square surface z = z0 of n x n quads over [0, L]^2, normal +z (towards the rock).
  ContactSurface flat_surface(int n, double L, double z0, double node_mass)
  {
    ContactSurface s;
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i)
      {
        s.position.insert(s.position.end(), {L * i / n, L * j / n, z0});
        s.velocity.insert(s.velocity.end(), {0, 0, 0});
        s.mass.push_back(node_mass);
      }
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
      {
        const unsigned a = j * (n + 1) + i;
        s.faces.push_back({{a, a + 1, a + n + 2, a + n + 1}}); // counter-clockwise seen from +z
      }
    return s;
  }

  /// n x n particles of 2 g, positions and velocities from the functions of the indices (i, j).
  struct Patch
  {
    std::vector<double> x, v, m;
    ContactParticles particles() const { return {x.data(), v.data(), m.data(), m.size()}; }
  };
  template <typename Position, typename Velocity>
  Patch particle_patch(const int n, const Position &position, const Velocity &velocity)
  {
    Patch p;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
      {
        const std::array<double, 3> xp = position(i, j), vp = velocity(i, j);
        p.x.insert(p.x.end(), xp.begin(), xp.end());
        p.v.insert(p.v.end(), vp.begin(), vp.end());
        p.m.push_back(2e-3);
      }
    return p;
  }

  /// The penalty contact of the exchange tests: k = 1e7 N/m, r = 1 mm, friction 0.3.
  ContactParameters frictional_contact()
  {
    ContactParameters prm;
    prm.stiffness       = 1e7;
    prm.radius          = 1e-3;
    prm.friction_static = prm.friction_dynamic = 0.3;
    return prm;
  }

  double sum_norm(const std::vector<double> &f)
  {
    double s = 0;
    for (std::size_t i = 0; i < f.size(); i += 3)
      s += std::sqrt(f[i] * f[i] + f[i + 1] * f[i + 1] + f[i + 2] * f[i + 2]);
    return s;
  }
} // namespace

TEST(ContactExchange, ForcesCancelToRoundOff)
{
  const ContactSurface s = flat_surface(4, 0.04, 0.0, 0.1);
  // a 7 x 7 patch of particles, some penetrating, some sliding sideways
  const Patch patch = particle_patch(
    7,
    [](int i, int j) {
      return std::array<double, 3>{{0.003 + 0.0055 * i, 0.002 + 0.0057 * j,
                                    0.0008 + 1e-5 * ((i * 7 + j) % 5)}};
    },
    [](int i, int j) { return std::array<double, 3>{{0.1 * i, -0.05 * j, -0.01}}; });
  const ContactParticles p = patch.particles();
  PenaltyContact contact(frictional_contact(), p.n);
  std::vector<double> fp(patch.x.size(), 0.0), fn(s.position.size(), 0.0);
  const std::size_t n_in = contact.apply(p, s, 1e-7, fp, fn);
  ASSERT_GT(n_in, 10u) << "the fixture must be in contact, or the test proves nothing";
  const double scale = sum_norm(fp);
  ASSERT_GT(scale, 0.0);
  // each contact force is applied once to the particle and once, split by weights summing to one,
  // to the nodes: only round-off (a few ulps per term) may remain
  for (int d = 0; d < 3; ++d)
  {
    double total = 0;
    for (std::size_t i = d; i < fp.size(); i += 3)
      total += fp[i];
    for (std::size_t i = d; i < fn.size(); i += 3)
      total += fn[i];
    EXPECT_LT(std::abs(total), 1e-12 * scale) << "component " << d;
  }
}

TEST(ContactExchange, FacesNotNodesCatchParticles)
{
  // one coarse face 10 mm wide; a particle over its middle, far from every node, must be held
  const ContactSurface s = flat_surface(1, 0.01, 0.0, 1.0);
  std::vector<double> x{0.005, 0.005, 0.0004}, v{0, 0, 0}, m{1e-3};
  ContactParameters prm;
  prm.stiffness = 1e6;
  prm.radius    = 5e-4;
  PenaltyContact contact(prm, 1);
  std::vector<double> fp(3, 0.0), fn(12, 0.0);
  ASSERT_EQ(contact.apply({x.data(), v.data(), m.data(), 1}, s, 1e-7, fp, fn), 1u);
  // penetration 0.1 mm at k = 1e6 N/m: 100 N straight up (exact for a flat face, up to round-off)
  EXPECT_NEAR(fp[2], 100.0, 1e-9);
  EXPECT_NEAR(fp[0], 0.0, 1e-12);
  // the reaction is shared equally by the four corner nodes of the face
  for (int a = 0; a < 4; ++a)
    EXPECT_NEAR(fn[3 * a + 2], -25.0, 1e-9);
}

TEST(ContactFriction, SlidesWhenTangentialForceReachesMuN)
{
  // A particle pressed with N onto a rigid face; a tangential pull T grows slowly. It must stay
  // stuck until T = mu_s N and slide from there on.
  const double mu = 0.3, N = 50.0, mass = 1e-3, k = 1e6, r = 5e-4;
  const ContactSurface s = flat_surface(2, 0.02, 0.0, 0.0);
  ContactParameters prm;
  prm.stiffness       = k;
  prm.radius          = r;
  prm.friction_static = prm.friction_dynamic = mu;
  PenaltyContact contact(prm, 1);
  std::vector<double> x{0.01, 0.01, r - N / k}, v{0, 0, 0}, m{mass};
  // dt well inside the stable bound 2 sqrt(m/k) = 6.3e-5 s
  // T grows slowly: the stuck particle follows the pull with a tangential oscillation of force
  // amplitude rate * sqrt(m / k) = 0.06 N (0.4 % of mu N), so the onset is not triggered early
  const double dt = 2e-6, rate = 2e3;
  double T_slip = -1;
  // critical damping of the normal bounce so that N is steady: c = 2 sqrt(k m)
  const double c = 2 * std::sqrt(k * mass);
  for (int step = 0; step < 200000 && T_slip < 0; ++step)
  {
    const double T = rate * step * dt;
    std::vector<double> fp(3, 0.0), fn(s.position.size(), 0.0);
    contact.apply({x.data(), v.data(), m.data(), 1}, s, dt, fp, fn);
    if (contact.n_sliding() > 0)
      T_slip = T;
    const double a[3] = {(fp[0] + T) / mass, fp[1] / mass, (fp[2] - N - c * v[2]) / mass};
    for (int d = 0; d < 3; ++d)
    {
      v[d] += dt * a[d];
      x[d] += dt * v[d];
    }
  }
  ASSERT_GT(T_slip, 0.0) << "the particle never slid";
  // 2 %: the target's tolerance; the tangential oscillation (0.4 % of mu N) and the normal
  // force's settling are the error sources
  EXPECT_NEAR(T_slip, mu * N, 0.02 * mu * N);
}

namespace
{
  /// One particle pressed onto a rigid face by N and pulled sideways by T, stepped with the
  /// body's symplectic Euler update and the kinematic contact; returns the contact's last force
  /// on the particle and whether it slid at the end.
  struct BlockResult
  {
    std::array<double, 3> force;
    double drift; ///< tangential displacement over the last half of the steps [m]
    bool sliding;
  };
  BlockResult press_and_pull(const ContactParameters &prm, double N, double T, int steps)
  {
    // heavy enough that a sliding block stays on the 20 mm face over the steps
    const double mass = 1.0, dt = 1e-6;
    const ContactSurface s = flat_surface(2, 0.02, 0.0, 0.0);
    PenaltyContact contact(prm, 1);
    std::vector<double> x{0.01, 0.01, prm.radius}, v{0, 0, 0}, m{mass};
    BlockResult r{};
    double x_half = 0;
    for (int step = 0; step < steps; ++step)
    {
      const std::vector<double> f{T, 0.0, -N};
      std::vector<double> fp(3, 0.0), fn(s.position.size(), 0.0);
      ContactParticles particles{x.data(), v.data(), m.data(), 1};
      particles.force = f.data();
      contact.apply(particles, s, dt, fp, fn);
      for (int d = 0; d < 3; ++d)
      {
        v[d] += dt * (f[d] + fp[d]) / mass;
        x[d] += dt * v[d];
        r.force[d] = fp[d];
      }
      if (step == steps / 2)
        x_half = x[0];
      r.sliding = contact.n_sliding() > 0;
    }
    r.drift = x[0] - x_half;
    // the constraint holds the particle exactly on the face (round-off of the coordinates)
    EXPECT_NEAR(x[2], prm.radius, 1e-15) << "kinematic contact leaves no penetration";
    return r;
  }
} // namespace

TEST(ContactKinematic, HoldsThePressedParticleOnTheFaceWithNoStiffness)
{
  ContactParameters prm;
  prm.method = ContactMethod::kinematic;
  prm.radius = 5e-4;
  const BlockResult r = press_and_pull(prm, 50.0, 0.0, 1000);
  // the normal force balances the load exactly (no spring, no bounce): round-off
  EXPECT_NEAR(r.force[2], 50.0, 1e-9);
  EXPECT_NEAR(r.force[0], 0.0, 1e-12);
}

TEST(ContactKinematic, CoulombStickBelowMuNAndSlideAtMuDynamicN)
{
  // the block-on-a-platen check: stuck below mu_s N, sliding against exactly mu_d N above it
  ContactParameters prm;
  prm.method           = ContactMethod::kinematic;
  prm.radius           = 5e-4;
  prm.friction_static  = 0.3;
  prm.friction_dynamic = 0.25;
  const double N       = 50.0;
  const BlockResult stuck = press_and_pull(prm, N, 0.99 * 0.3 * N, 10000);
  EXPECT_FALSE(stuck.sliding);
  EXPECT_NEAR(stuck.force[0], -0.99 * 0.3 * N, 1e-9); // stick: the pull balanced exactly
  EXPECT_EQ(stuck.drift, 0.0);
  const BlockResult slid = press_and_pull(prm, N, 1.01 * 0.3 * N, 10000);
  EXPECT_TRUE(slid.sliding);
  // slip: the dynamic force, stable over 10^4 steps (round-off)
  EXPECT_NEAR(slid.force[0], -0.25 * N, 1e-9);
  EXPECT_GT(slid.drift, 0.0);
}

TEST(ContactKinematic, BondedHoldsTensionAndShear)
{
  ContactParameters prm;
  prm.method = ContactMethod::kinematic;
  prm.radius = 5e-4;
  prm.bonded = true;
  // pulled away from the face and sideways: a bond holds both exactly
  const BlockResult r = press_and_pull(prm, -20.0, 30.0, 1000);
  EXPECT_NEAR(r.force[2], -20.0, 1e-9);
  EXPECT_NEAR(r.force[0], -30.0, 1e-9);
  EXPECT_EQ(r.drift, 0.0);
}

TEST(ContactKinematic, ForcesOnADeformableFaceCancelAndPushEveryParticleOut)
{
  // a patch of particles moving into a face of nodes with mass: each pair force applied once to
  // each side (momentum exact to round-off of the sums), every approaching particle pushed back
  const ContactSurface s = flat_surface(4, 0.04, 0.0, 0.1);
  ContactParameters prm;
  prm.method = ContactMethod::kinematic;
  prm.radius = 5e-4;
  const Patch p = particle_patch(
    6, [](int i, int j) { return std::array<double, 3>{{0.005 + 0.006 * i, 0.004 + 0.0065 * j, 4.9e-4}}; },
    [](int, int) { return std::array<double, 3>{{0.01, -0.02, -0.5}}; });
  PenaltyContact contact(prm, p.m.size());
  std::vector<double> fp(p.x.size(), 0.0), fn(s.position.size(), 0.0);
  const double dt = 1e-6;
  EXPECT_EQ(contact.apply(p.particles(), s, dt, fp, fn), p.m.size());
  double total[3] = {0, 0, 0}, scale = 0;
  for (std::size_t i = 0; i < fp.size(); ++i)
    total[i % 3] += fp[i], scale += std::abs(fp[i]);
  for (std::size_t i = 0; i < fn.size(); ++i)
    total[i % 3] += fn[i];
  for (int d = 0; d < 3; ++d)
    EXPECT_LT(std::abs(total[d]), 1e-14 * scale) << d;
  // every particle is stopped in the normal direction, none pulled (no bond)
  for (std::size_t i = 0; i < p.m.size(); ++i)
    EXPECT_GT(fp[3 * i + 2], 0.0);
}

TEST(ContactKinematic, ContactsSharingNodesEndTheStepExactlyOnTheDeformedFace)
{
  // 36 particles of 2 g move into a face whose nodes weigh as much as a particle: each node is
  // pushed by up to four particles, so a particle corrected alone against its node masses would
  // leave the others' pushes out. The contacts solved together end the step (the particles'
  // symplectic Euler step, the nodes' step under the reactions) at the contact radius from the
  // moved face, every one of them: 1e-6 of the radius, the sweeps' stopping rule.
  const double node_mass = 2e-3, dt = 1e-6, r = 5e-4;
  const int n_quads      = 4;
  const double L         = 0.04;
  const ContactSurface s = flat_surface(n_quads, L, 0.0, node_mass);
  ContactParameters prm;
  prm.method = ContactMethod::kinematic;
  prm.radius = r;
  const Patch p = particle_patch(
    6, [](int i, int j) { return std::array<double, 3>{{0.005 + 0.006 * i, 0.004 + 0.0065 * j, 4.9e-4}}; },
    [](int i, int) { return std::array<double, 3>{{0.0, 0.0, -0.5 - 0.1 * i}}; });
  PenaltyContact contact(prm, p.m.size());
  std::vector<double> fp(p.x.size(), 0.0), fn(s.position.size(), 0.0);
  ASSERT_EQ(contact.apply(p.particles(), s, dt, fp, fn), p.m.size());
  // the step of both sides
  std::vector<double> node_z(s.n_nodes());
  for (std::size_t a = 0; a < s.n_nodes(); ++a)
    node_z[a] = s.position[3 * a + 2] + dt * (s.velocity[3 * a + 2] + dt * fn[3 * a + 2] / node_mass);
  const double h = L / n_quads;
  double worst   = 0;
  for (std::size_t k = 0; k < p.m.size(); ++k)
  {
    double x[3];
    for (int d = 0; d < 3; ++d)
      x[d] = p.x[3 * k + d] + dt * (p.v[3 * k + d] + dt * fp[3 * k + d] / p.m[k]);
    // the moved face under the particle: bilinear in the quad that holds it
    const int i = static_cast<int>(x[0] / h), j = static_cast<int>(x[1] / h);
    const double u = x[0] / h - i, w = x[1] / h - j;
    const unsigned a = j * (n_quads + 1) + i;
    const double z_face = (1 - u) * (1 - w) * node_z[a] + u * (1 - w) * node_z[a + 1] +
                          u * w * node_z[a + n_quads + 2] + (1 - u) * w * node_z[a + n_quads + 1];
    worst = std::max(worst, std::abs(x[2] - z_face - r));
  }
  EXPECT_LT(worst, 1e-6 * r);
}

TEST(ContactEnergy, ElasticBounceKeepsEnergy)
{
  // A particle dropped on a rigid face at k = 0.5 of the stability bound bounces back with its
  // speed: the penalty is elastic and the central-difference error is second order in dt.
  const double mass = 1e-3, r = 5e-4, v0 = 1.0, dt = 1e-6;
  const double k         = 0.5 * stable_contact_stiffness(mass, 0.0, dt);
  const ContactSurface s = flat_surface(1, 0.01, 0.0, 0.0);
  ContactParameters prm;
  prm.stiffness = k;
  prm.radius    = r;
  PenaltyContact contact(prm, 1);
  std::vector<double> x{0.005, 0.005, r + 1e-6}, v{0, 0, -v0}, m{mass};
  for (int step = 0; step < 2000 && !(v[2] > 0 && x[2] > r); ++step)
  {
    std::vector<double> fp(3, 0.0), fn(12, 0.0);
    contact.apply({x.data(), v.data(), m.data(), 1}, s, dt, fp, fn);
    v[2] += dt * fp[2] / mass;
    x[2] += dt * v[2];
  }
  // 1 %: the symplectic step keeps a shadow energy; with about 4 steps per contact at this
  // stiffness the exit speed differs from v0 by the discrete-time phase error, under 1 %
  EXPECT_NEAR(v[2], v0, 0.01 * v0);
}

TEST(CurveAnalysis, SecantModulusOfABilinearCurve)
{
  // linear to the peak at slope 50 GPa, then falling: the secant 40-60 % is the slope, exactly
  std::vector<double> strain, stress;
  for (int i = 0; i <= 100; ++i)
  {
    strain.push_back(1e-5 * i);
    stress.push_back(i <= 60 ? 50e9 * 1e-5 * i : 50e9 * 1e-5 * (120 - i));
  }
  EXPECT_NEAR(secant_modulus(strain, stress), 50e9, 1e-6 * 50e9); // interpolation is exact here
  std::vector<double> lateral;
  for (double e : strain)
    lateral.push_back(-0.25 * e);
  EXPECT_NEAR(secant_poissons_ratio(strain, lateral, stress), 0.25, 1e-9);
  // a curve that never rises gives no modulus
  EXPECT_NEAR(secant_modulus(strain, std::vector<double>(101, 0.0)), 0.0, 0.0);
}

namespace
{
  /// A 90-degree wedge above the rock, apex line along y at x = 0, z = 0: two flank faces
  /// z = |x| for |x| <= a, y in [0, W], normals pointing down and out (towards the rock).
  ContactSurface wedge_surface(double a, double W)
  {
    ContactSurface s;
    const double nodes[6][3] = {{-a, 0, a}, {-a, W, a}, {0, W, 0}, {0, 0, 0}, {a, W, a}, {a, 0, a}};
    for (const auto &p : nodes)
    {
      s.position.insert(s.position.end(), {p[0], p[1], p[2]});
      s.velocity.insert(s.velocity.end(), {0, 0, 0});
      s.mass.push_back(0.0);
    }
    s.faces.push_back({{0, 1, 2, 3}}); // left flank, normal (-1, 0, -1)/sqrt(2)
    s.faces.push_back({{3, 2, 4, 5}}); // right flank, normal (1, 0, -1)/sqrt(2)
    return s;
  }

  /// Penalty energy of one particle at (x, y, z) against `s`.
  double energy_at(const ContactSurface &s, const ContactParameters &prm, double x, double y,
                   double z, std::vector<double> *force = nullptr)
  {
    const double pos[3] = {x, y, z}, vel[3] = {0, 0, 0}, mass = 1e-3;
    ContactParticles p{pos, vel, &mass, 1};
    PenaltyContact contact(prm, 1);
    std::vector<double> fp(3, 0.0), fn(3 * s.n_nodes(), 0.0);
    contact.apply(p, s, 1e-7, fp, fn);
    if (force)
      *force = fp;
    return contact.penalty_energy();
  }
} // namespace

TEST(ContactConvexApex, NoGapBelowASharpWedge)
{
  // A particle straight below a convex apex projects onto neither flank (it lies in the wedge
  // between the flanks' normals). Before the fix it felt nothing until the apex passed its
  // centre, then the full penalty at once: energy from nothing, the sharp-indenter instability.
  // The signed distance to a convex body is the largest of its face-plane distances,
  // d = (|x| - z)/sqrt(2) here, so the penalty energy is 0.5 k (r - d)^2 wherever d < r.
  const double r = 1e-3, a = 0.01, W = 0.01;
  const ContactSurface s = wedge_surface(a, W);
  ContactParameters prm;
  prm.stiffness     = 1e7;
  prm.radius        = r;
  prm.convex_master = true;
  const double x    = 0.2 * r;
  double previous   = 0, largest_jump = 0;
  for (int k = 0; k <= 400; ++k)
  {
    const double z        = -2.0 * r + k * (1.5 * r / 400); // from clear below up to -0.5 r
    const double d        = (std::abs(x) - z) / std::sqrt(2.0);
    const double expected = d < r ? 0.5 * prm.stiffness * (r - d) * (r - d) : 0.0;
    const double e        = energy_at(s, prm, x, 0.5 * W, z);
    // 1e-9 relative: round-off of the Newton projection onto a flat face
    EXPECT_NEAR(e, expected, 1e-9 * 0.5 * prm.stiffness * r * r) << "z/r = " << z / r;
    largest_jump = std::max(largest_jump, std::abs(e - previous));
    previous     = e;
  }
  // continuous: no step larger than the change of 0.5 k (r - d)^2 over one sample, which is
  // at most k r (dz / sqrt 2) with dz = 1.5 r / 400 (the old rule jumped by 0.5 k (0.8 r)^2 / 2)
  EXPECT_LT(largest_jump, prm.stiffness * r * (1.5 * r / 400));
  // at z = -0.5 r the particle (x = 0.2 r) is inside the normals' wedge: it must be pushed away
  // from the apex, down and towards +x (the nearer flank, x > 0)
  std::vector<double> f;
  energy_at(s, prm, x, 0.5 * W, -0.5 * r, &f);
  EXPECT_GT(f[0], 0.0);
  EXPECT_LT(f[2], 0.0);
  EXPECT_NEAR(f[0], -f[2], 1e-9 * std::abs(f[2])); // along the flank normal (1, 0, -1)/sqrt 2
}

TEST(ContactConvexApex, NoContactPastTheSurfacesOuterEdge)
{
  // past the wedge's outer edge (x = a, an edge of one face only) the flank's plane does not
  // extend: the particle lies beside the cutter, not under it
  const double r = 1e-3, a = 0.01, W = 0.01;
  const ContactSurface s = wedge_surface(a, W);
  ContactParameters prm;
  prm.stiffness     = 1e7;
  prm.radius        = r;
  prm.convex_master = true;
  // (x - z)/sqrt(2) = 0.49 r < r: in contact if the plane were extended
  EXPECT_EQ(energy_at(s, prm, a + 0.5 * r, 0.5 * W, a - 0.2 * r), 0.0);
  // and just inside the edge it is in contact
  EXPECT_GT(energy_at(s, prm, a - 0.5 * r, 0.5 * W, a - 1.2 * r), 0.0);
}

TEST(ContactRidge, AParticleOverAWarpedPlatensRidgeKeepsItsContact)
{
  // A platen face (flat master, normal +z towards the rock) warped into a shallow ridge along
  // y at x = 0: z = -s |x|, s = 0.02 (a loaded elastic platen's quads warp by far less; the slope
  // only sets how far off the crease the closest points fall: about r s). A particle above the
  // crease projects onto neither face; before the fix it felt no force (a UCS particle over such
  // a mesh vertex of an elastic platen then lost its contact and failed in tension at 6 % of
  // the strength). It must be pushed along a face normal by k (r - d), d = z / sqrt(1 + s^2)
  // its distance to the face planes through the crease, and the force must not vanish anywhere
  // across the crease.
  const double r = 1e-3, a = 0.01, W = 0.01, s = 0.02;
  ContactSurface m;
  const double nodes[6][3] = {{-a, 0, -s * a}, {0, 0, 0}, {0, W, 0}, {-a, W, -s * a},
                              {a, 0, -s * a},  {a, W, -s * a}};
  for (const auto &p : nodes)
  {
    m.position.insert(m.position.end(), {p[0], p[1], p[2]});
    m.velocity.insert(m.velocity.end(), {0, 0, 0});
    m.mass.push_back(0.0);
  }
  m.faces.push_back({{0, 1, 2, 3}}); // left flank, normal (s, 0, 1)/sqrt(1 + s^2)
  m.faces.push_back({{1, 4, 5, 2}}); // right flank, normal (-s, 0, 1)/sqrt(1 + s^2)
  ContactParameters prm;
  prm.stiffness = 1e7;
  prm.radius    = r;
  const double z = 0.9 * r; // 0.1 r of penetration
  std::vector<double> f;
  energy_at(m, prm, 0.0, 0.5 * W, z, &f);
  const double expected = prm.stiffness * (r - z / std::sqrt(1 + s * s));
  // 1e-9 relative: round-off of the Newton projection onto a flat face
  EXPECT_NEAR(std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]), expected, 1e-9 * expected);
  EXPECT_GT(f[2], 0.0);
  // across the crease the force never vanishes and follows the distance to the ridge,
  // (z + s |x|) / sqrt(1 + s^2) (the largest plane distance of a convex crease): within 1 % of
  // the penetration, since over the crease (|x| < r s) the fallback takes the nearer plane, off
  // by at most 2 s |x| < 2 r s^2 = 0.08 % of r, 0.8 % of this penetration
  for (int k = -50; k <= 50; ++k)
  {
    const double x           = k * 0.01 * r;
    const double penetration = r - (z + s * std::abs(x)) / std::sqrt(1 + s * s);
    energy_at(m, prm, x, 0.5 * W, z, &f);
    EXPECT_NEAR(std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]), prm.stiffness * penetration,
                0.01 * prm.stiffness * penetration)
      << "x/r = " << x / r;
  }
}

TEST(ContactConvexApex, NoContactFarFromAWarpedConeMesh)
{
  // The indentation cone as the driver builds it: 90 degrees, 16 mm base, meshed at 1.5 mm, so its
  // flank is bilinear quads whose corners lie on the cone but which are warped (corners at
  // different radii). The closest-point iteration does not converge onto such a quad for a
  // particle far from it and could stop inside it with a plane distance that said "penetrated":
  // with the apex 2.04 mm below the rock's top, particles of the top layer 3 mm from the flank
  // took 0.8 mm of penalty penetration from a face on the far side of the axis (170 J from
  // nothing; cases/indentation/README.md). The quads' corners lie on the cone and a convex body
  // holds its chords, so the mesh lies inside the ideal cone: a particle more than its diameter
  // 2 r clear of the ideal cone is more than 2 r from every face and must feel nothing.
  fem::BodyGeometry g;
  g.shape          = fem::BodyShape::cone;
  g.side           = fem::BodySide::above;
  g.diameter       = 0.016;
  g.tip_half_angle = 0.25 * 3.14159265358979323846;
  g.thickness      = 0.0128;
  g.center_x       = 0.0;
  g.center_y       = 0.0;
  const double apex = -2.04e-3;
  g.contact_z       = apex;
  fem::Parameters fp;
  fp.model        = fem::SteelModel::rigid;
  fp.element_size = 1.5e-3;
  const fem::SteelBody cone(g, fp);
  const ContactSurface s = contact_surface(cone);
  ASSERT_GT(s.faces.size(), 20u);
  ContactParameters prm;
  prm.stiffness     = 6.4e7;
  prm.radius        = 0.75e-3;
  prm.convex_master = true;
  const double r    = prm.radius;

  // every particle of a lattice around the tip at once (one apply, as the driver does)
  std::vector<double> x;
  for (double pz = -3e-3; pz <= 2e-3; pz += 0.25e-3)
    for (double py = -6e-3; py <= 6e-3; py += 0.25e-3)
      for (double px = -6e-3; px <= 6e-3; px += 0.25e-3)
        x.insert(x.end(), {px, py, pz});
  const std::size_t n = x.size() / 3;
  const std::vector<double> v(3 * n, 0.0), m(n, 1e-5);
  PenaltyContact contact(prm, n);
  std::vector<double> fp_(3 * n, 0.0), fn(3 * s.n_nodes(), 0.0);
  contact.apply(ContactParticles{x.data(), v.data(), m.data(), n}, s, 1e-7, fp_, fn);
  std::size_t n_far = 0, n_touching = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    // distance to the ideal cone z - apex >= rho in the meridian plane: to the flank where the
    // foot of the perpendicular lies on it, else to the apex
    const double rho = std::hypot(x[3 * i], x[3 * i + 1]), zeta = x[3 * i + 2] - apex;
    const double foot     = 0.5 * (rho + zeta);
    const double distance = foot >= 0 ? (rho - zeta) / std::sqrt(2.0) : std::hypot(rho, zeta);
    const double f = std::hypot(fp_[3 * i], fp_[3 * i + 1], fp_[3 * i + 2]);
    if (distance > 2.0 * r)
    {
      ++n_far;
      EXPECT_EQ(f, 0.0) << "particle at (" << x[3 * i] << ", " << x[3 * i + 1] << ", "
                        << x[3 * i + 2] << ") m, " << distance / r << " r from the cone";
    }
    // well inside the penalty range of the ideal cone's flank (the mesh's chords lie within
    // 0.1 mm inside it here): in contact
    if (std::abs(distance) < 0.5 * r && foot > 1e-3 && rho < 6e-3)
    {
      ++n_touching;
      EXPECT_GT(f, 0.0) << "particle at (" << x[3 * i] << ", " << x[3 * i + 1] << ", "
                        << x[3 * i + 2] << ") m lost its contact";
    }
  }
  ASSERT_GT(n_far, 10000u);
  ASSERT_GT(n_touching, 100u) << "the lattice must reach the flank, or the test proves little";
}

TEST(ContactExchange, SameForcesForAnyThreadCount)
{
  // each thread keeps the contacts of a contiguous chunk of particles and the forces are
  // scattered chunk after chunk: the node sums get their terms in particle order whatever the
  // thread count, so the results are bitwise equal (two applies: the friction springs carry over)
  const ContactSurface s = flat_surface(6, 0.06, 0.0, 0.1);
  const Patch patch = particle_patch(
    23,
    [](int i, int j) {
      return std::array<double, 3>{{0.001 + 0.0026 * i, 0.0015 + 0.0025 * j,
                                    0.0006 + 1e-5 * ((i * 7 + j) % 11)}};
    },
    [](int i, int j) {
      return std::array<double, 3>{{0.1 * ((i % 3) - 1), -0.05 * ((j % 5) - 2), -0.01}};
    });
  const ContactParticles p = patch.particles();
  const int threads_before = omp_get_max_threads();
  std::vector<std::vector<double>> particles, nodes, scalars;
  for (const int threads : {1, 2, 3})
  {
    omp_set_num_threads(threads);
    PenaltyContact contact(frictional_contact(), p.n);
    std::vector<double> fp(patch.x.size(), 0.0), fn(s.position.size(), 0.0);
    std::size_t n_in = 0;
    for (int step = 0; step < 2; ++step)
      n_in = contact.apply(p, s, 2e-3, fp, fn); // a long step: the springs slip
    ASSERT_GT(n_in, 100u) << "the fixture must be in contact, or the test proves nothing";
    particles.push_back(fp);
    nodes.push_back(fn);
    scalars.push_back({contact.normal_force(), contact.penalty_energy(),
                       contact.friction_dissipation(), double(contact.n_sliding())});
  }
  omp_set_num_threads(threads_before);
  EXPECT_GT(scalars[0][2], 0.0) << "some particles must slide, or friction is not exercised";
  for (const std::size_t k : {1, 2})
  {
    EXPECT_EQ(particles[0], particles[k]) << k + 1 << " threads against 1";
    EXPECT_EQ(nodes[0], nodes[k]) << k + 1 << " threads against 1";
    EXPECT_EQ(scalars[0], scalars[k]) << k + 1 << " threads against 1";
  }
}

TEST(ContactKinematic, APatchSpreadsAUniformPushOverTheNodesAsAPressure)
{
  // 15 x 15 particles whose 2 mm cells tile a 30 mm face of 10 x 10 quads (3 mm: the lattice and
  // the mesh out of step) move into it alike, as a uniform pressure p would push it. Its
  // consistent nodal loads are p h^2 at an interior node. A particle's force put on the face at
  // its centre loads the nodes as the lattice happens to fall on them; spread over its patch
  // (4 x 4 points) it loads them as the pressure does, within the patch sampling's error.
  const double r = 1e-3, L = 0.03, h = 3e-3, dt = 1e-7;
  const int n_quads      = 10;
  const ContactSurface s = flat_surface(n_quads, L, 0.0, 1e3); // heavy nodes: every push alike
  const Patch p          = particle_patch(
    15, [r](int i, int j) { return std::array<double, 3>{{r * (1 + 2 * i), r * (1 + 2 * j), r}}; },
    [](int, int) { return std::array<double, 3>{{0.0, 0.0, -0.1}}; });
  auto worst_interior_error = [&](const unsigned int points) {
    ContactParameters prm;
    prm.method       = ContactMethod::kinematic;
    prm.radius       = r;
    prm.patch_points = points;
    PenaltyContact contact(prm, p.m.size());
    std::vector<double> fp(p.x.size(), 0.0), fn(s.position.size(), 0.0);
    EXPECT_EQ(contact.apply(p.particles(), s, dt, fp, fn), p.m.size());
    double total = 0, total_nodes = 0;
    for (std::size_t k = 0; k < p.m.size(); ++k)
      total += fp[3 * k + 2];
    for (std::size_t a = 0; a < s.n_nodes(); ++a)
      total_nodes += fn[3 * a + 2];
    // every pair force once on each side: 1e-12 of the total
    EXPECT_NEAR(total_nodes / total, -1.0, 1e-12);
    const double consistent = total / (L * L) * h * h;
    double worst            = 0;
    for (int j = 1; j < n_quads; ++j)
      for (int i = 1; i < n_quads; ++i)
        worst = std::max(worst, std::abs(-fn[3 * (j * (n_quads + 1) + i) + 2] / consistent - 1.0));
    return worst;
  };
  const double at_points = worst_interior_error(1), over_patches = worst_interior_error(4);
  // measured: 23.5 % at the centres; 4e-7 over the patches, whose points (0.5 mm apart, 6 to a
  // quad's side) are a midpoint rule, exact for the bilinear shape functions within a quad.
  // 1e-3: round-off and the closest-point iterations' tolerance, with margin; the centres must
  // be off by more than 10 %, or the fixture does not put the lattice out of step with the mesh
  EXPECT_LT(over_patches, 1e-3);
  EXPECT_GT(at_points, 0.1);
}

TEST(ContactKinematic, AParticlePastTheOuterEdgeIsHeldWithinTheRimReach)
{
  // A platen's mesh ends in a polygon inside its circle; a specimen as wide as the platen has
  // rim particles past it. The kinematic contact holds a particle past the outer edge by up to
  // r, or by ContactParameters::rim_reach where that is larger (the polygon's sagitta), and
  // no farther: here 1.5 r past the edge of a 10 mm face, pressed into its plane.
  const double r = 5e-4, dt = 1e-6;
  const ContactSurface s = flat_surface(1, 0.01, 0.0, 0.0);
  std::vector<double> x{0.01 + 1.5 * r, 0.005, 0.9 * r}, v{0, 0, -0.1}, m{1e-3};
  auto held = [&](const double reach) {
    ContactParameters prm;
    prm.method    = ContactMethod::kinematic;
    prm.radius    = r;
    prm.rim_reach = reach;
    PenaltyContact contact(prm, 1);
    std::vector<double> fp(3, 0.0), fn(12, 0.0);
    return contact.apply({x.data(), v.data(), m.data(), 1}, s, dt, fp, fn) == 1 && fp[2] > 0;
  };
  EXPECT_FALSE(held(0.0)); // r alone: 1.5 r is too far
  EXPECT_TRUE(held(2.0 * r));
  x[0] = 0.01 + 0.5 * r; // within r of the edge: held without a rim reach
  EXPECT_TRUE(held(0.0));
}

TEST(ContactKinematic, TheRimMapLoadsThePlatensPolygonUniformly)
{
  // A platen's mesh ends in a polygon of n rim vertices inside its circle. The map of a
  // specimen's disc onto it (map_onto_rim_polygon) must keep the vertices, put the circle on
  // the chords and the whole disc inside the polygon, and shrink every area by the same factor,
  // sin(2a) / (2a): a uniform stress on the disc then loads the polygon uniformly.
  const int n    = 16;
  const double R = 0.025, a = M_PI / n;
  ContactParameters p;
  for (int k = 0; k < n; ++k) // an arbitrary phase: the first vertex at -pi + 0.1
    p.rim_angles.push_back(-M_PI + 0.1 + 2 * a * k);
  // 1e-15 m: round-off of the angles' sines and cosines on a 25 mm radius (a few ulps)
  for (int k = 0; k < n; ++k)
  {
    double x = R * std::cos(p.rim_angles[k]), y = R * std::sin(p.rim_angles[k]);
    map_onto_rim_polygon(p, x, y);
    EXPECT_NEAR(x, R * std::cos(p.rim_angles[k]), 1e-15);
    EXPECT_NEAR(y, R * std::sin(p.rim_angles[k]), 1e-15);
    const double middle = p.rim_angles[k] + a; // the arc's middle lands on the chord's
    x = R * std::cos(middle), y = R * std::sin(middle);
    map_onto_rim_polygon(p, x, y);
    EXPECT_NEAR(std::hypot(x, y), R * std::cos(a), 1e-15);
  }
  // a fine grid over the disc: how many of its points land in each of ten angular bins of one
  // sector of the polygon, against the bins' share of the polygon's area
  std::array<double, 10> count{};
  double total = 0;
  const int m  = 1500;
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j)
    {
      double x = R * (2.0 * (i + 0.5) / m - 1), y = R * (2.0 * (j + 0.5) / m - 1);
      if (std::hypot(x, y) > R)
        continue;
      map_onto_rim_polygon(p, x, y);
      double u = std::atan2(y, x) - p.rim_angles[0];
      u -= 2 * a * std::floor(u / (2 * a)); // within its sector, 0 to 2a
      const double across = x * std::cos(std::atan2(y, x) - u + a) + y * std::sin(std::atan2(y, x) - u + a);
      // 1e-12: round-off only (a point mapped onto a chord lies on it)
      ASSERT_LE(across, R * std::cos(a) * (1 + 1e-12)) << "outside the polygon";
      count[std::min(9, int(u / (2 * a) * 10))] += 1;
      total += 1;
    }
  for (int b = 0; b < 10; ++b)
  {
    // a bin of the triangle between the centre and a chord: (R cos a)^2 (tan t1 - tan t0) / 2
    const double t0 = -a + 0.2 * a * b, t1 = t0 + 0.2 * a;
    const double share = std::pow(R * std::cos(a), 2) * (std::tan(t1) - std::tan(t0)) / (R * R * std::sin(2 * a));
    // 0.5 %: the grid's 1.8 million points, about 11,000 per bin (counting noise 1 %, but the
    // grid is not random: measured within 0.2 %); the unmapped disc is 2.6 % off at the edges
    EXPECT_NEAR(count[b] / total / share, 1.0, 0.005) << "bin " << b;
  }
}

TEST(ContactKinematic, TheFaceRemapPutsTheDiscreteAreaInsideEachCircle)
{
  // A uniform stress pushes each end particle with its discrete loaded area A_i
  // (sph::Body::loaded_face_areas), which near the side differs from its cell's. The remap
  // (set_face_remap) moves a contact point from r to r' with pi r'^2 = the discrete area inside
  // r. Here rings of cells of a body-fitted disc, the second ring from the side carrying 25 %
  // more than its cell and the outer one the same area less (the pattern the 2.5 mm cylinder
  // has): inside, the identity; at the ring boundaries, the discrete area; beyond, the identity.
  const double dx = 0.0025, R = 0.025;
  const int rings = 10;
  std::vector<sph::Vector<3>> x0;
  std::vector<double> area, cell;
  double excess = 0;
  for (int k = 0; k < rings; ++k)
  {
    const double r_in = k * dx, r_out = (k + 1) * dx, r_mid = 0.5 * (r_in + r_out);
    const int n_ring  = k == 0 ? 1 : static_cast<int>(std::lround(2 * M_PI * r_mid / dx));
    const double c    = M_PI * (r_out * r_out - r_in * r_in) / n_ring;
    for (int j = 0; j < n_ring; ++j)
    {
      const double t = 2 * M_PI * j / n_ring, r = k == 0 ? 0.0 : r_mid;
      x0.emplace_back(r * std::cos(t), r * std::sin(t), 0.0);
      cell.push_back(c);
      double a = c;
      if (k == rings - 2)
        a = 1.25 * c, excess += 0.25 * c;
      area.push_back(a);
    }
  }
  // the outer ring gives back what the second one takes (the areas add up to the face)
  const double outer = M_PI * (R * R - std::pow(R - dx, 2));
  for (std::size_t i = 0; i < area.size(); ++i)
    if (std::hypot(x0[i][0], x0[i][1]) > R - dx)
      area[i] -= cell[i] * excess / outer;
  // each face's particles are tabulated twice (set_face_remap takes both end faces): here the
  // one face stands for both, so its areas count double
  for (double &a : area)
    a *= 2;
  for (double &c : cell)
    c *= 2;
  ContactParameters p;
  set_face_remap(p, x0, area, cell, dx);
  auto mapped = [&](const double r) {
    double x = r, y = 0;
    map_contact_point(p, x, y);
    return x;
  };
  // identity well inside (no cell within dx / 2 of r has A != c): sqrt(r^2) and the linear
  // interpolation between two such entries, round-off (1e-15 m, a few ulps of 10 mm)
  EXPECT_NEAR(mapped(0.010), 0.010, 1e-15);
  EXPECT_NEAR(mapped(0.018), 0.018, 1e-15);
  // at the boundary between the two outer rings the circle of r' holds the disc inside it plus
  // the second ring's excess (the spreading over r_i +- dx / 2 puts all of it inside r = R - dx,
  // the cells' outer edges, and none of the outer ring's deficit)
  const double r1 = R - dx;
  // 1e-12: r1 is a table entry (a multiple of dx / 8), so only the sums' round-off is left
  EXPECT_NEAR(M_PI * std::pow(mapped(r1), 2) / (M_PI * r1 * r1 + excess), 1.0, 1e-12);
  // the whole face maps onto itself: the areas add up (1e-12 m: the excesses' sum cancels to
  // round-off)
  EXPECT_NEAR(mapped(R), R, 1e-12);
  EXPECT_NEAR(mapped(R + 0.5 * dx), R + 0.5 * dx, 1e-12);
  // monotonic: no two contact points swap places
  double last = 0;
  for (double r = 1e-5; r < R + dx; r += 1e-5)
  {
    const double m = mapped(r);
    EXPECT_GT(m, last) << r;
    last = m;
  }
}
