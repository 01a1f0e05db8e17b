#include <sph/body.h>
#include <sph/lattice.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>

namespace
{
  using namespace sph;

  MaterialParameters elastic_rock()
  {
    MaterialParameters m;
    m.model          = RockModel::elastic;
    m.density        = 2700;
    m.youngs_modulus = 50e9;
    m.poissons_ratio = 0.25;
    return m;
  }

  Parameters numerics(const Formulation form, const double dx)
  {
    Parameters p;
    p.form    = form;
    p.spacing = dx;
    return p;
  }

  /// Moves every particle with the velocity field G x for one step of dt: afterwards
  /// x = (I + dt G) X exactly (up to round-off), an affine deformation.
  template <int dim>
  void affine_step(Body<dim> &body, const Tensor<dim> &G, const double dt)
  {
    body.compute_forces(); // stress-free: round-off forces only
    for (unsigned i = 0; i < body.n_particles(); ++i)
      {
        body.set_velocity(i, G * body.positions()[i]);
        // cancel the round-off force so that the step is exactly affine even for a long dt
        body.external_forces()[i] = -body.internal_forces()[i];
      }
    body.integrate(dt);
    body.compute_forces();
  }

  /// A weak Mohr-Coulomb rock (c = 1 MPa, phi = 0.5 rad): a few steps of flow yield it.
  MaterialParameters weak_mohr_coulomb()
  {
    MaterialParameters m = elastic_rock();
    m.model              = RockModel::mohr_coulomb;
    m.cohesion           = 1e6;
    m.friction_angle     = 0.5;
    return m;
  }

  /// Largest |a_i - b_i| over the particles; scale: the largest |b_i|.
  double largest_difference(const std::vector<Vector<3>> &a, const std::vector<Vector<3>> &b,
                            double &scale)
  {
    double worst = 0;
    scale        = 0;
    for (std::size_t i = 0; i < a.size(); ++i)
      {
        scale = std::max(scale, b[i].norm());
        worst = std::max(worst, (a[i] - b[i]).norm());
      }
    return worst;
  }

  TEST(SphCorrection, LinearFieldGradientExactEverywhereTotalLagrangian)
  {
    // With renormalised gradients, F of an affine motion is exact at every particle, surface and
    // edges included: only round-off (1e-10 on entries of order 1) may remain.
    for (const Formulation form :
         {Formulation::total_lagrangian_corrected, Formulation::total_lagrangian})
      {
        const Lattice<3> lat = make_cylinder<3>(0.02, 0.03, 0.002);
        Body<3>          body(numerics(form, 0.002), elastic_rock(), lat.positions, lat.volumes);
        Tensor<3>        G;
        G << 0.1, 0.02, -0.03, 0.01, -0.05, 0.04, 0.02, 0.03, 0.07;
        const double dt = 0.1;
        affine_step(body, G, dt);
        const Tensor<3> expected = Tensor<3>::Identity() + dt * G;
        double          worst    = 0;
        for (unsigned i = 0; i < body.n_particles(); ++i)
          worst = std::max(worst, (body.deformation_gradient(i) - expected).cwiseAbs().maxCoeff());
        EXPECT_LT(worst, 1e-10) << "FORM " << static_cast<int>(form);
      }
  }

  TEST(SphCorrection, SelfGradientIsHowAParticlesOwnMoveChangesItsF)
  {
    // F_i is linear in the positions: moving particle i alone by d changes its F by exactly
    // -d (x) g_i (Body::self_gradients), at the surface and inside (1e-10: round-off on F's
    // entries of order 1); g vanishes inside a full neighbourhood (1e-9 / spacing: the round-off
    // of sums of order 1 / spacing) and points into the body at a face: at the top face's centre
    // g_z dx = -0.958 (both forms), asserted below -0.5, half of it, far from the 0 a missing
    // surface term would give; its lateral part vanishes by symmetry
    for (const Formulation form :
         {Formulation::total_lagrangian_corrected, Formulation::total_lagrangian})
      {
        const double     dx  = 0.002;
        const Lattice<3> lat = make_cylinder<3>(0.02, 0.03, dx);
        std::size_t top = 0, inside = 0;
        Vector<3>   centre = Vector<3>::Zero();
        for (const Vector<3> &x : lat.positions)
          centre += x / static_cast<double>(lat.positions.size());
        for (std::size_t i = 0; i < lat.positions.size(); ++i)
          {
            const Vector<3> &x = lat.positions[i];
            if (x[2] > lat.positions[top][2] + 1e-12 || (x[2] > lat.positions[top][2] - 1e-12 &&
                                                        x.head<2>().norm() < lat.positions[top].head<2>().norm()))
              top = i;
            if ((x - centre).norm() < (lat.positions[inside] - centre).norm())
              inside = i;
          }
        for (const std::size_t i : {top, inside})
          {
            Body<3> body(numerics(form, dx), elastic_rock(), lat.positions, lat.volumes);
            const Vector<3> g = body.self_gradients()[i];
            const Vector<3> d(1e-6, -2e-6, 3e-6);
            const double    dt = 1e-3;
            body.compute_forces();
            for (unsigned k = 0; k < body.n_particles(); ++k)
              body.external_forces()[k] = -body.internal_forces()[k];
            body.set_velocity(static_cast<unsigned>(i), d / dt);
            body.integrate(dt);
            body.compute_forces();
            const Tensor<3> expected = Tensor<3>::Identity() - d * g.transpose();
            EXPECT_LT((body.deformation_gradient(static_cast<unsigned>(i)) - expected).cwiseAbs().maxCoeff(), 1e-10)
              << "FORM " << static_cast<int>(form) << ", particle " << i;
            if (i == inside)
              EXPECT_LT(g.norm() * dx, 1e-9) << "FORM " << static_cast<int>(form);
            else
              {
                EXPECT_LT(g[2] * dx, -0.5) << "FORM " << static_cast<int>(form);
                EXPECT_LT(g.head<2>().norm() * dx, 1e-9) << "FORM " << static_cast<int>(form);
              }
          }
      }
    // the updated Lagrangian forms integrate F from the velocity gradient: no such term
    const Lattice<3> lat = make_cylinder<3>(0.02, 0.03, 0.002);
    Body<3> body(numerics(Formulation::updated_lagrangian_corrected, 0.002), elastic_rock(), lat.positions,
                 lat.volumes);
    for (const Vector<3> &g : body.self_gradients())
      EXPECT_EQ(g.norm(), 0.0);
  }

  TEST(SphCorrection, LinearVelocityGradientExactUpdatedLagrangian)
  {
    // FORM 1: the velocity gradient of a linear field is exact at every particle, so a uniform
    // strain increment gives the same stress everywhere (1e-8 relative: round-off through C).
    const Lattice<2> lat = make_disc<2>(0.02, 0.01, 0.001);
    Body<2> body(numerics(Formulation::updated_lagrangian_corrected, 0.001), elastic_rock(),
                 lat.positions, lat.volumes);
    Tensor<2> G;
    G << 1e-3, 2e-4, -5e-4, -3e-4;
    affine_step(body, G, 1.0);
    const Tensor<2> s0 = body.stress(0);
    ASSERT_GT(s0.norm(), 1e6) << "the increment must stress the body";
    double worst = 0;
    for (unsigned i = 0; i < body.n_particles(); ++i)
      worst = std::max(worst, (body.stress(i) - s0).norm());
    EXPECT_LT(worst, 1e-8 * s0.norm());
  }

  template <int dim>
  void check_momentum(const Formulation form, const RockModel model)
  {
    // An isolated body with random velocities: every pair force is applied with opposite signs,
    // so the total momentum changes only by round-off of the sums (1e-12 of sum |m v|).
    const Lattice<dim> lat = make_disc<dim>(0.02, 0.006, 0.001);
    MaterialParameters m   = elastic_rock();
    m.model                = model;
    m.cohesion             = 5e6;
    m.friction_angle       = 0.6;
    m.tensile_strength     = 2e6;
    Body<dim>                              body(numerics(form, 0.001), m, lat.positions, lat.volumes);
    std::mt19937                           rng(7);
    std::normal_distribution<double>       u(0.0, 1.0);
    double                                 scale = 0;
    for (unsigned i = 0; i < body.n_particles(); ++i)
      {
        Vector<dim> v;
        for (int d = 0; d < dim; ++d)
          v[d] = u(rng);
        body.set_velocity(i, v);
        scale += body.masses()[i] * v.norm();
      }
    const Vector<dim> p0 = body.momentum();
    for (int step = 0; step < 40; ++step)
      {
        body.compute_forces();
        body.integrate(body.stable_time_step());
      }
    double max_force = 0;
    for (const auto &f : body.internal_forces())
      max_force = std::max(max_force, f.norm());
    ASSERT_GT(max_force, 0.0) << "the body must be loaded, or the test proves nothing";
    EXPECT_LT((body.momentum() - p0).norm(), 1e-12 * scale) << "FORM " << static_cast<int>(form);
  }

  TEST(SphPairForces, MomentumOfIsolatedBodyConstant)
  {
    for (const Formulation f :
         {Formulation::updated_lagrangian, Formulation::updated_lagrangian_corrected,
          Formulation::total_lagrangian, Formulation::total_lagrangian_corrected})
      {
        check_momentum<2>(f, RockModel::mohr_coulomb_cutoff);
        check_momentum<3>(f, RockModel::elastic);
      }
  }

  TEST(SphBody, RigidRotationGivesNoStress)
  {
    // a rigid spin increment: the objective (Hughes-Winget) update keeps the stress zero up to
    // the stretch of the linearised rotation I + dt W (F^T F - I = dt^2 W^T W ~ 2e-8): 1e-7 E
    const Lattice<3> lat = make_block<3>(Vector<3>::Zero(), Vector<3>::Constant(0.01), 0.001);
    Body<3>   body(numerics(Formulation::total_lagrangian_corrected, 0.001), elastic_rock(),
                   lat.positions, lat.volumes);
    Tensor<3> W;
    W << 0, -1, 0.5, 1, 0, -0.2, -0.5, 0.2, 0;
    affine_step(body, W, 1e-4);
    double worst = 0;
    for (unsigned i = 0; i < body.n_particles(); ++i)
      worst = std::max(worst, body.stress3(i).norm());
    EXPECT_LT(worst, 1e-7 * 50e9);
  }

  TEST(SphBody, SameResultForOneAndTwoThreads)
  {
    // every sum is taken in an order fixed by the chunks (Parameters::chunks), whichever thread
    // takes which chunk, so positions are bitwise equal for any thread count; a bitwise
    // comparison is the point of this test. Six chunks (the ~1,500 particles would get one
    // automatically): pairs across chunks in both passes, more chunks than threads. All three
    // pair loops: the vectorised ones (where the CPU has AVX2), in mixed and in double
    // precision, and the portable scalar one
    for (const int variant : {0, 1, 2})
      {
        const bool vectorised = variant < 2, single = variant == 0;
        std::vector<std::vector<Vector<3>>> result;
        for (const int threads : {1, 2, 3})
          {
            const Lattice<3> lat = make_cylinder<3>(0.01, 0.02, 0.001);
            Parameters       p   = numerics(Formulation::total_lagrangian_corrected, 0.001);
            p.n_threads          = threads;
            p.chunks             = 6;
            p.vectorised         = vectorised;
            p.single_precision   = single;
            const MaterialParameters m = weak_mohr_coulomb();
            Body<3> body(p, m, lat.positions, lat.volumes);
            for (unsigned i = 0; i < body.n_particles(); ++i)
              if (body.positions()[i][2] > 0.019)
                body.constrain(i, 2, -1.0);
            for (int s = 0; s < 30; ++s)
              {
                body.compute_forces();
                body.integrate(body.stable_time_step());
              }
            result.push_back(body.positions());
          }
        for (const std::size_t k : {1, 2})
          EXPECT_EQ(0, std::memcmp(result[0].data(), result[k].data(),
                                   result[0].size() * sizeof(Vector<3>)))
            << "vectorised " << vectorised << ", single precision " << single << ", " << k + 1
            << " threads against 1";
      }
  }

  TEST(SphBody, ChunksChangeTheResultsByRoundOffOnly)
  {
    // one chunk (every pair inside it) against seven (pairs across chunks: their shares of the
    // second particle added by its chunk, in the F sums before its own pairs, in the forces
    // after them): the same terms, in another order. Twenty steps of Mohr-Coulomb flow from
    // random velocities; a reordered sum of ~60 terms moves a force by ~1e-16 of it, and F, the
    // stress and the positions carry that on, and the plastic flow amplifies it (measured 2.6e-10
    // of the largest force vectorised, 4.4e-12 scalar; 1e-7 keeps a margin). A share
    // lost or added twice would move a force by ~1/60 of it
    for (const bool vectorised : {true, false})
      {
        std::vector<std::vector<Vector<3>>> force;
        for (const int chunks : {1, 7})
          {
            const Lattice<3> lat = make_cylinder<3>(0.01, 0.02, 0.001);
            Parameters       p   = numerics(Formulation::total_lagrangian_corrected, 0.001);
            p.chunks             = chunks;
            p.vectorised         = vectorised;
            p.single_precision   = false;
            p.n_threads          = 2;
            Body<3>      body(p, weak_mohr_coulomb(), lat.positions, lat.volumes);
            std::mt19937 rng(11);
            std::uniform_real_distribution<double> u(-1.0, 1.0);
            for (unsigned i = 0; i < body.n_particles(); ++i)
              body.set_velocity(i, Vector<3>(u(rng), u(rng), u(rng)));
            for (int s = 0; s < 20; ++s)
              {
                body.compute_forces();
                body.integrate(body.stable_time_step());
              }
            body.compute_forces();
            force.push_back(body.internal_forces());
          }
        double       scale = 0;
        const double worst = largest_difference(force[1], force[0], scale);
        ASSERT_GT(scale, 0.0) << "the state must be loaded, or the test proves nothing";
        std::printf("7 chunks against 1 (vectorised %d): worst force difference %.3g of the "
                    "largest\n", vectorised, worst / scale);
        EXPECT_LT(worst, 1e-7 * scale) << "vectorised " << vectorised;
      }
  }

  TEST(SphBody, VectorisedPairForceIsTheScalarOneToRoundOff)
  {
    // one state (random velocities: viscosity on approaching pairs; three steps of flow: stress,
    // F != I, hourglass terms) through the vectorised and the scalar pair loops. The same terms
    // in another order and with fused multiply-adds. F = I + O(1e-4) here is a sum of ~60 O(1)
    // terms: another order moves it by ~1e-15, i.e. 1e-11 of its strain part, and the stress
    // and forces follow (measured 5e-11 of the largest force with Mohr-Coulomb, 3e-11 elastic;
    // 8e-15 when only the pair forces were vectorised). 1e-9 keeps a margin and still catches
    // a wrong viscous or hourglass term, which carry ~1e-3 of the forces or more
    for (const Formulation form :
         {Formulation::total_lagrangian_corrected, Formulation::updated_lagrangian_corrected})
      {
        std::vector<std::vector<Vector<3>>> force;
        std::vector<Energies>               energy;
        for (const bool vectorised : {true, false})
          {
            const Lattice<3> lat = make_cylinder<3>(0.01, 0.02, 0.001);
            Parameters       p   = numerics(form, 0.001);
            p.vectorised         = vectorised;
            p.single_precision   = false; // the double kernel (the mixed one: the next test)
            p.n_threads          = 2;
            const MaterialParameters m = weak_mohr_coulomb();
            Body<3> body(p, m, lat.positions, lat.volumes);
            if (vectorised && !body.vectorised())
              GTEST_SKIP() << "this CPU has no AVX2: only the scalar pair force runs here";
            ASSERT_EQ(vectorised, body.vectorised());
            std::mt19937                           rng(7);
            std::uniform_real_distribution<double> u(-1.0, 1.0);
            for (unsigned i = 0; i < body.n_particles(); ++i)
              body.set_velocity(i, Vector<3>(u(rng), u(rng), u(rng)));
            for (int s = 0; s < 3; ++s)
              {
                body.compute_forces();
                body.integrate(body.stable_time_step());
              }
            body.compute_forces();
            force.push_back(body.internal_forces());
            energy.push_back(body.energies());
          }
        double       scale = 0;
        const double worst = largest_difference(force[0], force[1], scale);
        ASSERT_GT(scale, 0.0) << "the state must be loaded, or the test proves nothing";
        EXPECT_LT(worst, 1e-9 * scale) << "FORM " << static_cast<int>(form);
        // viscous and hourglass work of the three steps: sums of ~10^5 pair powers each
        ASSERT_GT(energy[1].viscous, 0.0) << "the viscosity must act, or the test proves nothing";
        EXPECT_NEAR(energy[0].viscous, energy[1].viscous, 1e-10 * std::abs(energy[1].viscous));
        EXPECT_NEAR(energy[0].hourglass, energy[1].hourglass,
                    1e-10 * std::abs(energy[1].viscous) + 1e-10 * std::abs(energy[1].hourglass));
      }
  }

  TEST(SphBody, MixedPrecisionPairForceIsTheDoubleOneToFloatRoundOff)
  {
    // Parameters::single_precision: the pair force in float with position differences and sums
    // in double. One state in both bodies, bit for bit: prescribed steps (velocities set, the
    // internal force cancelled by an external one) of a shear plus random velocities, so x, v,
    // F and the Mohr-Coulomb stresses do not depend on the pair force; then one force pass in
    // mixed and one in double precision. Float keeps 6e-8 of each pair term and a particle sums
    // ~60 terms of both signs: its force is off by a few 1e-7 of the largest forces (measured
    // 1.2e-7); 1e-5 keeps a margin and still catches a wrong term (the viscous and hourglass
    // forces carry 1e-3 of the forces or more, a wrong stress entry far more)
    std::vector<std::vector<Vector<3>>> force;
    for (const bool single : {true, false})
      {
        const Lattice<3> lat = make_cylinder<3>(0.01, 0.02, 0.001);
        Parameters       p   = numerics(Formulation::total_lagrangian_corrected, 0.001);
        p.single_precision   = single;
        const MaterialParameters m = weak_mohr_coulomb();
        Body<3> body(p, m, lat.positions, lat.volumes);
        if (!body.vectorised())
          GTEST_SKIP() << "this CPU has no AVX2: there is no mixed-precision pair force";
        ASSERT_EQ(single, body.single_precision());
        std::mt19937                           rng(11);
        std::uniform_real_distribution<double> u(-1.0, 1.0);
        for (int s = 0; s < 4; ++s)
          {
            body.compute_forces();
            for (unsigned i = 0; i < body.n_particles(); ++i)
              {
                const Vector<3> &x = body.positions()[i];
                body.set_velocity(i, Vector<3>(20.0 * x[2] + u(rng), u(rng), -10.0 * x[2] + u(rng)));
                body.external_forces()[i] = -body.internal_forces()[i] - body.pressure_forces()[i];
              }
            body.integrate(1e-7);
          }
        body.compute_forces();
        force.push_back(body.internal_forces());
      }
    double       scale = 0;
    const double worst = largest_difference(force[0], force[1], scale);
    ASSERT_GT(scale, 0.0) << "the state must be loaded, or the test proves nothing";
    std::printf("mixed against double precision: worst force difference %.3g of the largest\n",
                worst / scale);
    EXPECT_LT(worst, 1e-5 * scale);
    EXPECT_GT(worst, 0.0) << "the two kernels must differ, or the mixed one did not run";
  }

  TEST(SphBody, MixedPrecisionOnlyFromATenthOfAMillimetre)
  {
    // |grad W|^2 ~ 0.06 / h^8 leaves the float range (3.4e38) below h ~ 2e-5 m: under a spacing
    // of 0.1 mm the body keeps the double pair force (Parameters::single_precision's rule)
    for (const double dx : {1e-4, 5e-5})
      {
        const Lattice<3> lat =
          make_block<3>(Vector<3>::Zero(), Vector<3>::Constant(6 * dx), dx);
        Body<3> body(numerics(Formulation::total_lagrangian_corrected, dx), elastic_rock(),
                     lat.positions, lat.volumes);
        if (!body.vectorised())
          GTEST_SKIP() << "this CPU has no AVX2: there is no mixed-precision pair force";
        EXPECT_EQ(dx >= 1e-4, body.single_precision()) << "spacing " << dx;
      }
  }

  TEST(SphPressure, UniformPressureOnBlock)
  {
    // the area vectors of a closed body sum to zero by pair antisymmetry (round-off), and those
    // on the face z = max add up to the face area: 2e-3, the corrected symmetric boundary sum of
    // a flat lattice face is 1.001 dx^2 per column at CSLH 1.2 (the vectors are the force of a
    // uniform stress, so they carry the discrete face's area, not the exact one)
    const double     a = 0.01, dx = 0.001;
    const Lattice<3> lat = make_block<3>(Vector<3>::Zero(), Vector<3>::Constant(a), dx);
    Body<3>          body(numerics(Formulation::total_lagrangian_corrected, dx), elastic_rock(),
                          lat.positions, lat.volumes);
    const double p = 1e6;
    body.set_surface_pressure(p);
    body.compute_forces();
    Vector<3> total = Vector<3>::Zero();
    double    top = 0, norm = 0;
    for (unsigned i = 0; i < body.n_particles(); ++i)
      {
        const Vector<3> &f = body.pressure_forces()[i];
        total += f;
        norm += f.norm();
        // the top third of the block, away from the side faces
        const Vector<3> &x = body.positions()[i];
        if (x[2] > 2 * a / 3 && x[0] > 0.3 * a && x[0] < 0.7 * a && x[1] > 0.3 * a &&
            x[1] < 0.7 * a)
          top += f[2];
      }
    ASSERT_GT(norm, 0.0);
    EXPECT_LT(total.norm(), 1e-12 * norm);
    // interior columns 0.3a..0.7a: 4 x 4 columns of dx^2 each, pushed down (compression)
    EXPECT_NEAR(top, -p * 16 * dx * dx, 2e-3 * p * 16 * dx * dx);
  }

  TEST(SphBody, RejectsBadParameters)
  {
    const Lattice<2> lat = make_block<2>(Vector<2>::Zero(), Vector<2>::Constant(0.01), 0.001);
    Parameters       p   = numerics(Formulation::total_lagrangian_corrected, 0.001);
    p.tssfac             = 2;
    EXPECT_THROW(Body<2>(p, elastic_rock(), lat.positions, lat.volumes), std::invalid_argument);
    p        = numerics(Formulation::total_lagrangian_corrected, 0.001);
    p.chunks = -1;
    EXPECT_THROW(Body<2>(p, elastic_rock(), lat.positions, lat.volumes), std::invalid_argument);
    MaterialParameters m = elastic_rock();
    m.poissons_ratio     = 0.5;
    EXPECT_THROW(Body<2>(numerics(Formulation::total_lagrangian_corrected, 0.001), m,
                         lat.positions, lat.volumes),
                 std::invalid_argument);
  }

  TEST(SphBody, SaveLoadStateContinuesBitwise)
  {
    // save_state/load_state promise a bitwise continuation: run a shaken block 5 steps, copy it
    // into a fresh body, run both 5 more steps and compare every position exactly
    for (const Formulation form :
         {Formulation::updated_lagrangian_corrected, Formulation::total_lagrangian_corrected})
      {
        const Lattice<2> lat = make_block<2>(Vector<2>(0, 0), Vector<2>(0.02, 0.01), 0.001);
        Body<2>          a(numerics(form, 0.001), elastic_rock(), lat.positions, lat.volumes);
        Body<2>          b(numerics(form, 0.001), elastic_rock(), lat.positions, lat.volumes);
        for (unsigned i = 0; i < a.n_particles(); ++i)
          a.set_velocity(i, Vector<2>(std::sin(1e3 * lat.positions[i][1]), 0.0));
        const auto step = [](Body<2> &body) {
          body.compute_forces();
          body.integrate(body.stable_time_step());
        };
        for (int s = 0; s < 5; ++s)
          step(a);
        StateArrays saved;
        a.save_state(saved, "rock.");
        b.load_state(saved, "rock.");
        for (int s = 0; s < 5; ++s)
          {
            step(a);
            step(b);
          }
        for (unsigned i = 0; i < a.n_particles(); ++i)
          ASSERT_EQ(a.positions()[i], b.positions()[i]) << "particle " << i;
        StateArrays broken = saved;
        broken.erase("rock.stress");
        EXPECT_THROW(b.load_state(broken, "rock."), std::invalid_argument);
      }
  }

  TEST(SphBody, LoadStateRestoresTheHourglassControlOfItsCracks)
  {
    // No hourglass control across cracks (Parameters::hourglass_fade): a body that ran on past a
    // saved state has faded the pairs of particles that cracked since. The state loaded back
    // into it must continue as in a fresh body, bit for bit
    const Lattice<3>         lat = make_cylinder<3>(0.01, 0.02, 0.001);
    const Parameters         p   = numerics(Formulation::total_lagrangian_corrected, 0.001);
    MaterialParameters       m   = weak_mohr_coulomb();
    m.softening_strain           = 1e-3; // softening, so that cracks fade hourglass control
    Body<3>                  a(p, m, lat.positions, lat.volumes), b(p, m, lat.positions, lat.volumes);
    const auto pull = [](Body<3> &body) { // the top end pulled: the rock cracks in tension
      for (unsigned i = 0; i < body.n_particles(); ++i)
        if (body.reference_positions()[i][2] > 0.019)
          body.constrain(i, 2, 1.0);
    };
    const auto run = [](Body<3> &body, const int steps) {
      for (int s = 0; s < steps; ++s)
        {
          body.compute_forces();
          body.integrate(body.stable_time_step());
        }
    };
    const auto cracked = [](const Body<3> &body) {
      unsigned n = 0;
      for (unsigned i = 0; i < body.n_particles(); ++i)
        n += body.history(i).cracked ? 1 : 0;
      return n;
    };
    pull(a);
    run(a, 4);
    StateArrays saved;
    a.save_state(saved, "rock.");
    const unsigned before = cracked(a);
    run(a, 30);
    // the test needs particles that cracked after the save (measured: 240 then 564; without the
    // restore of the factors, or of the cracked flags, in load_state the positions then differ)
    ASSERT_GT(cracked(a), before + 10);
    for (Body<3> *body : {&a, &b})
      {
        body->load_state(saved, "rock.");
        pull(*body);
        run(*body, 15);
      }
    EXPECT_EQ(0, std::memcmp(a.positions().data(), b.positions().data(),
                             a.positions().size() * sizeof(Vector<3>)));
  }
} // namespace
