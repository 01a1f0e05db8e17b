#include "avx2_util.h"
#include "pair_kernel_mixed.h"

#include <algorithm>

// Built with -ffp-contract=off (sph/CMakeLists.txt), as pair_kernel_avx2.cc: each inlined copy of
// pair() computes the same bits.

namespace sph::pair_kernel::mixed
{
  namespace
  {
    using avx2::lane_sum;
    using avx2::transpose;
    using avx2::v4;
    using v8 = __m256;

    /// out[k] = float k of each 128-bit half of t[0..3], t[m] holding row m (low half) and row
    /// m + 4 (high half): a 4 x 4 transpose inside each half.
    SPH_AVX2 void transpose_halves(const v8 *t, v8 *out)
    {
      const v8 u0 = _mm256_unpacklo_ps(t[0], t[1]); // 0 of rows 0 1, 1 of rows 0 1 | rows 4 5
      const v8 u1 = _mm256_unpackhi_ps(t[0], t[1]); // 2 of rows 0 1, 3 of rows 0 1 | ..
      const v8 u2 = _mm256_unpacklo_ps(t[2], t[3]);
      const v8 u3 = _mm256_unpackhi_ps(t[2], t[3]);
      out[0]      = _mm256_shuffle_ps(u0, u2, 0x44);
      out[1]      = _mm256_shuffle_ps(u0, u2, 0xEE);
      out[2]      = _mm256_shuffle_ps(u1, u3, 0x44);
      out[3]      = _mm256_shuffle_ps(u1, u3, 0xEE);
    }

    /// Floats b..b+3 of the eight rows r[0..7] as lanes: out[k] = (r[0][b + k], .., r[7][b + k]).
    /// Eight 16-byte loads, two per register, and transpose_halves.
    SPH_AVX2 void transpose_block(const float *const *r, const int b, v8 *out)
    {
      v8 t[4]; // t[k] = floats b..b+3 of row k (low half) and of row k + 4 (high half)
      for (int k = 0; k < 4; ++k)
        t[k] = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(r[k] + b)),
                                    _mm_loadu_ps(r[k + 4] + b), 1);
      transpose_halves(t, out);
    }

    /// One particle's record in every lane.
    SPH_AVX2 void broadcast(const float *record, const std::int32_t i, v8 *lane)
    {
      const float *r = record + float_size * static_cast<std::int64_t>(i);
      for (int k = 0; k < float_size; ++k)
        lane[k] = _mm256_broadcast_ss(r + k);
    }

    /// The exact double values of eight floats, in two groups of four.
    SPH_AVX2 void widen(const v8 x, v4 &lo, v4 &hi)
    {
      lo = _mm256_cvtps_pd(_mm256_castps256_ps128(x));
      hi = _mm256_cvtps_pd(_mm256_extractf128_ps(x, 1));
    }

    /// Per-pair data of eight pairs: g[0..2] = grad_i W_ij, g[3] = hourglass factor.
    SPH_AVX2 void pair_data(const float *pair, const std::int32_t *p, v8 *g)
    {
      const float *r[8];
      for (int l = 0; l < 8; ++l)
        r[l] = pair + pair_size * static_cast<std::int64_t>(p[l]);
      transpose_block(r, 0, g);
    }

    /// The same for the eight consecutive pairs k..k+7: four 32-byte loads and the same
    /// transpose (the same values as pair_data).
    SPH_AVX2 void pair_data_run(const float *pair, const std::int32_t k, v8 *g)
    {
      const float *r  = pair + pair_size * static_cast<std::int64_t>(k);
      const v8     a0 = _mm256_loadu_ps(r), a1 = _mm256_loadu_ps(r + 8); // pairs 0 1, 2 3
      const v8     a2 = _mm256_loadu_ps(r + 16), a3 = _mm256_loadu_ps(r + 24); // 4 5, 6 7
      v8 t[4]; // t[m] = pair m (low half) and pair m + 4 (high half)
      t[0]        = _mm256_permute2f128_ps(a0, a2, 0x20);
      t[1]        = _mm256_permute2f128_ps(a0, a2, 0x31);
      t[2]        = _mm256_permute2f128_ps(a1, a3, 0x20);
      t[3]        = _mm256_permute2f128_ps(a1, a3, 0x31);
      transpose_halves(t, g);
    }

    /// What pair() gives for eight pairs, in lanes.
    struct Lanes8
    {
      v8 force[3]; ///< on the first particle [N]
      v8 power;    ///< viscous power [W] (<= 0)
      v8 hg_power; ///< hourglass power [W]
    };

    /// The records of eight particles, read a block of four fields at a time as lanes.
    struct Gathered
    {
      const float *r[8];
      SPH_AVX2 Gathered(const float *record, const std::int32_t *p)
      {
        for (int l = 0; l < 8; ++l)
          r[l] = record + float_size * static_cast<std::int64_t>(p[l]);
      }
      SPH_AVX2 void block(const int b, v8 *out) const { transpose_block(r, b, out); }
    };

    /// One particle's record in every lane, broadcast once (the same interface).
    struct Broadcast
    {
      v8 lane[float_size];
      SPH_AVX2 Broadcast(const float *record, const std::int32_t i) { broadcast(record, i, lane); }
      SPH_AVX2 void block(const int b, v8 *out) const
      {
        for (int k = 0; k < 4; ++k)
          out[k] = lane[b + k];
      }
    };

    /// Eight pairs (i side a, j side b: Gathered or Broadcast; g[0..2] gradients, g[3] hourglass
    /// factors): the terms of pair_kernel_avx2.cc's pair() in single precision. The record's
    /// blocks are read in order and each is used at once (field order = order of use).
    template <typename A, typename B>
    SPH_AVX2 Lanes8 pair(const Args &arg, const A &a, const B &b, const v8 *g)
    {
      namespace f   = field;
      const v8 zero = _mm256_setzero_ps(), half = _mm256_set1_ps(0.5f);
      static_assert(f::u == 0 && f::x0 == 3 && f::v == 6 && f::h == 9 && f::density == 10 &&
                    f::mass == 11 && f::volume == 12 && f::q == 13 && f::h_grad == 22);
      v8 ab[4], bb[4]; // the current block of each side
      // u_ij = u_i - u_j, X = X_j - X_i, x_ij = u_ij - X
      v8 uij[3], dX[3], xij[3], vij[3];
      a.block(0, ab); // u, X_x
      b.block(0, bb);
      for (int d = 0; d < 3; ++d)
        uij[d] = _mm256_sub_ps(ab[d], bb[d]);
      dX[0] = _mm256_sub_ps(bb[3], ab[3]);
      a.block(4, ab); // X_y, X_z, v_x, v_y
      b.block(4, bb);
      dX[1]  = _mm256_sub_ps(bb[0], ab[0]);
      dX[2]  = _mm256_sub_ps(bb[1], ab[1]);
      vij[0] = _mm256_sub_ps(ab[2], bb[2]);
      vij[1] = _mm256_sub_ps(ab[3], bb[3]);
      a.block(8, ab); // v_z, h, density, mass
      b.block(8, bb);
      vij[2] = _mm256_sub_ps(ab[0], bb[0]);
      v8 r2 = zero, vr = zero;
      for (int d = 0; d < 3; ++d)
      {
        xij[d] = _mm256_sub_ps(uij[d], dX[d]);
        r2     = _mm256_fmadd_ps(xij[d], xij[d], r2);
        vr     = _mm256_fmadd_ps(vij[d], xij[d], vr);
      }
      // one division for 1/r^2 and the viscosity's quotients (see pair_kernel_avx2.cc)
      const v8 r2_pos = _mm256_cmp_ps(r2, zero, _CMP_GT_OQ);
      const v8 hb     = _mm256_mul_ps(half, _mm256_add_ps(ab[1], bb[1]));
      const v8 rho_ij = _mm256_mul_ps(half, _mm256_add_ps(ab[2], bb[2]));
      const v8 D      = _mm256_fmadd_ps(_mm256_set1_ps(0.01f), _mm256_mul_ps(hb, hb), r2);
      const v8 r2D    = _mm256_mul_ps(r2, D);
      const v8 z      = _mm256_div_ps(_mm256_set1_ps(1.0f), _mm256_mul_ps(r2D, rho_ij));
      const v8 inv_r2 = _mm256_mul_ps(_mm256_mul_ps(D, rho_ij), z);
      v8 s_av         = zero;
      if (arg.av)
      {
        const v8 mu =
          _mm256_mul_ps(_mm256_mul_ps(hb, vr), _mm256_mul_ps(_mm256_mul_ps(r2, rho_ij), z));
        const v8 pi = _mm256_mul_ps(
          _mm256_mul_ps(mu, _mm256_fmadd_ps(_mm256_set1_ps(static_cast<float>(arg.beta)), mu,
                                            _mm256_set1_ps(static_cast<float>(-arg.alpha * arg.c)))),
          _mm256_mul_ps(r2D, z));
        v8 gw2 = zero;
        for (int d = 0; d < 3; ++d)
          gw2 = _mm256_fmadd_ps(g[d], g[d], gw2);
        const v8 gw_r = _mm256_sqrt_ps(_mm256_mul_ps(gw2, r2));
        s_av = _mm256_mul_ps(_mm256_mul_ps(_mm256_mul_ps(ab[3], bb[3]), pi),
                             _mm256_mul_ps(gw_r, inv_r2));
        // only approaching pairs (v_ij . x_ij < 0) at distinct positions
        s_av = _mm256_and_ps(_mm256_and_ps(_mm256_cmp_ps(vr, zero, _CMP_LT_OQ), r2_pos), s_av);
      }
      // blocks 3 to 7: V, Q (9, column-major: Q(r, k) at 3 k + r), H (9, the same), one unused
      v8 vv    = zero;
      v8 qs[3] = {zero, zero, zero}; // sum_k (Q_i + Q_j)(r, k) g[k]
      v8 y[3]  = {zero, zero, zero}; // sum_k (H_i + H_j)(r, k) X[k]
#pragma GCC unroll 5
      for (int blk = 12; blk < float_size; blk += 4)
      {
        a.block(blk, ab);
        b.block(blk, bb);
#pragma GCC unroll 4
        for (int l = 0; l < 4; ++l)
        {
          const int e = blk + l - f::q; // position in the Q, H run
          if (e == -1)
            vv = _mm256_mul_ps(ab[l], bb[l]);
          else if (e >= 0 && e < 9)
            qs[e % 3] = _mm256_fmadd_ps(_mm256_add_ps(ab[l], bb[l]), g[e / 3], qs[e % 3]);
          else if (e >= 9 && e < 18 && arg.hourglass)
            y[(e - 9) % 3] =
              _mm256_fmadd_ps(_mm256_add_ps(ab[l], bb[l]), dX[(e - 9) / 3], y[(e - 9) % 3]);
        }
      }
      Lanes8 out;
      // stress: f_i = V_i V_j (Q_i + Q_j) grad W_ij
      for (int r = 0; r < 3; ++r)
        out.force[r] = _mm256_mul_ps(vv, qs[r]);
      v8 s_hg = zero;
      if (arg.hourglass)
      {
        // e = (F_i + F_j) X / 2 + x_ij = (H_i + H_j) X / 2 + u_ij (F = I + H, X = X_j - X_i,
        // u_ij = x_ij + X); s_hg = -factor (e . x_ij) / r^2
        v8 e_dot = zero;
        for (int r = 0; r < 3; ++r)
          e_dot = _mm256_fmadd_ps(_mm256_fmadd_ps(half, y[r], uij[r]), xij[r], e_dot);
        s_hg = _mm256_and_ps(
          r2_pos, _mm256_mul_ps(_mm256_mul_ps(g[3], e_dot), _mm256_sub_ps(zero, inv_r2)));
      }
      const v8 s = _mm256_add_ps(s_av, s_hg);
      for (int d = 0; d < 3; ++d)
        out.force[d] = _mm256_fmadd_ps(s, xij[d], out.force[d]);
      out.power    = _mm256_mul_ps(s_av, vr);
      out.hg_power = _mm256_mul_ps(s_hg, vr);
      return out;
    }
  } // namespace

  __attribute__((target("avx2,fma"))) double *
  particle_forces(const Args &a, const std::int32_t i, const std::int32_t pb, const std::int32_t pe,
                  const std::int32_t *second, const std::int32_t e, double *f_int, double *share,
                  double *sum)
  {
    const Broadcast la(a.record, i);
    const v4 zero = _mm256_setzero_pd();
    const __m256i lane_index = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    v4 acc[5]     = {zero, zero, zero, zero, zero};
    for (std::int32_t k = pb; k < pe; k += 8)
    {
      // a short group (fewer than 8 pairs left) repeats its last pair in the remaining lanes
      const int    n_valid = std::min(8, pe - k);
      std::int32_t p[8], j[8];
      for (int l = 0; l < 8; ++l)
      {
        p[l] = std::min(k + l, pe - 1);
        j[l] = second[p[l]];
      }
      const v8 valid =
        _mm256_castsi256_ps(_mm256_cmpgt_epi32(_mm256_set1_epi32(n_valid), lane_index));
      v8 g[pair_size];
      if (n_valid == 8)
        pair_data_run(a.pair, k, g);
      else
        pair_data(a.pair, p, g);
      const Gathered lb(a.record, j);
      const Lanes8   r = pair(a, la, lb, g);
      // the sums on i in double, lanes past pe masked (a whole group has none: it adds the
      // forces widened for the scatter below, the same values, one conversion fewer)
      v4 f_lo[3], f_hi[3];
      for (int d = 0; d < 3; ++d)
        widen(r.force[d], f_lo[d], f_hi[d]);
      const v8 out[5] = {r.force[0], r.force[1], r.force[2], r.power, r.hg_power};
      for (int c = 0; c < 5; ++c)
      {
        v4 lo, hi;
        if (c < 3 && n_valid == 8)
          lo = f_lo[c], hi = f_hi[c];
        else
          widen(_mm256_and_ps(valid, out[c]), lo, hi);
        acc[c] = _mm256_add_pd(_mm256_add_pd(acc[c], lo), hi);
      }
      // minus the force on each second particle j < e, pair by pair (ascending p)
      v4 f[8];
      transpose(f_lo[0], f_lo[1], f_lo[2], zero, f);
      transpose(f_hi[0], f_hi[1], f_hi[2], zero, f + 4);
      for (int m = 0; m < n_valid; ++m)
        if (j[m] < e)
        {
          double *fj = f_int + 3 * static_cast<std::int64_t>(j[m]);
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
} // namespace sph::pair_kernel::mixed
