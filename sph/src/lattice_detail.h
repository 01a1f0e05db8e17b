#pragma once
/// @file
/// Helpers of the particle-set generators (lattice.cc, fitted_bodies.cc): argument checks,
/// volume scaling to the true body, the Morton order. Internal to the sph library.

#include <sph/lattice.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace sph::lattice_detail
{
  constexpr double pi = 3.14159265358979323846;

  inline int n_cells(const double side, const double dx)
  {
    return std::max(1, static_cast<int>(std::lround(side / dx)));
  }

  inline void check(const double value, const char *what)
  {
    if (!(value > 0) || !std::isfinite(value))
      throw std::invalid_argument(std::string("sph lattice: ") + what +
                                  " must be a positive length in metres, got " +
                                  std::to_string(value));
  }

  /// Centred coordinates of n cells of size dx: (k + 1/2 - n/2) dx.
  inline double centred(const int k, const int n, const double dx)
  {
    return (k + 0.5 - 0.5 * n) * dx;
  }

  template <int dim>
  void scale_volumes(Lattice<dim> &lattice)
  {
    double sum = 0;
    for (const double v : lattice.volumes)
      sum += v;
    if (lattice.volumes.empty())
      throw std::invalid_argument("sph lattice: no particle fits in the body; "
                                  "use a smaller particle spacing");
    const double f = lattice.true_volume / sum;
    for (double &v : lattice.volumes)
      v *= f;
  }

  /// Reorders the particles along a Morton (Z-order) curve of their lattice cells (cell sizes
  /// `step`): particles close in space get close indices, so the neighbours of a particle lie
  /// within a few cache lines of it at any body size (lexicographic order puts the neighbours
  /// one layer up about a layer's worth of particles away). Deterministic: particles that share
  /// a cell (body-fitted sets can put two in one) keep their order.
  template <int dim>
  void order_along_morton_curve(Lattice<dim> &lattice, const Vector<dim> &step)
  {
    const std::size_t n = lattice.positions.size();
    if (n == 0)
      return;
    Vector<dim> lo = lattice.positions[0];
    for (const auto &x : lattice.positions)
      lo = lo.cwiseMin(x);
    constexpr int bits = 63 / dim; // 21 bits per coordinate in 3-D, 31 in 2-D
    std::vector<std::pair<std::uint64_t, std::size_t>> keys(n);
    for (std::size_t i = 0; i < n; ++i)
      {
        std::uint64_t key = 0;
        for (int d = 0; d < dim; ++d)
          {
            const auto c =
              static_cast<std::uint64_t>(std::lround((lattice.positions[i][d] - lo[d]) / step[d]));
            if (c >> bits)
              throw std::invalid_argument("sph lattice: more than 2^" + std::to_string(bits) +
                                          " cells along one axis; use a larger particle spacing");
            for (int b = 0; b < bits; ++b)
              key |= ((c >> b) & 1u) << (b * dim + d);
          }
        keys[i] = {key, i};
      }
    std::sort(keys.begin(), keys.end());
    std::vector<Vector<dim>> positions(n);
    std::vector<double>      volumes(n);
    for (std::size_t k = 0; k < n; ++k)
      {
        positions[k] = lattice.positions[keys[k].second];
        volumes[k]   = lattice.volumes[keys[k].second];
      }
    lattice.positions.swap(positions);
    lattice.volumes.swap(volumes);
  }
} // namespace sph::lattice_detail
