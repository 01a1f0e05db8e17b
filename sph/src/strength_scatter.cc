/// @file
/// Weibull strength factors from a counter-based hash of the lattice cell (see strength_scatter.h).

#include <sph/rock_models.h>
#include <sph/strength_scatter.h>

#include <cmath>
#include <stdexcept>

namespace sph
{
  namespace
  {
    // splitmix64's finaliser: a bijective mixer of 64-bit words
    std::uint64_t mix(std::uint64_t z)
    {
      z += 0x9e3779b97f4a7c15ULL;
      z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
      z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
      return z ^ (z >> 31);
    }
  } // namespace

  template <int dim>
  std::vector<double> weibull_strength_factors(const std::vector<Vector<dim>> &x0,
                                               const double spacing, const double modulus,
                                               const std::uint64_t seed)
  {
    if (!(modulus >= 1.0) || !std::isfinite(modulus))
      throw std::invalid_argument("weibull_strength_factors: Weibull modulus must be >= 1");
    if (!(spacing > 0))
      throw std::invalid_argument("weibull_strength_factors: spacing must be > 0");
    std::vector<double> factors(x0.size());
    for (std::size_t i = 0; i < x0.size(); ++i)
    {
      std::uint64_t h = mix(seed);
      for (int d = 0; d < dim; ++d)
      {
        // the cell of a cell-centred particle; floor keeps cells distinct on both sides of 0
        const auto cell = static_cast<std::int64_t>(std::floor(x0[i][d] / spacing));
        h               = mix(h ^ static_cast<std::uint64_t>(cell));
      }
      // 53 random bits, shifted by half a unit: u in (0, 1), so the factor is finite and > 0
      const double u = (static_cast<double>(h >> 11) + 0.5) * 0x1.0p-53;
      factors[i]     = rock::weibull_strength_factor(u, modulus);
    }
    return factors;
  }

  template std::vector<double> weibull_strength_factors<2>(const std::vector<Vector<2>> &, double,
                                                           double, std::uint64_t);
  template std::vector<double> weibull_strength_factors<3>(const std::vector<Vector<3>> &, double,
                                                           double, std::uint64_t);
} // namespace sph
