#pragma once
/// @file
/// The 3-D pair force of Body::pair_forces on four pairs at once (AVX2 + FMA), for CPUs that have
/// it. Private to sph/src. Same physics as the scalar pair force in body.cc (stress, Monaghan
/// viscosity, Ganzenmueller hourglass control); the two differ by round-off only. Every pair goes
/// through one sequence of IEEE operations (the file is built without contraction), whatever its
/// lane: the results stay independent of the thread count.

#include <cstdint>

namespace sph::pair_kernel
{
  /// Offsets of a particle's fields in its record of `record_size` doubles, packed once per force
  /// pass: the four pairs' second particles are then read as eight 4 x 4 blocks and transposed.
  namespace field
  {
    enum : int
    {
      // in the order the pair force uses them: each block of four is transposed just before
      // its use, so few of the 32 lanes are live at once
      x           = 0,  ///< position [m]
      v           = 3,  ///< velocity [m/s]
      h           = 6,  ///< smoothing length [m]
      density     = 7,  ///< [kg/m^3]
      mass        = 8,  ///< [kg]
      volume      = 9,  ///< V0 (TL) or V (UL) [m^3]
      x0          = 10, ///< reference position [m]
      q           = 13, ///< Q = P L (TL) or sigma L (UL), column-major [Pa]
      f           = 22, ///< deformation gradient F, column-major [-]
      record_size = 32
    };
  } // namespace field
  using field::record_size;

  /// What the pair force reads besides the records.
  struct Args
  {
    const double *record    = nullptr; ///< record_size doubles per particle
    const double *grad_w    = nullptr; ///< 3 per pair: grad_i W_ij
    const double *hg_factor = nullptr; ///< 1 per pair; nullptr: no hourglass control
    double alpha = 0, beta = 0;        ///< Monaghan viscosity coefficients [-]
    double c = 0;                      ///< sound speed of the viscosity [m/s]
    bool av  = false;                  ///< viscosity on
  };

  /// Output per pair: force on the first particle (3) [N], viscous power, hourglass power [W].
  constexpr int out_size = 5;

  /// True where the CPU runs AVX2 and FMA.
  bool avx2_available();

  /// The pairs [pb, pe) of particle i (consecutive, second particle second[p]), four at a time:
  /// subtracts the force on i of each pair from its second particle's f_int (3 per particle)
  /// where j < e, pair by pair in pair order, and writes the force on i of each pair whose
  /// j >= e to share (3 doubles each, in pair order; returns the end of what it wrote). Sums
  /// over all the pairs the force on i (sum[0..2]), the viscous and the hourglass power (sum[3],
  /// sum[4]), each in a fixed order (4 lanes).
  double *particle_forces(const Args &a, std::int32_t i, std::int32_t pb, std::int32_t pe,
                          const std::int32_t *second, std::int32_t e, double *f_int, double *share,
                          double *sum);

  /// The deformation-gradient sums of total Lagrangian SPH over the pairs [pb, pe) of particle i
  /// (A_i = sum_j V0_j (x_j - x_i) (x) grad_i W_ij, column-major), four pairs at a time.
  /// position_volume holds (x, V0) per particle (4 doubles). Adds the share of each second
  /// particle j < e, V0_i (x_j - x_i) (x) g, to a[9 j ..] in pair order (a product rounded, then
  /// one addition per entry, as Body adds the shares of pairs from earlier chunks); returns i's own sum in own[0..8]
  /// (a fixed order: lanes, then lane sums).
  /// The gradients are read from grad_w (3 doubles per pair) or, where pair_float is not null,
  /// from its 4 floats per pair (the gradient, then the hourglass factor; mixed precision, whose
  /// gradients are floats: 16 bytes a pair to stream instead of 24, the same values).
  void particle_gradient(const double *position_volume, const double *grad_w,
                         const float *pair_float, std::int32_t i, std::int32_t pb,
                         std::int32_t pe, const std::int32_t *second, std::int32_t e, double *a,
                         double *own);

  /// The terms of the pairs k in [0, n) in the deformation-gradient sums of their second
  /// particles, in order: a[9 j[k] ..] += d (x) g_k with d = -V0_i (x_i - x_j) (= V0_i (x_j -
  /// x_i)), i = i[k], g_k = g[3 k .. 3 k + 2]; position_volume as in particle_gradient. The
  /// same products and sums as Body's scalar loop over the pairs from earlier chunks.
  void incoming_gradient(const double *position_volume, const std::int32_t *i,
                         const std::int32_t *j, const double *g, std::int32_t n, double *a);
} // namespace sph::pair_kernel
