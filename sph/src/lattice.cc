#include <sph/lattice.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>

namespace sph
{
  namespace
  {
    constexpr double pi = 3.14159265358979323846;

    int n_cells(const double side, const double dx)
    {
      return std::max(1, static_cast<int>(std::lround(side / dx)));
    }

    void check(const double value, const char *what)
    {
      if (!(value > 0) || !std::isfinite(value))
        throw std::invalid_argument(std::string("sph lattice: ") + what +
                                    " must be a positive length in metres, got " +
                                    std::to_string(value));
    }

    /// Centred coordinates of n cells of size dx: (k + 1/2 - n/2) dx.
    double centred(const int k, const int n, const double dx)
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
    /// one layer up about a layer's worth of particles away). Deterministic; cells are unique,
    /// so the keys are.
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
  } // namespace

  template <int dim>
  Lattice<dim> make_cylinder(const double D, const double L, const double dx)
  {
    check(D, "cylinder diameter");
    check(L, "cylinder length");
    check(dx, "particle spacing");
    Lattice<dim> out;
    out.spacing     = dx;
    const int    nr = n_cells(D, dx), nz = n_cells(L, dx);
    const double dz = L / nz, R = 0.5 * D;
    int          n_layer = 0;
    for (int k = 0; k < nz; ++k)
      {
        const double z = (k + 0.5) * dz;
        if constexpr (dim == 3)
          {
            for (int j = 0; j < nr; ++j)
              for (int i = 0; i < nr; ++i)
                {
                  const double x = centred(i, nr, dx), y = centred(j, nr, dx);
                  if (x * x + y * y <= R * R * (1.0 + 1e-12))
                    {
                      out.positions.emplace_back(x, y, z);
                      out.volumes.push_back(dx * dx * dz);
                      if (k == 0)
                        ++n_layer;
                    }
                }
          }
        else
          {
            for (int i = 0; i < nr; ++i)
              {
                out.positions.emplace_back(centred(i, nr, dx), z);
                out.volumes.push_back(dx * dz);
                if (k == 0)
                  ++n_layer;
              }
          }
      }
    if constexpr (dim == 3)
      {
        out.lattice_section_area = n_layer * dx * dx;
        out.true_section_area    = pi * R * R;
        out.true_volume          = pi * R * R * L;
      }
    else
      {
        out.lattice_section_area = n_layer * dx;
        out.true_section_area    = D;
        out.true_volume          = D * L;
      }
    scale_volumes(out);
    Vector<dim> step = Vector<dim>::Constant(dx);
    step[dim - 1]    = dz;
    out.cell_size    = step;
    order_along_morton_curve(out, step);
    return out;
  }

  template <int dim>
  Lattice<dim> make_disc(const double D, const double t, const double dx)
  {
    check(D, "disc diameter");
    check(t, "disc thickness");
    check(dx, "particle spacing");
    Lattice<dim> out;
    out.spacing     = dx;
    const int    n  = n_cells(D, dx), ny = n_cells(t, dx);
    const double R  = 0.5 * D, dy = t / ny;
    // the layer x closest to 0 (the splitting plane): cell index n/2 (odd n: the centre cell)
    const int i_mid   = n / 2;
    int       n_layer = 0;
    for (int k = 0; k < n; ++k)
      {
        const double z = R + centred(k, n, dx);
        if constexpr (dim == 3)
          {
            for (int j = 0; j < ny; ++j)
              for (int i = 0; i < n; ++i)
                {
                  const double x = centred(i, n, dx), y = (j + 0.5 - 0.5 * ny) * dy;
                  const double zc = z - R;
                  if (x * x + zc * zc <= R * R * (1.0 + 1e-12))
                    {
                      out.positions.emplace_back(x, y, z);
                      out.volumes.push_back(dx * dx * dy);
                      if (i == i_mid)
                        ++n_layer;
                    }
                }
          }
        else
          {
            for (int i = 0; i < n; ++i)
              {
                const double x = centred(i, n, dx), zc = z - R;
                if (x * x + zc * zc <= R * R * (1.0 + 1e-12))
                  {
                    out.positions.emplace_back(x, z);
                    out.volumes.push_back(dx * dx);
                    if (i == i_mid)
                      ++n_layer;
                  }
              }
          }
      }
    if constexpr (dim == 3)
      {
        out.lattice_section_area = n_layer * dx * dy;
        out.true_section_area    = D * t;
        out.true_volume          = pi * R * R * t;
      }
    else
      {
        out.lattice_section_area = n_layer * dx;
        out.true_section_area    = D;
        out.true_volume          = pi * R * R;
      }
    scale_volumes(out);
    Vector<dim> step = Vector<dim>::Constant(dx);
    if constexpr (dim == 3)
      step[1] = dy;
    out.cell_size = step;
    order_along_morton_curve(out, step);
    return out;
  }

  template <int dim>
  Lattice<dim> make_block(const Vector<dim> &lower, const Vector<dim> &upper, const double dx)
  {
    check(dx, "particle spacing");
    for (int d = 0; d < dim; ++d)
      check(upper[d] - lower[d], "block side (upper - lower)");
    Lattice<dim> out;
    out.spacing = dx;
    std::array<int, dim>    n;
    Vector<dim>             cell;
    for (int d = 0; d < dim; ++d)
      {
        n[d]    = n_cells(upper[d] - lower[d], dx);
        cell[d] = (upper[d] - lower[d]) / n[d];
      }
    const int total = [&] {
      int t = 1;
      for (int d = 0; d < dim; ++d)
        t *= n[d];
      return t;
    }();
    double cell_volume = 1;
    for (int d = 0; d < dim; ++d)
      cell_volume *= cell[d];
    for (int c = 0; c < total; ++c)
      {
        int         r = c;
        Vector<dim> x;
        for (int d = 0; d < dim; ++d)
          {
            x[d] = lower[d] + (r % n[d] + 0.5) * cell[d];
            r /= n[d];
          }
        out.positions.push_back(x);
        out.volumes.push_back(cell_volume);
      }
    out.true_volume        = cell_volume * total;
    out.true_section_area  = out.true_volume / (upper[dim - 1] - lower[dim - 1]);
    out.lattice_section_area = out.true_section_area;
    scale_volumes(out);
    out.cell_size = cell;
    order_along_morton_curve(out, cell);
    return out;
  }

  template Lattice<2> make_cylinder<2>(double, double, double);
  template Lattice<3> make_cylinder<3>(double, double, double);
  template Lattice<2> make_disc<2>(double, double, double);
  template Lattice<3> make_disc<3>(double, double, double);
  template Lattice<2> make_block<2>(const Vector<2> &, const Vector<2> &, double);
  template Lattice<3> make_block<3>(const Vector<3> &, const Vector<3> &, double);
} // namespace sph
