#pragma once
/// @file
/// Small AVX2 helpers of the vectorised pair kernels (pair_kernel_avx2.cc, pair_kernel_mixed.cc):
/// 4 x 4 transposes of doubles and per-pair vector loads. Private to sph/src; every function is
/// compiled for AVX2 + FMA and always inlined into a function that is.

#include <immintrin.h>

#include <cstdint>

#define SPH_AVX2 __attribute__((target("avx2,fma"), always_inline)) inline

namespace sph::avx2
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

  /// Sum of the four lanes, in one fixed order.
  SPH_AVX2 double lane_sum(const v4 s)
  {
    alignas(32) double l[4];
    _mm256_store_pd(l, s);
    return (l[0] + l[1]) + (l[2] + l[3]);
  }
} // namespace sph::avx2
