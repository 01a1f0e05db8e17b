// Broyden's method for two unknowns (joint_solver.h).
#include <app/joint_solver.h>

#include <algorithm>
#include <cmath>

namespace app
{
  JointSolution solve_broyden(const std::function<Vector2(const Vector2 &)> &r, Vector2 x, Matrix2 J,
                              const double tolerance, const int max_evaluations, const double max_step,
                              const std::function<void(const Vector2 &, const Vector2 &)> &seen)
  {
    JointSolution s;
    Vector2 f = r(x);
    s.evaluations = 1;
    if (seen)
      seen(x, f);
    const auto small = [tolerance](const Vector2 &v) {
      return std::abs(v[0]) <= tolerance && std::abs(v[1]) <= tolerance;
    };
    while (!small(f) && s.evaluations < max_evaluations)
    {
      const double det = J[0][0] * J[1][1] - J[0][1] * J[1][0];
      if (!(std::abs(det) > 1e-12) || !std::isfinite(det))
        break;
      // Newton step on the current Jacobian, each component limited
      Vector2 dx{-(J[1][1] * f[0] - J[0][1] * f[1]) / det, -(-J[1][0] * f[0] + J[0][0] * f[1]) / det};
      for (double &d : dx)
        d = std::clamp(d, -max_step, max_step);
      const Vector2 x_new{x[0] + dx[0], x[1] + dx[1]};
      const Vector2 f_new = r(x_new);
      ++s.evaluations;
      if (seen)
        seen(x_new, f_new);
      // Broyden's update: J += (df - J dx) dx^T / (dx . dx)
      const Vector2 df{f_new[0] - f[0], f_new[1] - f[1]};
      const double dd = dx[0] * dx[0] + dx[1] * dx[1];
      if (dd > 0)
        for (int i = 0; i < 2; ++i)
        {
          const double miss = df[i] - (J[i][0] * dx[0] + J[i][1] * dx[1]);
          for (int j = 0; j < 2; ++j)
            J[i][j] += miss * dx[j] / dd;
        }
      x = x_new;
      f = f_new;
    }
    s.x         = x;
    s.r         = f;
    s.converged = small(f);
    return s;
  }
} // namespace app
