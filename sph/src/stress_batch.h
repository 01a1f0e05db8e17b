#pragma once
/// @file
/// The kinematics and the closing algebra of the 3-D total Lagrangian stress update
/// (Body::update_stress_total_lagrangian), four particles at a time: with AVX2 one particle per
/// lane of a 256-bit register, otherwise the same operations lane by lane in scalars. Private to
/// sph/src. Both versions perform one sequence of IEEE operations per particle (the file is built
/// without contraction): a particle's results do not depend on the path, on its lane or on the
/// other particles of its batch (so not on the thread count either).
///
/// Per particle i (3 x 3 tensors column-major, as Eigen stores them):
///   F = A L^T, G = (F - F_prev) ((F + F_prev) / 2)^{-1}, de = sym G, w = skew G,
///   R = Hughes-Winget rotation of w (Cayley transform), rotated = R sigma R^T (symmetric),
///   trial = rotated + 2 G_shear de + lambda tr(de) I, C = cof F, J = det F;
/// then, with the new stress s from the rock model (trial where it is elastic):
///   work += V0 J (rotated + s) / 2 : de, P = s C, Q = P L (corrected) or P,
///   sigma = s, F = F_prev = F, V = V0 J, rho = m / V.

#include <cstddef>
#include <cstdint>

namespace sph::stress_batch
{
  constexpr int lanes = 4;

  /// The per-particle arrays the update reads and writes (3 x 3 tensors: 9 doubles each).
  struct Fields
  {
    double *F             = nullptr; ///< in: A = sum_j V0_j (x_j - x_i) (x) grad W; out: F
    const double *L       = nullptr; ///< kernel-gradient correction (identity when off)
    double *F_prev        = nullptr; ///< F of the last update (in), the new F (out)
    double *stress        = nullptr; ///< Cauchy stress [Pa]
    double *Q             = nullptr; ///< out: P L or P [Pa]
    const double *volume0 = nullptr; ///< [m^3]
    const double *mass    = nullptr; ///< [kg]
    double *volume        = nullptr; ///< out: V0 J [m^3]
    double *density       = nullptr; ///< out: m / V [kg/m^3]
    double *work          = nullptr; ///< stress work, incremented [J]
    double two_G          = 0;       ///< 2 x shear modulus [Pa]
    double lambda         = 0;       ///< K - 2G/3 [Pa]
    bool corrected        = false;   ///< Q = P L (else P)
  };

  /// One batch between the two halves, lane by lane: value e of lane l at [e][l].
  struct Batch
  {
    std::int32_t idx[lanes]; ///< the lanes' particles (a short batch repeats its last one)
    int n = 0;               ///< lanes with a particle of their own (written by finish)
    alignas(32) double F[9][lanes];
    alignas(32) double de[9][lanes];
    alignas(32) double rotated[9][lanes];
    alignas(32) double C[9][lanes];
    alignas(32) double J[lanes];
    /// The new stress: the elastic trial after kinematics; the caller replaces it where the rock
    /// model's update differs (where the trial is not surely elastic)
    alignas(32) double stress[9][lanes];
  };

  /// First half for the particles idx[0..n), 1 <= n <= 4: b.idx, b.n, F, de, rotated, C, J and
  /// the trial in b.stress. `simd`: the AVX2 version (the caller checked the CPU).
  void kinematics(const Fields &f, const std::int32_t *idx, int n, Batch &b, bool simd);

  /// Asks the memory for the fields of particles [i, i + 4) (those below n) that the next batch
  /// reads and writes, and for their history records (`history_size` bytes each from `history`).
  void prefetch_next(const Fields &f, std::int32_t i, std::int32_t n, const void *history,
                     std::size_t history_size);

  /// Second half: writes the results of b's particles (b.stress final).
  void finish(const Fields &f, const Batch &b, bool simd);
} // namespace sph::stress_batch
