// The batched total Lagrangian stress update (sph/src/stress_batch.h): its two paths against each
// other bit for bit, and its kinematics against closed forms.
#include "stress_batch.h"

#include <sph/rock_models.h>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

namespace
{
  using sph::stress_batch::Batch;
  using sph::stress_batch::Fields;
  using Tensor = Eigen::Matrix3d;

  /// Per-particle arrays of n particles, owned, with Fields pointing into them.
  struct Store
  {
    std::vector<Tensor> F, L, F_prev, stress, Q;
    std::vector<double> volume0, mass, volume, density, work;
    explicit Store(const std::size_t n)
        : F(n, Tensor::Identity())
        , L(n, Tensor::Identity())
        , F_prev(n, Tensor::Identity())
        , stress(n, Tensor::Zero())
        , Q(n, Tensor::Zero())
        , volume0(n, 1e-9)
        , mass(n, 2.7e-6)
        , volume(n, 0.0)
        , density(n, 0.0)
        , work(n, 0.0)
    {}
    Fields fields(const bool corrected)
    {
      Fields f;
      f.F         = F[0].data();
      f.L         = L[0].data();
      f.F_prev    = F_prev[0].data();
      f.stress    = stress[0].data();
      f.Q         = Q[0].data();
      f.volume0   = volume0.data();
      f.mass      = mass.data();
      f.volume    = volume.data();
      f.density   = density.data();
      f.work      = work.data();
      f.two_G     = 2.0 * 24e9;
      f.lambda    = 40e9 - 2.0 / 3.0 * 24e9;
      f.corrected = corrected;
      return f;
    }
  };

  /// Runs the update of particles idx[0..n) with the trial as the new stress (elastic).
  void update(Store &s, const std::int32_t *idx, const int n, const bool simd, const bool corrected)
  {
    const Fields f = s.fields(corrected);
    Batch b;
    sph::stress_batch::kinematics(f, idx, n, b, simd);
    sph::stress_batch::finish(f, b, simd);
  }

  /// n particles near the identity with a random correction, a random symmetric stress of
  /// ~10 MPa, random volumes and stress work: a state with strain, spin and stress.
  Store random_store(const std::size_t n)
  {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    Store a(n);
    for (std::size_t i = 0; i < n; ++i)
    {
      for (int e = 0; e < 9; ++e)
      {
        a.F[i].data()[e] += 1e-6 * u(rng); // A (the sum in F before the update)
        a.L[i].data()[e] += 0.1 * u(rng);
        a.F_prev[i].data()[e] += 1e-6 * u(rng);
      }
      const Tensor s = Tensor::NullaryExpr([&]() { return 1e7 * u(rng); });
      a.stress[i]    = s + s.transpose();
      a.volume0[i] *= 1.0 + 0.1 * u(rng);
      a.work[i] = 1e-3 * u(rng);
    }
    return a;
  }

  bool has_avx2()
  {
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  }

  TEST(StressBatch, VectorAndScalarPathsGiveTheSameBits)
  {
    // a particle's results must not depend on the path, its lane or its batch: Body's results
    // are then the same for any thread count and on a CPU without AVX2 (bitwise: that is the
    // claim; both paths are one sequence of IEEE operations, built without contraction)
    if (!has_avx2())
      GTEST_SKIP() << "this CPU has no AVX2: only the scalar path runs here";
    const Store a = random_store(11);
    // batches of 4, 4 and 3 (a padded lane) on one path; 2, 4, 4, 1 on the other
    for (const bool corrected : {true, false})
    {
      Store x = a, y = a;
      std::int32_t i1[4] = {0, 1, 2, 3}, i2[4] = {4, 5, 6, 7}, i3[4] = {8, 9, 10};
      update(x, i1, 4, true, corrected);
      update(x, i2, 4, true, corrected);
      update(x, i3, 3, true, corrected);
      std::int32_t j1[4] = {0, 1}, j2[4] = {2, 3, 4, 5}, j3[4] = {6, 7, 8, 9}, j4[4] = {10};
      update(y, j1, 2, false, corrected);
      update(y, j2, 4, false, corrected);
      update(y, j3, 4, false, corrected);
      update(y, j4, 1, false, corrected);
      const auto same = [&](const auto &p, const auto &q, const char *what) {
        EXPECT_EQ(0, std::memcmp(p.data(), q.data(), p.size() * sizeof(p[0])))
          << what << ", corrected " << corrected;
      };
      same(x.F, y.F, "F");
      same(x.F_prev, y.F_prev, "F_prev");
      same(x.stress, y.stress, "stress");
      same(x.Q, y.Q, "Q");
      same(x.volume, y.volume, "volume");
      same(x.density, y.density, "density");
      same(x.work, y.work, "work");
      // and the update did something (the state moved), or the test proves nothing
      EXPECT_GT((x.stress[5] - a.stress[5]).norm(), 1e3);
    }
  }

  TEST(StressBatch, TrialIsTheRockModelsElasticUpdate)
  {
    // Body skips the rock model where its surely_elastic test holds and keeps the batch's trial:
    // that is only right if the trial is, bit for bit, what the model returns for an elastic
    // step. rock::elastic_trial on the batch's rotated stress and strain increment, and
    // MohrCoulomb itself with a cohesion far above these stresses (surely elastic), must give
    // the batch's trial exactly, on both paths
    sph::rock::ModelConstants prm;
    prm.G        = 24e9; // as Store::fields: two_G = 2 G, lambda = K - 2G/3
    prm.K        = 40e9;
    prm.cohesion = 1e12;
    const sph::rock::MohrCoulomb mc;
    for (const bool simd : {false, true})
    {
      if (simd && !has_avx2())
        continue;
      Store a                   = random_store(4);
      const std::int32_t idx[4] = {0, 1, 2, 3};
      Batch b;
      sph::stress_batch::kinematics(a.fields(true), idx, 4, b, simd);
      for (int l = 0; l < 4; ++l)
      {
        Tensor trial, rotated, de;
        for (int e = 0; e < 9; ++e)
        {
          trial.data()[e]   = b.stress[e][l];
          rotated.data()[e] = b.rotated[e][l];
          de.data()[e]      = b.de[e][l];
        }
        ASSERT_GT(de.norm(), 1e-9) << "the step must strain, or the test proves nothing";
        ASSERT_TRUE(mc.surely_elastic(trial, sph::MaterialState{}, prm));
        EXPECT_EQ(trial, sph::rock::elastic_trial(rotated, de, prm)) << "simd " << simd;
        EXPECT_EQ(trial, mc(rotated, de, sph::MaterialState{}, prm).stress) << "simd " << simd;
      }
    }
  }

  TEST(StressBatch, UniaxialStretchFromRest)
  {
    // F_prev = I, sigma = 0, F = diag(1 + e, 1, 1), L = I: G = diag(e / (1 + e/2), 0, 0), no
    // spin; the new stress is lambda G11 I + 2 mu G11 e1 e1, J = 1 + e, cof F = diag(1, 1+e, 1+e)
    // and Q = P = sigma cof F. Closed forms evaluated in a few operations: 1e-14 relative is
    // round-off of a dozen operations with margin
    for (const bool simd : {false, true})
    {
      if (simd && !has_avx2())
        continue;
      // e = F11 - 1 exactly (1 + 1e-4 is not a double: the stretch is the double's)
      const double e = (1.0 + 1e-4) - 1.0;
      Store s(1);
      s.F[0](0, 0)        = 1.0 + e;
      std::int32_t idx[4] = {0};
      update(s, idx, 1, simd, true);
      const double g11 = e / (1.0 + 0.5 * e);
      const double mu2 = 2.0 * 24e9, lambda = 40e9 - 2.0 / 3.0 * 24e9;
      Tensor sigma = Tensor::Identity() * lambda * g11;
      sigma(0, 0) += mu2 * g11;
      const Tensor cof = Eigen::Vector3d(1.0, 1.0 + e, 1.0 + e).asDiagonal();
      const Tensor P   = sigma * cof;
      EXPECT_LT((s.stress[0] - sigma).norm(), 1e-14 * sigma.norm()) << "simd " << simd;
      EXPECT_LT((s.Q[0] - P).norm(), 1e-14 * P.norm()) << "simd " << simd;
      EXPECT_NEAR(s.volume[0], 1e-9 * (1.0 + e), 1e-14 * 1e-9);
      EXPECT_NEAR(s.density[0], 2.7e-6 / (1e-9 * (1.0 + e)), 1e-14 * 2.7e3);
      // work: V0 J (0 + sigma) / 2 : de, a sum of nine products on top of the stress's own
      // round-off: 1e-13 relative
      EXPECT_NEAR(s.work[0], 1e-9 * (1.0 + e) * 0.5 * sigma(0, 0) * g11,
                  1e-13 * 1e-9 * sigma(0, 0) * g11);
      EXPECT_EQ(s.F[0], s.F_prev[0]);
    }
  }

  TEST(StressBatch, RigidRotationTurnsTheStress)
  {
    // F_prev = I, F = R (a rotation by 0.2 rad about an oblique axis): G = (R - I)((R + I)/2)^-1
    // is the Cayley form of R, exactly antisymmetric, and the Hughes-Winget rotation of its spin
    // is R itself. So the stress rotates as R sigma R^T with no strain (objectivity), however
    // large the angle; round-off of ~50 operations on O(1) entries: 1e-13 relative
    for (const bool simd : {false, true})
    {
      if (simd && !has_avx2())
        continue;
      const Tensor R =
        Eigen::AngleAxisd(0.2, Eigen::Vector3d(1.0, -2.0, 0.5).normalized()).toRotationMatrix();
      Store s(1);
      Tensor sigma;
      sigma << -30e6, 4e6, 1e6, 4e6, -10e6, -2e6, 1e6, -2e6, 5e6;
      s.stress[0]         = sigma;
      s.F[0]              = R;
      std::int32_t idx[4] = {0};
      update(s, idx, 1, simd, false);
      const Tensor expected = R * sigma * R.transpose();
      EXPECT_LT((s.stress[0] - expected).norm(), 1e-13 * sigma.norm()) << "simd " << simd;
      EXPECT_NEAR(s.volume[0], 1e-9, 1e-22); // det R = 1 to round-off of O(1) products: 1e-13
      // no strain, no work (round-off of the rotated stress against de ~ 1e-17)
      EXPECT_LT(std::abs(s.work[0]), 1e-9 * 1e-13 * sigma.norm());
      // the stress stays exactly symmetric
      EXPECT_EQ(s.stress[0], s.stress[0].transpose());
    }
  }
} // namespace
