#pragma once
/// @file
/// The 3 x 3 tensor algebra of the stress updates as templates on the number type: T = double
/// for one tensor, or a vector register (__m256d, one tensor per lane; stress_batch.cc). Tensors
/// are 9 values, column-major as Eigen stores a Matrix3d. Private to sph/src. Every caller gets
/// the same sequence of IEEE operations (the same bits wherever no contraction is made).

namespace sph::tensor3
{
  /// Entry (r, c) of a column-major 3 x 3 tensor.
  constexpr int at(const int r, const int c)
  {
    return r + 3 * c;
  }

  /// Cofactor matrix cof(m) = det(m) m^{-T}, without a division (cyclic index form); det(m) is
  /// the dot product of a row of m with the same row of cof(m).
  template <typename T>
  __attribute__((always_inline)) inline void cofactor(const T *m, T *out)
  {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
      {
        const int r1 = (r + 1) % 3, r2 = (r + 2) % 3, c1 = (c + 1) % 3, c2 = (c + 2) % 3;
        out[at(r, c)] = m[at(r1, c1)] * m[at(r2, c2)] - m[at(r1, c2)] * m[at(r2, c1)];
      }
  }

  /// Hughes-Winget rotation R = (I - w/2)^{-1} (I + w/2) of the spin increment w (antisymmetric),
  /// in closed form (Cayley transform): with w/2 = A = [a]_x (A v = a x v) and A^3 = -|a|^2 A,
  /// R = I + 2 (A + A^2) / (1 + |a|^2), A^2 = a a^T - |a|^2 I. No inverse, no division by a
  /// determinant.
  template <typename T>
  __attribute__((always_inline)) inline void hughes_winget(const T *w, T *R)
  {
    const T a[3] = {0.5 * w[at(2, 1)], 0.5 * w[at(0, 2)], 0.5 * w[at(1, 0)]};
    const T a2   = (a[0] * a[0] + a[1] * a[1]) + a[2] * a[2];
    const T k    = 2.0 / (1.0 + a2);
    const T diag = 1.0 - k * a2;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
      {
        R[at(r, c)] = k * (0.5 * w[at(r, c)] + a[r] * a[c]);
        if (r == c)
          R[at(r, c)] = R[at(r, c)] + diag;
      }
  }
} // namespace sph::tensor3
