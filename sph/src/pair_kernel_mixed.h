#pragma once
/// @file
/// The 3-D pair force of Body::pair_forces in mixed precision, eight pairs at once (AVX2 + FMA):
/// Parameters::single_precision. Private to sph/src. The same physics as pair_kernel.h, with the
/// quantities formed so that float's 7 digits are not spent on a cancellation:
/// - positions enter as the displacement u = x - X (formed in double, then rounded) and the
///   reference position X relative to the body's centre: x_ij = (X_i - X_j) + (u_i - u_j);
///   the hourglass error e = (F_i + F_j) X / 2 + x_ij = (H_i + H_j) X / 2 + (u_i - u_j) with
///   H = F - I (formed in double) has no cancellation against the identity;
/// - the stress term V_i V_j (Q_i + Q_j) grad W, the viscosity and the hourglass term in float;
/// - the sums of the pair forces on each particle and the powers in double.
/// A pair's force is one float triple applied as +f to i and -f to j (converted exactly), so
/// momentum is conserved to double round-off. Every pair goes through one sequence of IEEE
/// operations in both loops (the file is built without contraction): the results stay
/// independent of the thread count.

#include <cstdint>

namespace sph::pair_kernel::mixed
{
  /// A particle's record of `float_size` floats.
  namespace field
  {
    enum : int
    {
      // in the order the pair force uses them (each block of four is transposed just before
      // its use, so few lanes are live at once)
      u          = 0,  ///< displacement x - X [m]
      x0         = 3,  ///< reference position X minus the body's reference centre [m]
      v          = 6,  ///< velocity [m/s]
      h          = 9,  ///< smoothing length [m]
      density    = 10, ///< [kg/m^3]
      mass       = 11, ///< [kg]
      volume     = 12, ///< V0 (TL) or V (UL) [m^3]
      q          = 13, ///< Q = P L (TL) or sigma L (UL), column-major [Pa]
      h_grad     = 22, ///< H = F - I, column-major [-]
      float_size = 32  ///< 128 bytes per particle, read in 8 blocks of 4 (the last one padded)
    };
  } // namespace field
  using field::float_size;
  /// Per pair: grad_i W_ij (3) and the hourglass factor (0 without hourglass control), floats.
  constexpr int pair_size = 4;

  /// What the pair force reads.
  struct Args
  {
    const float *record = nullptr; ///< float_size floats per particle
    const float *pair   = nullptr; ///< pair_size floats per pair
    double alpha = 0, beta = 0;    ///< Monaghan viscosity coefficients [-]
    double c = 0;                  ///< sound speed of the viscosity [m/s]
    bool av        = false;        ///< viscosity on
    bool hourglass = false;        ///< hourglass control on
  };

  /// Output per pair, as in pair_kernel.h: force on the first particle (3) [N], viscous power,
  /// hourglass power [W].
  constexpr int out_size = 5;

  /// As pair_kernel::particle_forces, eight pairs at a time: subtracts the force on i of each
  /// pair [pb, pe) of particle i from its second particle's f_int where j < e (pair order),
  /// writes it to share where j >= e (3 doubles each; returns the end of what it wrote) and
  /// returns the sums over all the pairs of the force on i and of the two powers in sum[0..4].
  double *particle_forces(const Args &a, std::int32_t i, std::int32_t pb, std::int32_t pe,
                          const std::int32_t *second, std::int32_t e, double *f_int, double *share,
                          double *sum);
} // namespace sph::pair_kernel::mixed
