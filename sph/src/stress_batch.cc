#include "stress_batch.h"

#include "avx2_util.h"
#include "tensor3_kernels.h"

#include <algorithm>
#include <cstddef>
#include <initializer_list>

// Built with -ffp-contract=off (sph/CMakeLists.txt): the scalar and the AVX2 instantiations of
// the templates below then compute the same bits.

namespace sph::stress_batch
{
  namespace
  {
#define SPH_INLINE __attribute__((always_inline)) inline

    using tensor3::at;
    using tensor3::cofactor;
    using tensor3::hughes_winget;

    /// The first half for one particle (T = double) or four (T = __m256d), see the file comment.
    template <typename T>
    SPH_INLINE void kinematics_of(const T *A, const T *L, const T *Fp, const T *s,
                                  const double two_G, const double lambda, T *F, T *de, T *rot,
                                  T *trial, T *C, T &J)
    {
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) // F = A L^T
          F[at(r, c)] =
            (A[at(r, 0)] * L[at(c, 0)] + A[at(r, 1)] * L[at(c, 1)]) + A[at(r, 2)] * L[at(c, 2)];
      // G = (F - F_prev) M^{-1}, M = (F + F_prev) / 2, M^{-1} = cof(M)^T / det M
      T D[9], M[9], Mc[9], G[9];
      for (int e = 0; e < 9; ++e)
      {
        D[e] = F[e] - Fp[e];
        M[e] = 0.5 * (F[e] + Fp[e]);
      }
      cofactor(M, Mc);
      const T inv_det = 1.0 / ((M[at(0, 0)] * Mc[at(0, 0)] + M[at(0, 1)] * Mc[at(0, 1)]) +
                               M[at(0, 2)] * Mc[at(0, 2)]);
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
          G[at(r, c)] = ((D[at(r, 0)] * Mc[at(c, 0)] + D[at(r, 1)] * Mc[at(c, 1)]) +
                         D[at(r, 2)] * Mc[at(c, 2)]) *
                        inv_det;
      // de = sym G (exactly symmetric), w = skew G (exactly antisymmetric)
      T w[9];
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
        {
          de[at(r, c)] = 0.5 * (G[at(r, c)] + G[at(c, r)]);
          w[at(r, c)]  = 0.5 * (G[at(r, c)] - G[at(c, r)]);
        }
      T R[9];
      hughes_winget(w, R);
      // rotated = (R sigma) R^T: the upper triangle, mirrored (exactly symmetric)
      T Rs[9];
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
          Rs[at(r, c)] =
            (R[at(r, 0)] * s[at(0, c)] + R[at(r, 1)] * s[at(1, c)]) + R[at(r, 2)] * s[at(2, c)];
      for (int r = 0; r < 3; ++r)
        for (int c = r; c < 3; ++c)
        {
          rot[at(r, c)] =
            (Rs[at(r, 0)] * R[at(c, 0)] + Rs[at(r, 1)] * R[at(c, 1)]) + Rs[at(r, 2)] * R[at(c, 2)];
          rot[at(c, r)] = rot[at(r, c)];
        }
      // elastic trial, in the order of rock::elastic_trial
      const T lt = lambda * ((de[at(0, 0)] + de[at(1, 1)]) + de[at(2, 2)]);
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
        {
          trial[at(r, c)] = rot[at(r, c)] + two_G * de[at(r, c)];
          if (r == c)
            trial[at(r, c)] = trial[at(r, c)] + lt;
        }
      cofactor(F, C);
      J = (F[at(0, 0)] * C[at(0, 0)] + F[at(0, 1)] * C[at(0, 1)]) + F[at(0, 2)] * C[at(0, 2)];
    }

    /// The second half for one particle or four: the stress work increment and Q.
    template <typename T>
    SPH_INLINE void finish_of(const T *s, const T *rot, const T *de, const T *C, const T *L,
                              const T &J, const T &V0, const bool corrected, T &work, T *Q)
    {
      T sum = 0.5 * (rot[0] + s[0]) * de[0];
      for (int e = 1; e < 9; ++e)
        sum = sum + 0.5 * (rot[e] + s[e]) * de[e];
      work = V0 * J * sum;
      T P[9]; // P = sigma cof(F)
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
          P[at(r, c)] =
            (s[at(r, 0)] * C[at(0, c)] + s[at(r, 1)] * C[at(1, c)]) + s[at(r, 2)] * C[at(2, c)];
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
          Q[at(r, c)] = corrected ? (P[at(r, 0)] * L[at(0, c)] + P[at(r, 1)] * L[at(1, c)]) +
                                      P[at(r, 2)] * L[at(2, c)]
                                  : P[at(r, c)];
    }

    const double *tensor(const double *base, const std::int32_t i)
    {
      return base + 9 * static_cast<std::int64_t>(i);
    }
    double *tensor(double *base, const std::int32_t i)
    {
      return base + 9 * static_cast<std::int64_t>(i);
    }

    void kinematics_scalar(const Fields &f, Batch &b)
    {
      for (int l = 0; l < lanes; ++l)
      {
        const std::int32_t i = b.idx[l];
        double F[9], de[9], rot[9], trial[9], C[9], J;
        kinematics_of(tensor(f.F, i), tensor(f.L, i), tensor(f.F_prev, i), tensor(f.stress, i),
                      f.two_G, f.lambda, F, de, rot, trial, C, J);
        for (int e = 0; e < 9; ++e)
        {
          b.F[e][l]       = F[e];
          b.de[e][l]      = de[e];
          b.rotated[e][l] = rot[e];
          b.stress[e][l]  = trial[e];
          b.C[e][l]       = C[e];
        }
        b.J[l] = J;
      }
    }

    void finish_scalar(const Fields &f, const Batch &b)
    {
      for (int l = 0; l < b.n; ++l)
      {
        const std::int32_t i = b.idx[l];
        double s[9], rot[9], de[9], C[9], Q[9], work;
        for (int e = 0; e < 9; ++e)
        {
          s[e]   = b.stress[e][l];
          rot[e] = b.rotated[e][l];
          de[e]  = b.de[e][l];
          C[e]   = b.C[e][l];
        }
        finish_of(s, rot, de, C, tensor(f.L, i), b.J[l], f.volume0[i], f.corrected, work, Q);
        f.work[i] += work;
        for (int e = 0; e < 9; ++e)
        {
          tensor(f.stress, i)[e] = s[e];
          tensor(f.F, i)[e]      = b.F[e][l];
          tensor(f.F_prev, i)[e] = b.F[e][l];
          tensor(f.Q, i)[e]      = Q[e];
        }
        f.volume[i]  = f.volume0[i] * b.J[l];
        f.density[i] = f.mass[i] / f.volume[i];
      }
    }

    using avx2::v4;

    /// The 9 entries of the tensors of particles idx[0..3] as lanes.
    SPH_AVX2 void load_lanes(const double *base, const std::int32_t *idx, v4 *out)
    {
      const double *r[lanes];
      for (int l = 0; l < lanes; ++l)
        r[l] = tensor(base, idx[l]);
      avx2::transpose_load(r[0], r[1], r[2], r[3], out);
      avx2::transpose_load(r[0] + 4, r[1] + 4, r[2] + 4, r[3] + 4, out + 4);
      out[8] = _mm256_set_pd(r[3][8], r[2][8], r[1][8], r[0][8]);
    }

    /// Writes lanes 0..n_valid-1 of the 9 entries to the tensors of particles idx[l].
    SPH_AVX2 void store_lanes(const v4 *in, const std::int32_t *idx, const int n_valid,
                              double *base)
    {
      v4 lo[4], hi[4];
      avx2::transpose(in[0], in[1], in[2], in[3], lo); // lo[l] = entries 0..3 of lane l
      avx2::transpose(in[4], in[5], in[6], in[7], hi);
      alignas(32) double last[lanes];
      _mm256_store_pd(last, in[8]);
      for (int l = 0; l < n_valid; ++l)
      {
        double *t = tensor(base, idx[l]);
        _mm256_storeu_pd(t, lo[l]);
        _mm256_storeu_pd(t + 4, hi[l]);
        t[8] = last[l];
      }
    }

    __attribute__((target("avx2,fma"))) void kinematics_avx2(const Fields &f, Batch &b)
    {
      v4 A[9], L[9], Fp[9], s[9], F[9], de[9], rot[9], trial[9], C[9], J;
      load_lanes(f.F, b.idx, A);
      load_lanes(f.L, b.idx, L);
      load_lanes(f.F_prev, b.idx, Fp);
      load_lanes(f.stress, b.idx, s);
      kinematics_of(A, L, Fp, s, f.two_G, f.lambda, F, de, rot, trial, C, J);
      for (int e = 0; e < 9; ++e)
      {
        _mm256_store_pd(b.F[e], F[e]);
        _mm256_store_pd(b.de[e], de[e]);
        _mm256_store_pd(b.rotated[e], rot[e]);
        _mm256_store_pd(b.stress[e], trial[e]);
        _mm256_store_pd(b.C[e], C[e]);
      }
      _mm256_store_pd(b.J, J);
    }

    __attribute__((target("avx2,fma"))) void finish_avx2(const Fields &f, const Batch &b)
    {
      v4 s[9], rot[9], de[9], C[9], L[9], Q[9], F[9], work;
      for (int e = 0; e < 9; ++e)
      {
        s[e]   = _mm256_load_pd(b.stress[e]);
        rot[e] = _mm256_load_pd(b.rotated[e]);
        de[e]  = _mm256_load_pd(b.de[e]);
        C[e]   = _mm256_load_pd(b.C[e]);
        F[e]   = _mm256_load_pd(b.F[e]);
      }
      const std::int32_t *idx = b.idx;
      load_lanes(f.L, idx, L);
      const v4 V0 =
        _mm256_set_pd(f.volume0[idx[3]], f.volume0[idx[2]], f.volume0[idx[1]], f.volume0[idx[0]]);
      const v4 J = _mm256_load_pd(b.J);
      finish_of(s, rot, de, C, L, J, V0, f.corrected, work, Q);
      store_lanes(s, idx, b.n, f.stress);
      store_lanes(F, idx, b.n, f.F);
      store_lanes(F, idx, b.n, f.F_prev);
      store_lanes(Q, idx, b.n, f.Q);
      alignas(32) double w[lanes], V[lanes];
      _mm256_store_pd(w, work);
      _mm256_store_pd(V, V0 * J);
      for (int l = 0; l < b.n; ++l)
      {
        const std::int32_t i = idx[l];
        f.work[i] += w[l];
        f.volume[i]  = V[l];
        f.density[i] = f.mass[i] / V[l];
      }
    }
  } // namespace

  void kinematics(const Fields &f, const std::int32_t *idx, const int n, Batch &b, const bool simd)
  {
    for (int l = 0; l < lanes; ++l) // a short batch repeats its last particle
      b.idx[l] = idx[std::min(l, n - 1)];
    b.n = n;
    if (simd)
      kinematics_avx2(f, b);
    else
      kinematics_scalar(f, b);
  }

  void prefetch_next(const Fields &f, const std::int32_t i, const std::int32_t n,
                     const void *history, const std::size_t history_size)
  {
    if (i >= n)
      return;
    const std::int32_t last = std::min(i + lanes, n) - 1;
    // every 64-byte line that holds a byte of [from, to)
    const auto lines = [](const void *from, const void *to, const bool write) {
      const std::uintptr_t b = reinterpret_cast<std::uintptr_t>(to);
      for (std::uintptr_t a = reinterpret_cast<std::uintptr_t>(from) & ~std::uintptr_t(63); a < b;
           a += 64)
      {
        if (write)
          __builtin_prefetch(reinterpret_cast<const void *>(a), 1);
        else
          __builtin_prefetch(reinterpret_cast<const void *>(a), 0);
      }
    };
    lines(tensor(f.L, i), tensor(f.L, last + 1), false);
    lines(tensor(f.F_prev, i), tensor(f.F_prev, last + 1), true);
    lines(tensor(f.stress, i), tensor(f.stress, last + 1), true);
    lines(tensor(f.Q, i), tensor(f.Q, last + 1), true);
    for (const double *a : {f.volume0, f.mass})
      lines(a + i, a + last + 1, false);
    for (double *a : {f.work, f.volume, f.density})
      lines(a + i, a + last + 1, true);
    const char *h = static_cast<const char *>(history);
    lines(h + history_size * i, h + history_size * (last + 1), true);
  }

  void finish(const Fields &f, const Batch &b, const bool simd)
  {
    if (simd)
      finish_avx2(f, b);
    else
      finish_scalar(f, b);
  }
} // namespace sph::stress_batch
