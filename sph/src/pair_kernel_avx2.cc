#include "avx2_util.h"
#include "pair_kernel.h"

#include <algorithm>

// Built with -ffp-contract=off (sph/CMakeLists.txt): the compiler may not fuse or reorder any of
// the operations below, so each inlined copy of pair() computes the same bits.

namespace sph::pair_kernel
{
  namespace
  {
    using avx2::lane_sum;
    using avx2::pair_vectors;
    using avx2::pair_vectors_run;
    using avx2::transpose;
    using avx2::transpose_load;
    using avx2::v4;

    /// The records of four particles, read a block of four fields at a time as lanes:
    /// block(b, out): out[k] = field b + k of particles p[0..3].
    struct Gathered
    {
      const double *r[4];
      SPH_AVX2 Gathered(const double *record, const std::int32_t *p)
      {
        for (int l = 0; l < 4; ++l)
          r[l] = record + record_size * static_cast<std::int64_t>(p[l]);
      }
      SPH_AVX2 void block(const int b, v4 *out) const
      {
        transpose_load(r[0] + b, r[1] + b, r[2] + b, r[3] + b, out);
      }
    };

    /// One particle's record in every lane, broadcast once (the same interface).
    struct Broadcast
    {
      v4 lane[record_size];
      SPH_AVX2 Broadcast(const double *record, const std::int32_t i)
      {
        const double *r = record + record_size * static_cast<std::int64_t>(i);
        for (int k = 0; k < record_size; ++k)
          lane[k] = _mm256_broadcast_sd(r + k);
      }
      SPH_AVX2 void block(const int b, v4 *out) const
      {
        for (int k = 0; k < 4; ++k)
          out[k] = lane[b + k];
      }
    };

    /// The pair data of a group of four: indices, gradients, hourglass factors; a short group
    /// (n_valid < 4) repeats its last pair in the remaining lanes.
    struct Group
    {
      std::int32_t j[4];
      v4 g[3];
      v4 factor;
      v4 valid; ///< all bits set in the lanes of real pairs
      int n_valid;
    };

    /// Group of the consecutive pairs k.. of a particle (pairs up to pe).
    SPH_AVX2 Group run_group(const double *grad_w, const double *hg_factor,
                             const std::int32_t *second, const std::int32_t k,
                             const std::int32_t pe)
    {
      Group gr;
      gr.n_valid = std::min(4, pe - k);
      if (gr.n_valid == 4)
      {
        for (int l = 0; l < 4; ++l)
          gr.j[l] = second[k + l];
        if (grad_w) // (else: the caller reads the gradients)
          pair_vectors_run(grad_w, k, gr.g);
        gr.factor = hg_factor ? _mm256_loadu_pd(hg_factor + k) : _mm256_setzero_pd();
        gr.valid  = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
      }
      else
      {
        std::int32_t p[4];
        for (int l = 0; l < 4; ++l)
        {
          p[l]    = std::min(k + l, pe - 1);
          gr.j[l] = second[p[l]];
        }
        if (grad_w)
          pair_vectors(grad_w, p, gr.g);
        gr.factor = hg_factor ? _mm256_set_pd(hg_factor[p[3]], hg_factor[p[2]], hg_factor[p[1]],
                                              hg_factor[p[0]])
                              : _mm256_setzero_pd();
        gr.valid  = _mm256_castsi256_pd(
           _mm256_cmpgt_epi64(_mm256_set1_epi64x(gr.n_valid), _mm256_set_epi64x(3, 2, 1, 0)));
      }
      return gr;
    }

    /// What pair() gives for four pairs, in lanes.
    struct Lanes4
    {
      v4 force[3]; ///< on the first particle [N]
      v4 power;    ///< viscous power [W] (<= 0)
      v4 hg_power; ///< hourglass power [W]
    };

    /// Four pairs (i side a, j side b: Gathered or Broadcast; gradients g, hourglass factors).
    /// The fields are read block by block in record order and each block is used at once (the
    /// record's order is the order of use below).
    template <typename A, typename B>
    SPH_AVX2 Lanes4 pair(const Args &arg, const A &a, const B &b, const v4 *g, const v4 factor)
    {
      namespace f   = field;
      const v4 zero = _mm256_setzero_pd(), half = _mm256_set1_pd(0.5);
      v4       ab[4], bb[4]; // the current block of each side
      static_assert(f::x == 0 && f::v == 3 && f::h == 6 && f::density == 7 && f::mass == 8 &&
                    f::volume == 9 && f::x0 == 10 && f::q == 13 && f::f == 22);

      // block 0: x, v_x; block 1: v_y, v_z, h, density
      v4 xij[3], vij[3];
      a.block(0, ab);
      b.block(0, bb);
      for (int d = 0; d < 3; ++d)
        xij[d] = _mm256_sub_pd(ab[d], bb[d]);
      vij[0] = _mm256_sub_pd(ab[3], bb[3]);
      a.block(4, ab);
      b.block(4, bb);
      vij[1] = _mm256_sub_pd(ab[0], bb[0]);
      vij[2] = _mm256_sub_pd(ab[1], bb[1]);
      v4 r2 = zero, vr = zero;
      for (int d = 0; d < 3; ++d)
      {
        r2 = _mm256_fmadd_pd(xij[d], xij[d], r2);
        vr = _mm256_fmadd_pd(vij[d], xij[d], vr);
      }
      // one division for 1/r^2 and the viscosity's two quotients: with D = r^2 + 0.01 hb^2 and
      // z = 1 / (r^2 D rho_ij), 1/r^2 = D rho_ij z, mu = hb vr / D = hb vr r^2 rho_ij z and
      // Pi = mu (beta mu - alpha c) / rho_ij = mu (beta mu - alpha c) r^2 D z
      // (r = 0 lanes are masked below)
      const v4 r2_pos = _mm256_cmp_pd(r2, zero, _CMP_GT_OQ);
      const v4 hb     = _mm256_mul_pd(half, _mm256_add_pd(ab[2], bb[2]));
      const v4 rho_ij = _mm256_mul_pd(half, _mm256_add_pd(ab[3], bb[3]));
      const v4 D      = _mm256_fmadd_pd(_mm256_set1_pd(0.01), _mm256_mul_pd(hb, hb), r2);
      const v4 r2D    = _mm256_mul_pd(r2, D);
      const v4 z      = _mm256_div_pd(_mm256_set1_pd(1.0), _mm256_mul_pd(r2D, rho_ij));
      const v4 inv_r2 = _mm256_mul_pd(_mm256_mul_pd(D, rho_ij), z);
      // block 2: mass, volume, X_x, X_y
      a.block(8, ab);
      b.block(8, bb);
      v4 s_av = zero;
      if (arg.av)
      {
        const v4 mu =
          _mm256_mul_pd(_mm256_mul_pd(hb, vr), _mm256_mul_pd(_mm256_mul_pd(r2, rho_ij), z));
        const v4 pi =
          _mm256_mul_pd(_mm256_mul_pd(mu, _mm256_fmadd_pd(_mm256_set1_pd(arg.beta), mu,
                                                          _mm256_set1_pd(-arg.alpha * arg.c))),
                        _mm256_mul_pd(r2D, z));
        // |grad W| / r = sqrt(|grad W|^2 r^2) / r^2: the square root does not wait for the
        // division (both are long-latency; they now run side by side)
        v4 gw2 = zero;
        for (int d = 0; d < 3; ++d)
          gw2 = _mm256_fmadd_pd(g[d], g[d], gw2);
        const v4 gw_r = _mm256_sqrt_pd(_mm256_mul_pd(gw2, r2));
        s_av = _mm256_mul_pd(_mm256_mul_pd(_mm256_mul_pd(ab[0], bb[0]), pi),
                             _mm256_mul_pd(gw_r, inv_r2));
        // only approaching pairs (v_ij . x_ij < 0) at distinct positions
        s_av = _mm256_and_pd(_mm256_and_pd(_mm256_cmp_pd(vr, zero, _CMP_LT_OQ), r2_pos), s_av);
      }
      const v4 vv = _mm256_mul_pd(ab[1], bb[1]);
      v4 dx0[3]; // X_j - X_i
      dx0[0] = _mm256_sub_pd(bb[2], ab[2]);
      dx0[1] = _mm256_sub_pd(bb[3], ab[3]);
      // blocks 3 to 7: X_z, Q (9, column-major: Q(r, k) at 3 k + r), F (9, the same), one unused.
      // Entry e = 0..17 of the Q, F run is field 13 + e, in block (12 + 1 + e) / 4 at lane
      // (1 + e) % 4
      v4 qs[3] = {zero, zero, zero}; // sum_k (Q_i + Q_j)(r, k) g[k]
      v4 y[3]  = {zero, zero, zero}; // sum_k (F_i + F_j)(r, k) X[k]
#pragma GCC unroll 5
      for (int blk = 12; blk < 32; blk += 4)
      {
        a.block(blk, ab);
        b.block(blk, bb);
#pragma GCC unroll 4
        for (int l = 0; l < 4; ++l)
        {
          const int e = blk + l - f::q; // position in the Q, F run
          if (e == -1)
            dx0[2] = _mm256_sub_pd(bb[l], ab[l]);
          else if (e >= 0 && e < 9)
            qs[e % 3] = _mm256_fmadd_pd(_mm256_add_pd(ab[l], bb[l]), g[e / 3], qs[e % 3]);
          else if (e >= 9 && e < 18 && arg.hg_factor)
            y[(e - 9) % 3] =
              _mm256_fmadd_pd(_mm256_add_pd(ab[l], bb[l]), dx0[(e - 9) / 3], y[(e - 9) % 3]);
        }
      }
      Lanes4 out;
      // stress: f_i = V_i V_j (Q_i + Q_j) grad W_ij
      for (int r = 0; r < 3; ++r)
        out.force[r] = _mm256_mul_pd(vv, qs[r]);
      v4 s_hg = zero;
      if (arg.hg_factor)
      {
        // e = (F_i + F_j) X / 2 + x_ij with X = X_j - X_i; s_hg = -factor (e . x_ij) / r^2
        v4 e_dot = zero;
        for (int r = 0; r < 3; ++r)
          e_dot = _mm256_fmadd_pd(_mm256_fmadd_pd(half, y[r], xij[r]), xij[r], e_dot);
        s_hg = _mm256_and_pd(
          r2_pos, _mm256_mul_pd(_mm256_mul_pd(factor, e_dot), _mm256_sub_pd(zero, inv_r2)));
      }
      const v4 s = _mm256_add_pd(s_av, s_hg);
      for (int d = 0; d < 3; ++d)
        out.force[d] = _mm256_fmadd_pd(s, xij[d], out.force[d]);
      out.power    = _mm256_mul_pd(s_av, vr);
      out.hg_power = _mm256_mul_pd(s_hg, vr);
      return out;
    }

  } // namespace

  bool avx2_available()
  {
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  }

  __attribute__((target("avx2,fma"))) double *
  particle_forces(const Args &a, const std::int32_t i, const std::int32_t pb, const std::int32_t pe,
                  const std::int32_t *second, const std::int32_t e, double *f_int, double *share,
                  double *sum)
  {
    const Broadcast la(a.record, i);
    const v4 zero = _mm256_setzero_pd();
    v4 acc[5]     = {zero, zero, zero, zero, zero};
    for (std::int32_t k = pb; k < pe; k += 4)
    {
      const Group    gr = run_group(a.grad_w, a.hg_factor, second, k, pe);
      const Gathered lb(a.record, gr.j);
      const Lanes4   r = pair(a, la, lb, gr.g, gr.factor);
      // lanes past pe repeat the last pair: they add nothing to the sums
      for (int d = 0; d < 3; ++d)
        acc[d] = _mm256_add_pd(acc[d], _mm256_and_pd(gr.valid, r.force[d]));
      acc[3] = _mm256_add_pd(acc[3], _mm256_and_pd(gr.valid, r.power));
      acc[4] = _mm256_add_pd(acc[4], _mm256_and_pd(gr.valid, r.hg_power));
      // minus the force on each second particle j < e, pair by pair (ascending p)
      v4 f[4];
      transpose(r.force[0], r.force[1], r.force[2], zero, f);
      for (int m = 0; m < gr.n_valid; ++m)
        if (gr.j[m] < e)
        {
          double *fj = f_int + 3 * static_cast<std::int64_t>(gr.j[m]);
          _mm_storeu_pd(fj, _mm_sub_pd(_mm_loadu_pd(fj), _mm256_castpd256_pd128(f[m])));
          fj[2] -= _mm_cvtsd_f64(_mm256_extractf128_pd(f[m], 1));
        }
        else // j in a later chunk: the force to the share, subtracted from f_int[j] later
        {
          _mm_storeu_pd(share, _mm256_castpd256_pd128(f[m]));
          share[2] = _mm_cvtsd_f64(_mm256_extractf128_pd(f[m], 1));
          share += 3;
        }
    }
    for (int c = 0; c < 5; ++c)
      sum[c] = lane_sum(acc[c]);
    return share;
  }

  namespace
  {
    /// Gradients of the pairs k..k+3 from the float pair data (4 floats a pair: the gradient,
    /// then the hourglass factor) as exact doubles, lanes = pairs; pairs from n_valid on repeat
    /// the last one.
    SPH_AVX2 void float_gradients(const float *pair_float, const std::int32_t k, const int n_valid,
                                  v4 *g)
    {
      v4           rows[4];
      const float *r = pair_float + 4 * static_cast<std::int64_t>(k);
      if (n_valid == 4) // 64 contiguous bytes
      {
        const __m256 a01 = _mm256_loadu_ps(r), a23 = _mm256_loadu_ps(r + 8);
        rows[0]          = _mm256_cvtps_pd(_mm256_castps256_ps128(a01));
        rows[1]          = _mm256_cvtps_pd(_mm256_extractf128_ps(a01, 1));
        rows[2]          = _mm256_cvtps_pd(_mm256_castps256_ps128(a23));
        rows[3]          = _mm256_cvtps_pd(_mm256_extractf128_ps(a23, 1));
      }
      else
        for (int l = 0; l < 4; ++l)
          rows[l] = _mm256_cvtps_pd(_mm_loadu_ps(r + 4 * std::min(l, n_valid - 1)));
      v4 cols[4];
      transpose(rows[0], rows[1], rows[2], rows[3], cols);
      for (int d = 0; d < 3; ++d)
        g[d] = cols[d];
    }

    /// One group of four pairs of particle i (position x_i, volume V0i) in particle_gradient:
    /// second particles j[0..3], gradients g; lanes from n_valid on repeat the last pair: masked
    /// out of i's sums (valid) and not scattered.
    SPH_AVX2 void gradient_group(const double *position_volume, const v4 *x_i, const v4 V0i,
                                 const std::int32_t *j, const v4 *g, const v4 valid,
                                 const int n_valid, const std::int32_t e, double *a, v4 *acc)
    {
      v4 xv[4]; // x, y, z, V0 of the four j
      transpose_load(position_volume + 4 * static_cast<std::int64_t>(j[0]),
                     position_volume + 4 * static_cast<std::int64_t>(j[1]),
                     position_volume + 4 * static_cast<std::int64_t>(j[2]),
                     position_volume + 4 * static_cast<std::int64_t>(j[3]), xv);
      v4 di[3], dj[3];
      for (int r = 0; r < 3; ++r)
      {
        const v4 d = _mm256_sub_pd(xv[r], x_i[r]);
        di[r]      = _mm256_and_pd(valid, _mm256_mul_pd(xv[3], d));
        dj[r]      = _mm256_mul_pd(V0i, d);
      }
      // entry (r, c) at 3 c + r (column-major, as Eigen stores a 3 x 3 matrix)
      v4 t[9];
      for (int cc = 0; cc < 3; ++cc)
        for (int r = 0; r < 3; ++r)
        {
          acc[3 * cc + r] = _mm256_fmadd_pd(di[r], g[cc], acc[3 * cc + r]);
          t[3 * cc + r]   = _mm256_mul_pd(dj[r], g[cc]);
        }
      v4 lo[4], hi[4];
      transpose(t[0], t[1], t[2], t[3], lo); // lo[m]: entries 0..3 of pair m
      transpose(t[4], t[5], t[6], t[7], hi); // hi[m]: entries 4..7
      alignas(32) double last[4];            // entry 8 of each pair
      _mm256_store_pd(last, t[8]);
      for (int m = 0; m < n_valid; ++m)
        if (j[m] < e) // j >= e: added by j's chunk (Body::incoming_)
        {
          double *aj = a + 9 * static_cast<std::int64_t>(j[m]);
          _mm256_storeu_pd(aj, _mm256_add_pd(_mm256_loadu_pd(aj), lo[m]));
          _mm256_storeu_pd(aj + 4, _mm256_add_pd(_mm256_loadu_pd(aj + 4), hi[m]));
          aj[8] += last[m];
        }
    }
  } // namespace

  __attribute__((target("avx2,fma"))) void
  particle_gradient(const double *position_volume, const double *grad_w, const float *pair_float,
                    const std::int32_t i, const std::int32_t pb, const std::int32_t pe,
                    const std::int32_t *second, const std::int32_t e, double *a, double *own)
  {
    const double *xi = position_volume + 4 * static_cast<std::int64_t>(i);
    const v4 x_i[3]  = {_mm256_broadcast_sd(xi), _mm256_broadcast_sd(xi + 1),
                        _mm256_broadcast_sd(xi + 2)};
    const v4 V0i     = _mm256_broadcast_sd(xi + 3);
    const v4 zero    = _mm256_setzero_pd();
    const v4 all     = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
    v4 acc[9];
    for (int k = 0; k < 9; ++k)
      acc[k] = zero;
    std::int32_t k = pb;
    for (; k + 4 <= pe; k += 4) // whole groups: contiguous loads, no masks
    {
      v4 g[3];
      if (pair_float)
        float_gradients(pair_float, k, 4, g);
      else
        pair_vectors_run(grad_w, k, g);
      gradient_group(position_volume, x_i, V0i, second + k, g, all, 4, e, a, acc);
    }
    if (k < pe) // the last, short group
    {
      Group gr = run_group(pair_float ? nullptr : grad_w, nullptr, second, k, pe);
      if (pair_float)
        float_gradients(pair_float, k, gr.n_valid, gr.g);
      gradient_group(position_volume, x_i, V0i, gr.j, gr.g, gr.valid, gr.n_valid, e, a, acc);
    }
    for (int c = 0; c < 9; ++c)
      own[c] = lane_sum(acc[c]);
  }

  __attribute__((target("avx2,fma"))) void
  incoming_gradient(const double *position_volume, const std::int32_t *i, const std::int32_t *j,
                    const double *g, const std::int32_t n, double *a)
  {
    const v4 sign = _mm256_set1_pd(-0.0);
    for (std::int32_t k = 0; k < n; ++k)
    {
      const double *pi = position_volume + 4 * static_cast<std::int64_t>(i[k]);
      const double *pj = position_volume + 4 * static_cast<std::int64_t>(j[k]);
      // lanes d0, d1, d2 (and a fourth, unused)
      const v4 d = _mm256_mul_pd(_mm256_xor_pd(_mm256_broadcast_sd(pi + 3), sign),
                                 _mm256_sub_pd(_mm256_loadu_pd(pi), _mm256_loadu_pd(pj)));
      // column-major entries 0..3 = (d0 g0, d1 g0, d2 g0, d0 g1), 4..7 = (d1 g1, d2 g1, d0 g2,
      // d1 g2), 8 = d2 g2
      const double *gk  = g + 3 * static_cast<std::int64_t>(k);
      const v4      d_a = _mm256_permute4x64_pd(d, _MM_SHUFFLE(0, 2, 1, 0));
      const v4      d_b = _mm256_permute4x64_pd(d, _MM_SHUFFLE(1, 0, 2, 1));
      const v4      g_a = _mm256_setr_pd(gk[0], gk[0], gk[0], gk[1]);
      const v4      g_b = _mm256_setr_pd(gk[1], gk[1], gk[2], gk[2]);
      double       *aj  = a + 9 * static_cast<std::int64_t>(j[k]);
      _mm256_storeu_pd(aj, _mm256_add_pd(_mm256_loadu_pd(aj), _mm256_mul_pd(d_a, g_a)));
      _mm256_storeu_pd(aj + 4, _mm256_add_pd(_mm256_loadu_pd(aj + 4), _mm256_mul_pd(d_b, g_b)));
      aj[8] += _mm_cvtsd_f64(_mm256_extractf128_pd(d, 1)) * gk[2];
    }
  }
} // namespace sph::pair_kernel
