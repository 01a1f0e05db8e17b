#pragma once
/// @file
/// Hondros's plane-stress solution of the Brazilian disc, for the disc tests.

#include <cmath>
#include <utility>

namespace coupling::test
{
  /// Hondros's plane-stress field of a disc of radius 1 loaded by a uniform pressure over the
  /// arcs |theta| <= a about both ends of the z axis (theta from +z), per T = 2P/(pi D t):
  /// (sigma_xx, sigma_zz) at (x, z). The series in rho^(2n-2), summed to 1e-12 (rho <= 0.5).
  inline std::pair<double, double> hondros(const double x, const double z, const double a)
  {
    const double rho = std::hypot(x, z), th = std::atan2(x, z);
    double       sr = a, st = a, tau = 0, pw = 1; // pw = rho^(2n-2)
    for (int n = 1; n < 400 && pw > 1e-13; ++n, pw *= rho * rho)
      {
        const double c = pw * std::sin(2 * n * a), r2 = rho * rho;
        sr += (1 - (1 - 1.0 / n) * r2) * c * std::cos(2 * n * th);
        st -= (1 - (1 + 1.0 / n) * r2) * c * std::cos(2 * n * th);
        tau += (1 - r2) * c * std::sin(2 * n * th);
      }
    sr *= -1 / a, st *= -1 / a, tau *= 1 / a; // 2p/pi = T/a for p = P/(2 a R t)
    const double s = std::sin(th), c = std::cos(th);
    return {sr * s * s + st * c * c + 2 * tau * s * c, sr * c * c + st * s * s - 2 * tau * s * c};
  }
} // namespace coupling::test
