#include "pair_kernel.h"

#include <immintrin.h>

#include <algorithm>

// Built with -ffp-contract=off (sph/CMakeLists.txt): the compiler may not fuse or reorder any of
// the operations below, so each inlined copy of pair() computes the same bits.
#define SPH_AVX2 __attribute__((target("avx2,fma"), always_inline)) inline

namespace sph::pair_kernel
{
  namespace
  {
    using v4 = __m256d;

    /// Columns of the 4 x 4 block (r0..r3 as rows): out[k] = (r0[k], r1[k], r2[k], r3[k]).
    SPH_AVX2 void transpose(const v4 r0, const v4 r1, const v4 r2, const v4 r3, v4 *out)
    {
      const v4 u0 = _mm256_unpacklo_pd(r0, r1); // r0[0] r1[0] r0[2] r1[2]
      const v4 u1 = _mm256_unpackhi_pd(r0, r1); // r0[1] r1[1] r0[3] r1[3]
      const v4 u2 = _mm256_unpacklo_pd(r2, r3);
      const v4 u3 = _mm256_unpackhi_pd(r2, r3);
      out[0]      = _mm256_permute2f128_pd(u0, u2, 0x20);
      out[1]      = _mm256_permute2f128_pd(u1, u3, 0x20);
      out[2]      = _mm256_permute2f128_pd(u0, u2, 0x31);
      out[3]      = _mm256_permute2f128_pd(u1, u3, 0x31);
    }

    /// Columns of the 4 x 4 block whose rows start at r0..r3 in memory: out[k] = (r0[k], r1[k],
    /// r2[k], r3[k]). Half-row loads merged by vinsertf128 and one unpack per column: no
    /// cross-lane permutes.
    SPH_AVX2 void transpose_load(const double *r0, const double *r1, const double *r2,
                                 const double *r3, v4 *out)
    {
      const v4 t0 = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(r0)), _mm_loadu_pd(r2),
                                         1); // r0[0] r0[1] r2[0] r2[1]
      const v4 t1 =
        _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(r1)), _mm_loadu_pd(r3), 1);
      const v4 t2 =
        _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(r0 + 2)), _mm_loadu_pd(r2 + 2), 1);
      const v4 t3 =
        _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(r1 + 2)), _mm_loadu_pd(r3 + 2), 1);
      out[0] = _mm256_unpacklo_pd(t0, t1);
      out[1] = _mm256_unpackhi_pd(t0, t1);
      out[2] = _mm256_unpacklo_pd(t2, t3);
      out[3] = _mm256_unpackhi_pd(t2, t3);
    }

    /// The records of four particles as lanes: lane[k] = field k of particles p[0..3].
    SPH_AVX2 void gather(const double *record, const std::int32_t *p, v4 *lane)
    {
      const double *r0 = record + record_size * static_cast<std::int64_t>(p[0]);
      const double *r1 = record + record_size * static_cast<std::int64_t>(p[1]);
      const double *r2 = record + record_size * static_cast<std::int64_t>(p[2]);
      const double *r3 = record + record_size * static_cast<std::int64_t>(p[3]);
      for (int b = 0; b < record_size; b += 4)
        transpose_load(r0 + b, r1 + b, r2 + b, r3 + b, lane + b);
    }

    /// One particle's record in every lane.
    SPH_AVX2 void broadcast(const double *record, const std::int32_t i, v4 *lane)
    {
      const double *r = record + record_size * static_cast<std::int64_t>(i);
      for (int k = 0; k < record_size; ++k)
        lane[k] = _mm256_broadcast_sd(r + k);
    }

    /// Per-pair vectors of four pairs p[0..3] as lanes: out[d] = (v[p0][d], .., v[p3][d]).
    SPH_AVX2 void pair_vectors(const double *v, const std::int32_t *p, v4 *out)
    {
      const double *q[4] = {
        v + 3 * static_cast<std::int64_t>(p[0]), v + 3 * static_cast<std::int64_t>(p[1]),
        v + 3 * static_cast<std::int64_t>(p[2]), v + 3 * static_cast<std::int64_t>(p[3])};
      for (int d = 0; d < 3; ++d)
        out[d] = _mm256_set_pd(q[3][d], q[2][d], q[1][d], q[0][d]);
    }

    /// The same for four consecutive pairs k..k+3: three loads and eight shuffles.
    SPH_AVX2 void pair_vectors_run(const double *v, const std::int64_t k, v4 *out)
    {
      const v4 a  = _mm256_loadu_pd(v + 3 * k);           // 0x 0y 0z 1x
      const v4 b  = _mm256_loadu_pd(v + 3 * k + 4);       // 1y 1z 2x 2y
      const v4 c  = _mm256_loadu_pd(v + 3 * k + 8);       // 2z 3x 3y 3z
      const v4 m1 = _mm256_permute2f128_pd(a, b, 0x21);   // 0z 1x 1y 1z
      const v4 m2 = _mm256_permute2f128_pd(b, c, 0x21);   // 2x 2y 2z 3x
      const v4 A  = _mm256_permute2f128_pd(a, m2, 0x20);  // 0x 0y 2x 2y
      const v4 B  = _mm256_permute2f128_pd(m1, m2, 0x30); // 0z 1x 2z 3x
      const v4 C  = _mm256_permute2f128_pd(m1, c, 0x31);  // 1y 1z 3y 3z
      out[0]      = _mm256_shuffle_pd(A, B, 0xA);
      out[1]      = _mm256_shuffle_pd(A, C, 0x5);
      out[2]      = _mm256_shuffle_pd(B, C, 0xA);
    }

    /// The pair data of a group of four: indices, gradients, hourglass factors; a short group
    /// (n_valid < 4) repeats its last pair in the remaining lanes.
    struct Group
    {
      std::int32_t p[4], j[4];
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
        {
          gr.p[l] = k + l;
          gr.j[l] = second[k + l];
        }
        pair_vectors_run(grad_w, k, gr.g);
        gr.factor = hg_factor ? _mm256_loadu_pd(hg_factor + k) : _mm256_setzero_pd();
        gr.valid  = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
      }
      else
      {
        for (int l = 0; l < 4; ++l)
        {
          gr.p[l] = std::min(k + l, pe - 1);
          gr.j[l] = second[gr.p[l]];
        }
        pair_vectors(grad_w, gr.p, gr.g);
        gr.factor = hg_factor ? _mm256_set_pd(hg_factor[gr.p[3]], hg_factor[gr.p[2]],
                                              hg_factor[gr.p[1]], hg_factor[gr.p[0]])
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

    /// Four pairs (i lanes a, j lanes b, gradients g, hourglass factors).
    SPH_AVX2 Lanes4 pair(const Args &arg, const v4 *a, const v4 *b, const v4 *g, const v4 factor)
    {
      const v4 zero = _mm256_setzero_pd(), half = _mm256_set1_pd(0.5);

      v4 xij[3], r2 = zero, vr = zero;
      for (int d = 0; d < 3; ++d)
      {
        xij[d]       = _mm256_sub_pd(a[field::x + d], b[field::x + d]);
        const v4 vij = _mm256_sub_pd(a[field::v + d], b[field::v + d]);
        r2           = _mm256_fmadd_pd(xij[d], xij[d], r2);
        vr           = _mm256_fmadd_pd(vij, xij[d], vr);
      }
      Lanes4 out;
      // stress: f_i = V_i V_j (Q_i + Q_j) grad W_ij (Q column-major: Q(r, k) at 3 k + r)
      const v4 vv = _mm256_mul_pd(a[field::volume], b[field::volume]);
      for (int r = 0; r < 3; ++r)
      {
        v4 s = zero;
        for (int k = 0; k < 3; ++k)
          s = _mm256_fmadd_pd(_mm256_add_pd(a[field::q + 3 * k + r], b[field::q + 3 * k + r]), g[k],
                              s);
        out.force[r] = _mm256_mul_pd(vv, s);
      }
      // one division for 1/r^2 and the viscosity's two quotients: with D = r^2 + 0.01 hb^2 and
      // z = 1 / (r^2 D rho_ij), 1/r^2 = D rho_ij z, mu = hb vr / D = hb vr r^2 rho_ij z and
      // Pi = mu (beta mu - alpha c) / rho_ij = mu (beta mu - alpha c) r^2 D z
      // (r = 0 lanes are masked below)
      const v4 r2_pos = _mm256_cmp_pd(r2, zero, _CMP_GT_OQ);
      const v4 hb     = _mm256_mul_pd(half, _mm256_add_pd(a[field::h], b[field::h]));
      const v4 rho_ij = _mm256_mul_pd(half, _mm256_add_pd(a[field::density], b[field::density]));
      const v4 D      = _mm256_fmadd_pd(_mm256_set1_pd(0.01), _mm256_mul_pd(hb, hb), r2);
      const v4 r2D    = _mm256_mul_pd(r2, D);
      const v4 z      = _mm256_div_pd(_mm256_set1_pd(1.0), _mm256_mul_pd(r2D, rho_ij));
      const v4 inv_r2 = _mm256_mul_pd(_mm256_mul_pd(D, rho_ij), z);
      v4 s_av         = zero;
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
        s_av = _mm256_mul_pd(_mm256_mul_pd(_mm256_mul_pd(a[field::mass], b[field::mass]), pi),
                             _mm256_mul_pd(gw_r, inv_r2));
        // only approaching pairs (v_ij . x_ij < 0) at distinct positions
        s_av = _mm256_and_pd(_mm256_and_pd(_mm256_cmp_pd(vr, zero, _CMP_LT_OQ), r2_pos), s_av);
      }
      v4 s_hg = zero;
      if (arg.hg_factor)
      {
        // e = (F_i + F_j) X / 2 + x_ij with X = X_j - X_i; s_hg = -factor (e . x_ij) / r^2
        v4 dx0[3];
        for (int k = 0; k < 3; ++k)
          dx0[k] = _mm256_sub_pd(b[field::x0 + k], a[field::x0 + k]);
        v4 e_dot = zero;
        for (int r = 0; r < 3; ++r)
        {
          v4 y = zero;
          for (int k = 0; k < 3; ++k)
            y = _mm256_fmadd_pd(_mm256_add_pd(a[field::f + 3 * k + r], b[field::f + 3 * k + r]),
                                dx0[k], y);
          e_dot = _mm256_fmadd_pd(_mm256_fmadd_pd(half, y, xij[r]), xij[r], e_dot);
        }
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

    /// Sum of the four lanes, in one fixed order.
    SPH_AVX2 double lane_sum(const v4 s)
    {
      alignas(32) double l[4];
      _mm256_store_pd(l, s);
      return (l[0] + l[1]) + (l[2] + l[3]);
    }
  } // namespace

  bool avx2_available()
  {
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  }

  __attribute__((target("avx2,fma"))) void list_forces(const Args &a, const std::int32_t *list,
                                                       const int n, const std::int32_t *first,
                                                       const std::int32_t *second, double *out)
  {
    v4 la[record_size], lb[record_size];
    for (int k = 0; k < n; k += 4)
    {
      // a short last group repeats its last pair; those lanes' outputs are not read
      std::int32_t p[4], i[4], j[4];
      for (int l = 0; l < 4; ++l)
      {
        p[l] = list[std::min(k + l, n - 1)];
        i[l] = first[p[l]];
        j[l] = second[p[l]];
      }
      gather(a.record, i, la);
      gather(a.record, j, lb);
      v4 g[3];
      pair_vectors(a.grad_w, p, g);
      const v4 factor = a.hg_factor ? _mm256_set_pd(a.hg_factor[p[3]], a.hg_factor[p[2]],
                                                    a.hg_factor[p[1]], a.hg_factor[p[0]])
                                    : _mm256_setzero_pd();
      const Lanes4 r  = pair(a, la, lb, g, factor);
      // out[5 m .. 5 m + 3] = (force, viscous power) of pair k + m, out[5 m + 4] its
      // hourglass power
      v4 rows[4];
      transpose(r.force[0], r.force[1], r.force[2], r.power, rows);
      alignas(32) double hp[4];
      _mm256_store_pd(hp, r.hg_power);
      double *o = out + out_size * k;
      for (int m = 0; m < 4; ++m)
      {
        _mm256_storeu_pd(o + out_size * m, rows[m]);
        o[out_size * m + 4] = hp[m];
      }
    }
  }

  __attribute__((target("avx2,fma"))) void
  particle_forces(const Args &a, const std::int32_t i, const std::int32_t pb, const std::int32_t pe,
                  const std::int32_t *second, const std::int32_t e, double *f_int, double *sum)
  {
    v4 la[record_size], lb[record_size];
    broadcast(a.record, i, la);
    const v4 zero = _mm256_setzero_pd();
    v4 acc[5]     = {zero, zero, zero, zero, zero};
    for (std::int32_t k = pb; k < pe; k += 4)
    {
      const Group gr = run_group(a.grad_w, a.hg_factor, second, k, pe);
      gather(a.record, gr.j, lb);
      const Lanes4 r = pair(a, la, lb, gr.g, gr.factor);
      // lanes past pe repeat the last pair: they add nothing to the sums
      for (int d = 0; d < 3; ++d)
        acc[d] = _mm256_add_pd(acc[d], _mm256_and_pd(gr.valid, r.force[d]));
      acc[3] = _mm256_add_pd(acc[3], _mm256_and_pd(gr.valid, r.power));
      acc[4] = _mm256_add_pd(acc[4], _mm256_and_pd(gr.valid, r.hg_power));
      // minus the force on each second particle j < e, pair by pair (ascending p)
      v4 f[4];
      transpose(r.force[0], r.force[1], r.force[2], zero, f);
      for (int m = 0; m < gr.n_valid; ++m)
        if (gr.j[m] < e) // else: subtracted by j's owner (cross-range share)
        {
          double *fj = f_int + 3 * static_cast<std::int64_t>(gr.j[m]);
          _mm_storeu_pd(fj, _mm_sub_pd(_mm_loadu_pd(fj), _mm256_castpd256_pd128(f[m])));
          fj[2] -= _mm_cvtsd_f64(_mm256_extractf128_pd(f[m], 1));
        }
    }
    for (int c = 0; c < 5; ++c)
      sum[c] = lane_sum(acc[c]);
  }

  __attribute__((target("avx2,fma"))) void
  particle_gradient(const double *position_volume, const double *grad_w, const std::int32_t i,
                    const std::int32_t pb, const std::int32_t pe, const std::int32_t *second,
                    const std::int32_t e, double *a, double *own)
  {
    const double *xi = position_volume + 4 * static_cast<std::int64_t>(i);
    const v4 x_i[3]  = {_mm256_broadcast_sd(xi), _mm256_broadcast_sd(xi + 1),
                        _mm256_broadcast_sd(xi + 2)};
    const v4 V0i     = _mm256_broadcast_sd(xi + 3);
    const v4 zero    = _mm256_setzero_pd();
    v4 acc[9];
    for (int k = 0; k < 9; ++k)
      acc[k] = zero;
    for (std::int32_t k = pb; k < pe; k += 4)
    {
      const Group gr        = run_group(grad_w, nullptr, second, k, pe);
      const std::int32_t *j = gr.j;
      const v4 *g           = gr.g;
      const v4 valid        = gr.valid;
      const int n_valid     = gr.n_valid;
      v4 xv[4]; // x, y, z, V0 of the four j
      transpose_load(position_volume + 4 * static_cast<std::int64_t>(j[0]),
                     position_volume + 4 * static_cast<std::int64_t>(j[1]),
                     position_volume + 4 * static_cast<std::int64_t>(j[2]),
                     position_volume + 4 * static_cast<std::int64_t>(j[3]), xv);
      // lanes past pe repeat the last pair: they add nothing and are not scattered
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
      alignas(32) double last[4];
      _mm256_store_pd(last, t[8]);
      for (int m = 0; m < n_valid; ++m)
        if (j[m] < e) // else: added by j's owner (cross-range share)
        {
          double *aj = a + 9 * static_cast<std::int64_t>(j[m]);
          _mm256_storeu_pd(aj, _mm256_add_pd(_mm256_loadu_pd(aj), lo[m]));
          _mm256_storeu_pd(aj + 4, _mm256_add_pd(_mm256_loadu_pd(aj + 4), hi[m]));
          aj[8] += last[m];
        }
    }
    for (int k = 0; k < 9; ++k)
      own[k] = lane_sum(acc[k]);
  }
} // namespace sph::pair_kernel
