#pragma once
/// @file
/// Broyden's method for two unknowns: the joint calibration of `cosim calibrate --simulate
/// --with-bts` solves (log UCS miss, log BTS miss) = 0 for (log c scale, the shift of
/// log tan(pi/4 + phi/2)) with it, each evaluation being coupled runs. Kept apart from the runs so that it is tested on closed
/// forms.

#include <array>
#include <functional>

namespace app
{
  using Vector2 = std::array<double, 2>;
  using Matrix2 = std::array<Vector2, 2>; ///< rows: d r_i / d x_j

  struct JointSolution
  {
    Vector2 x{}, r{};      ///< the last point and its residual
    int evaluations = 0;   ///< calls of the residual
    bool converged  = false;
  };

  /// Solves r(x) = 0 from x0 by Broyden's ("good") method with the Jacobian guess J0: each step
  /// x <- x - J^-1 r, each component limited to max_step, then the rank-one update of J from the
  /// step and the change of r. Stops when max |r_i| <= tolerance, after max_evaluations calls of
  /// r, or when J turns singular. `seen` is called with every evaluated point.
  JointSolution solve_broyden(const std::function<Vector2(const Vector2 &)> &r, Vector2 x0, Matrix2 J0,
                              double tolerance, int max_evaluations, double max_step,
                              const std::function<void(const Vector2 &, const Vector2 &)> &seen = {});
} // namespace app
