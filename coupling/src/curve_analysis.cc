#include <coupling/curve_analysis.h>

#include <algorithm>
#include <cmath>

namespace coupling
{
  std::size_t peak_index(const std::vector<double> &y)
  {
    return static_cast<std::size_t>(std::max_element(y.begin(), y.end()) - y.begin());
  }

  bool crossing(const std::vector<double> &x, const std::vector<double> &y, double level,
                double &x_at_level)
  {
    if (y.empty())
      return false;
    const std::size_t top = peak_index(y);
    for (std::size_t i = 1; i <= top; ++i)
      if (y[i - 1] < level && y[i] >= level)
      {
        const double w = (level - y[i - 1]) / (y[i] - y[i - 1]);
        x_at_level     = x[i - 1] + w * (x[i] - x[i - 1]);
        return true;
      }
    if (y[0] >= level)
    {
      x_at_level = x[0];
      return top == 0 ? false : true;
    }
    return false;
  }

  double secant_modulus(const std::vector<double> &strain, const std::vector<double> &stress,
                        double lo, double hi)
  {
    if (stress.size() < 2)
      return 0;
    const double peak = stress[peak_index(stress)];
    double e_lo = 0, e_hi = 0;
    if (!(peak > 0) || !crossing(strain, stress, lo * peak, e_lo) ||
        !crossing(strain, stress, hi * peak, e_hi) || !(e_hi > e_lo))
      return 0;
    return (hi - lo) * peak / (e_hi - e_lo);
  }

  double secant_poissons_ratio(const std::vector<double> &axial_strain,
                               const std::vector<double> &lateral_strain,
                               const std::vector<double> &stress, double lo, double hi)
  {
    if (stress.size() < 2)
      return -1;
    const double peak = stress[peak_index(stress)];
    double a_lo = 0, a_hi = 0, l_lo = 0, l_hi = 0;
    if (!(peak > 0) || !crossing(axial_strain, stress, lo * peak, a_lo) ||
        !crossing(axial_strain, stress, hi * peak, a_hi) ||
        !crossing(lateral_strain, stress, lo * peak, l_lo) ||
        !crossing(lateral_strain, stress, hi * peak, l_hi) || !(std::abs(a_hi - a_lo) > 0))
      return -1;
    return -(l_hi - l_lo) / (a_hi - a_lo);
  }
} // namespace coupling
