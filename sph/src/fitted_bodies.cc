#include <sph/fitted_bodies.h>

#include "lattice_detail.h"

#include <cmath>

namespace sph
{
  using namespace lattice_detail;

  namespace
  {
    /// One layer of rings of outer radius R: (u, v, area) of each particle in the layer's plane.
    /// Ring k at radius k dr has 2 round(pi k) particles at angles 2 pi j / n_k from the v axis,
    /// so the ring is symmetric about u = 0 and v = 0 and has particles on the v axis.
    struct RingPoint
    {
      double u, v, area;
    };

    std::vector<RingPoint> ring_layer(const double R, const double dx, double &dr)
    {
      const int n_rings = std::max(1, static_cast<int>(std::lround(R / dx - 0.5)));
      dr                = R / (n_rings + 0.5);
      std::vector<RingPoint> layer;
      layer.push_back({0.0, 0.0, pi * 0.25 * dr * dr});
      for (int k = 1; k <= n_rings; ++k)
        {
          const int    n_k   = 2 * std::max(1, static_cast<int>(std::lround(pi * k)));
          const double r     = k * dr;
          const double annulus = 2.0 * pi * r * dr; // pi ((r + dr/2)^2 - (r - dr/2)^2)
          for (int j = 0; j < n_k; ++j)
            {
              const double theta = 2.0 * pi * j / n_k;
              layer.push_back({r * std::sin(theta), r * std::cos(theta), annulus / n_k});
            }
        }
      return layer;
    }

    /// `layer` stacked `n` times, `step` [m] apart: layer k's ring point p at place(k, p), its
    /// volume p's area times `step`.
    template <typename Place>
    void stack_layers(Lattice<3> &out, const std::vector<RingPoint> &layer, const int n,
                      const double step, const Place &place)
    {
      for (int k = 0; k < n; ++k)
        for (const RingPoint &p : layer)
          {
            out.positions.push_back(place(k, p));
            out.volumes.push_back(p.area * step);
          }
    }
  } // namespace

  Lattice<3> make_fitted_cylinder(const double D, const double L, const double dx)
  {
    check(D, "cylinder diameter");
    check(L, "cylinder length");
    check(dx, "particle spacing");
    Lattice<3> out;
    out.spacing    = dx;
    const double R = 0.5 * D;
    double       dr = 0;
    const std::vector<RingPoint> layer = ring_layer(R, dx, dr);
    const int    nz = n_cells(L, dx);
    const double dz = L / nz;
    stack_layers(out, layer, nz, dz, [&](const int k, const RingPoint &p) {
      return Vector<3>(p.u, p.v, (k + 0.5) * dz);
    });
    out.true_section_area    = pi * R * R;
    out.lattice_section_area = out.true_section_area; // the rings' areas sum to pi R^2
    out.true_volume          = pi * R * R * L;
    scale_volumes(out); // round-off only: the annuli sum to the circle
    out.cell_size = Vector<3>(dr, dr, dz);
    order_along_morton_curve(out, Vector<3>(0.5 * dr, 0.5 * dr, dz));
    return out;
  }

  Lattice<3> make_fitted_disc(const double D, const double t, const double dx)
  {
    check(D, "disc diameter");
    check(t, "disc thickness");
    check(dx, "particle spacing");
    Lattice<3> out;
    out.spacing    = dx;
    const double R = 0.5 * D;
    double       dr = 0;
    const std::vector<RingPoint> layer = ring_layer(R, dx, dr);
    const int    ny = n_cells(t, dx);
    const double dy = t / ny;
    stack_layers(out, layer, ny, dy, [&](const int k, const RingPoint &p) {
      return Vector<3>(p.u, centred(k, ny, dy), R + p.v);
    });
    out.true_section_area    = D * t;
    out.lattice_section_area = out.true_section_area; // the splitting plane x = 0 is the diameter's
    out.true_volume          = pi * R * R * t;
    scale_volumes(out);
    out.cell_size = Vector<3>(dr, dy, dr);
    order_along_morton_curve(out, Vector<3>(0.5 * dr, dy, 0.5 * dr));
    return out;
  }
} // namespace sph
