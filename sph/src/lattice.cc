#include <sph/lattice.h>

#include "lattice_detail.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>

namespace sph
{
  using namespace lattice_detail;

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
  Lattice<dim> make_disc(const double D, const double t, const double dx, const double flat_angle)
  {
    check(D, "disc diameter");
    check(t, "disc thickness");
    check(dx, "particle spacing");
    if (!(flat_angle >= 0 && flat_angle <= max_flat_angle))
      throw std::invalid_argument("sph lattice: flat loading angle must be in [0, " +
                                  std::to_string(max_flat_angle) + "] rad, got " +
                                  std::to_string(flat_angle));
    Lattice<dim> out;
    out.spacing     = dx;
    const int    n  = n_cells(D, dx), ny = n_cells(t, dx);
    const double R  = 0.5 * D, dy = t / ny;
    // rows along the load: a round disc has round(D / dx) rows of dx (a spacing that does not
    // divide D reaches up to dx / 2 past it; the driver moves its platens); a flattened one fills its
    // height H = D cos(alpha) with round(H / dx) equal rows, so that the outer rows' particles
    // reach half a row out to the flats exactly and the flats are 2 R sin(alpha) wide within a
    // row's chord, at any spacing
    const double alpha = 0.5 * flat_angle;
    const double H     = alpha > 0 ? D * std::cos(alpha) : D;
    const int    nz    = alpha > 0 ? n_cells(H, dx) : n;
    const double dz    = alpha > 0 ? H / nz : dx;
    // the layer x closest to 0 (the splitting plane): cell index n/2 (odd n: the centre cell)
    const int i_mid   = n / 2;
    int       n_layer = 0;
    for (int k = 0; k < nz; ++k)
      {
        const double z = R + centred(k, nz, dz);
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
                      out.volumes.push_back(dx * dz * dy);
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
                    out.volumes.push_back(dx * dz);
                    if (i == i_mid)
                      ++n_layer;
                  }
              }
          }
      }
    // the circle less the two segments cut off by the flats (each R^2 (2 alpha - sin 2 alpha) / 2)
    const double face = pi * R * R - R * R * (2 * alpha - std::sin(2 * alpha));
    if constexpr (dim == 3)
      {
        out.lattice_section_area = n_layer * dz * dy;
        out.true_section_area    = H * t;
        out.true_volume          = face * t;
      }
    else
      {
        out.lattice_section_area = n_layer * dz;
        out.true_section_area    = H;
        out.true_volume          = face;
      }
    scale_volumes(out);
    Vector<dim> step = Vector<dim>::Constant(dx);
    step[dim - 1]    = dz;
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
  template Lattice<2> make_disc<2>(double, double, double, double);
  template Lattice<3> make_disc<3>(double, double, double, double);
  template Lattice<2> make_block<2>(const Vector<2> &, const Vector<2> &, double);
  template Lattice<3> make_block<3>(const Vector<3> &, const Vector<3> &, double);
} // namespace sph
