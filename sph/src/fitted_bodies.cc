#include <sph/fitted_bodies.h>

#include "lattice_detail.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

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
      double half_angle; ///< half the angle its annulus sector spans (the centre's: pi)
    };

    /// The number of rings n of a layer of outer radius R at spacing dx (dr = R / (n + 1/2)).
    int ring_count(const double R, const double dx)
    {
      return std::max(1, static_cast<int>(std::lround(R / dx - 0.5)));
    }

    /// The particles on ring k: 2 round(pi k), even, so that the ring is symmetric about both axes.
    int ring_points(const int k) { return 2 * std::max(1, static_cast<int>(std::lround(pi * k))); }

    std::vector<RingPoint> ring_layer(const double R, const double dx, double &dr)
    {
      const int n_rings = ring_count(R, dx);
      dr                = R / (n_rings + 0.5);
      std::vector<RingPoint> layer;
      layer.push_back({0.0, 0.0, pi * 0.25 * dr * dr, pi});
      for (int k = 1; k <= n_rings; ++k)
        {
          const int    n_k   = ring_points(k);
          const double r     = k * dr;
          const double annulus = 2.0 * pi * r * dr; // pi ((r + dr/2)^2 - (r - dr/2)^2)
          for (int j = 0; j < n_k; ++j)
            {
              const double theta = 2.0 * pi * j / n_k;
              layer.push_back({r * std::sin(theta), r * std::cos(theta), annulus / n_k, pi / n_k});
            }
        }
      return layer;
    }

    /// The outer ring (the layer's last `n` = ring_points(k) points, at radius r) re-spaced so
    /// that each flat's arc |theta| <= a (and |theta - pi| <= a) holds a whole number m of equal
    /// sectors: the odd m (a particle stays on the loaded diameter) whose sectors are nearest in
    /// angle to those of the round arcs between the flats, which share the rest equally. With the ring's even
    /// spacing the corner at a falls inside a sector, whose particle stays on the round arc just
    /// below the flat: at D/20 (2.5 mm) the flat's particles then covered 82 % of it, the platen
    /// loaded a narrower arc than the specimen's, the disc's tension reached too far towards the
    /// flats and its peak was 7 % low (at D/40 the ring's spacing happens to divide the flat).
    void align_outer_ring_with_flats(std::vector<RingPoint> &layer, const std::size_t n,
                                     const double r, const double a)
    {
      // n = ring_points(k) >= 6, so m = 1 leaves each round arc at least one sector (q >= 1)
      int    best          = 1;
      double best_mismatch = std::numeric_limits<double>::max();
      for (int m = 1; 2 * m < static_cast<int>(n); m += 2)
        {
          const double flat = 2 * a / m, round = 2 * (pi - 2 * a) / (n - 2 * m);
          const double mismatch = std::abs(std::log(flat / round));
          if (mismatch < best_mismatch)
            {
              best_mismatch = mismatch;
              best          = m;
            }
        }
      const int    m     = best;
      const int    q     = (static_cast<int>(n) - 2 * m) / 2; // sectors on each round arc
      const double flat  = 2 * a / m, round = (pi - 2 * a) / q;
      const double area  = layer.back().area * n; // the ring's annulus
      std::vector<double> angles, widths;
      for (int j = 0; j < m; ++j) // the top flat, centred on theta = 0
        {
          angles.push_back(-a + (j + 0.5) * flat);
          widths.push_back(flat);
        }
      for (int j = 0; j < q; ++j) // the round arc towards theta = pi
        {
          angles.push_back(a + (j + 0.5) * round);
          widths.push_back(round);
        }
      for (int j = 0; j < m; ++j) // the bottom flat, centred on theta = pi
        {
          angles.push_back(pi - a + (j + 0.5) * flat);
          widths.push_back(flat);
        }
      for (int j = 0; j < q; ++j) // back to the top flat
        {
          angles.push_back(pi + a + (j + 0.5) * round);
          widths.push_back(round);
        }
      for (std::size_t j = 0; j < n; ++j)
        {
          RingPoint &p = layer[layer.size() - n + j];
          p            = {r * std::sin(angles[j]), r * std::cos(angles[j]),
                          area * widths[j] / (2.0 * pi), 0.5 * widths[j]};
        }
    }

    /// The Jacobian (rho / R)^2 of the flattening map, rho(theta) = min(R, R cos a / |cos theta|),
    /// averaged over angles: its primitive is cos^2 a tan(theta) on the flat (|theta| <= a) and
    /// grows by one per radian elsewhere, odd and rising by 2 G(pi/2) every pi.
    struct FlattenedJacobian
    {
      double a;
      double primitive(const double theta) const
      {
        const double half = std::sin(a) * std::cos(a) + (0.5 * pi - a); // G(pi / 2)
        const double k    = std::floor((theta + 0.5 * pi) / pi);
        const double u    = theta - k * pi, w = std::abs(u); // u in [-pi/2, pi/2)
        const double g =
          w <= a ? std::cos(a) * std::cos(a) * std::tan(w) : std::sin(a) * std::cos(a) + (w - a);
        return 2 * k * half + (u < 0 ? -g : g);
      }
      double mean(const double lo, const double hi) const
      {
        return (primitive(hi) - primitive(lo)) / (hi - lo);
      }
    };

    /// The areas of the layer's centre and first three rings (r < 3.5 dr) made consistent with
    /// the kernel (SummedWith): each one's sum_j A_j step W over the layer stacked `step` apart
    /// without end equal to the mean sum of the next three rings' (those of them 2h inside the
    /// boundary; `inner`: whether a point of the plane is); the others keep their areas. Ring k
    /// holds 2 round(pi k) particles: the first rings' are 4.5 % short of 2 pi k, and the centre's
    /// disc of radius dr / 2 sits among them (sums 1.06 and 1.03 for the centre and ring 1); from
    /// the fourth ring out every particle's sum lies in 0.998-1.0003 (1.25 mm, cubic spline, h
    /// 1.2 dx). Fixed-point iteration A_i <- A_i target / S_i to 1e-10 of the target. Nothing to
    /// do where no ring of the next three lies 2h inside (D below about 13 dx).
    template <typename Inner>
    void make_areas_consistent(std::vector<RingPoint> &layer, const double step, const double dr,
                               const SummedWith &with, const Inner &inner)
    {
      if (!(with.h > 0 && std::isfinite(with.h)))
        throw std::invalid_argument("sph fitted body: the smoothing length must be > 0, got " +
                                    std::to_string(with.h));
      const double h = with.h, reach = 2 * h;
      std::vector<std::size_t> own, beyond; // the particles corrected; those that set the target
      for (std::size_t i = 0; i < layer.size(); ++i)
        if (inner(layer[i].u, layer[i].v))
        {
          const double r = std::hypot(layer[i].u, layer[i].v);
          if (r < 3.5 * dr)
            own.push_back(i);
          else if (r < 6.5 * dr)
            beyond.push_back(i);
        }
      if (own.empty() || beyond.empty())
        return;
      // the kernel between two particles of the plane, summed over the stack
      const int layers = static_cast<int>(std::floor(reach / step));
      const auto stacked = [&](const RingPoint &a, const RingPoint &b) {
        const double d2 = std::pow(a.u - b.u, 2) + std::pow(a.v - b.v, 2);
        double w = 0;
        if (d2 < reach * reach)
          for (int k = -layers; k <= layers; ++k)
            w += kernels::w<3>(with.kernel, std::sqrt(d2 + std::pow(k * step, 2)), h);
        return w * step;
      };
      // each particle's neighbours and their kernel sums: the corrected ones, then the others
      std::vector<std::size_t> all = own;
      all.insert(all.end(), beyond.begin(), beyond.end());
      std::vector<std::vector<std::pair<std::size_t, double>>> terms(all.size());
      for (std::size_t a = 0; a < all.size(); ++a)
        for (std::size_t j = 0; j < layer.size(); ++j)
          if (const double w = stacked(layer[all[a]], layer[j]); w > 0)
            terms[a].push_back({j, w});
      // A_i <- A_i target / S_i converges for the kernels up to h = 1.3 dx; a wider kernel couples
      // the corrected particles more strongly than their own weights and the iteration oscillates
      // apart (h = 1.4 dx on). Then the same conditions are solved as the linear system they are:
      // sum_(j own) (w_aj - m_j) A_j = t - c_a, with c the fixed particles' share of a sum, m_j
      // and t the mean over the target rings of w_bj and of c_b. The iteration stays first where
      // it converges: the volumes it gives are those of every stored result. It changes only the
      // unknowns' areas, so the fixed particles' c are the same for the system.
      for (int it = 0; it < 1000; ++it)
        {
          std::vector<double> sum(all.size(), 0.0);
          for (std::size_t a = 0; a < all.size(); ++a)
            for (const auto &[j, w] : terms[a])
              sum[a] += layer[j].area * w;
          // the target moves with the corrected areas (rings 4-6 reach rings 2-3)
          double target = 0, worst = 0;
          for (std::size_t a = own.size(); a < all.size(); ++a)
            target += sum[a] / beyond.size();
          for (std::size_t a = 0; a < own.size(); ++a)
            worst = std::max(worst, std::abs(sum[a] / target - 1));
          if (worst < 1e-10)
            return;
          if (!(worst < 1e3))
            break; // oscillating apart (a converging iteration stays within a few per cent)
          for (std::size_t a = 0; a < own.size(); ++a)
            layer[own[a]].area *= target / sum[a];
        }
      const std::size_t n = own.size();
      std::vector<std::size_t> column(layer.size(), n); // layer index -> unknown (n: fixed)
      for (std::size_t a = 0; a < n; ++a)
        column[own[a]] = a;
      Eigen::MatrixXd M = Eigen::MatrixXd::Zero(n, n);
      Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n), mean_w = Eigen::VectorXd::Zero(n);
      double mean_c = 0;
      for (std::size_t a = n; a < all.size(); ++a)
        for (const auto &[j, w] : terms[a])
          {
            if (column[j] < n)
              mean_w[column[j]] += w / beyond.size();
            else
              mean_c += layer[j].area * w / beyond.size();
          }
      for (std::size_t a = 0; a < n; ++a)
        {
          double c = 0;
          for (const auto &[j, w] : terms[a])
            {
              if (column[j] < n)
                M(a, column[j]) += w;
              else
                c += layer[j].area * w;
            }
          M.row(a) -= mean_w.transpose();
          rhs[a] = mean_c - c;
        }
      const Eigen::VectorXd A = M.colPivHouseholderQr().solve(rhs);
      bool positive = (M * A - rhs).norm() <= 1e-8 * rhs.norm();
      for (std::size_t a = 0; a < n; ++a)
        positive = positive && A[a] > 0;
      if (positive)
        {
          for (std::size_t a = 0; a < n; ++a)
            layer[own[a]].area = A[a];
          return;
        }
      throw std::domain_error("the body-fitted particles' kernel-consistent volumes have no positive "
                              "solution at h = " + std::to_string(h / dr) + " ring steps");
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

  Lattice<3> make_fitted_cylinder(const double D, const double L, const double dx,
                                  const std::optional<SummedWith> &summed_with)
  {
    check(D, "cylinder diameter");
    check(L, "cylinder length");
    check(dx, "particle spacing");
    Lattice<3> out;
    out.spacing    = dx;
    const double R = 0.5 * D;
    double       dr = 0;
    std::vector<RingPoint> layer = ring_layer(R, dx, dr);
    const int    nz = n_cells(L, dx);
    const double dz = L / nz;
    if (summed_with)
      make_areas_consistent(layer, dz, dr, *summed_with, [&](const double u, const double v) {
        return std::hypot(u, v) <= R - 2 * summed_with->h;
      });
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

  Lattice<3> make_fitted_disc(const double D, const double t, const double dx,
                              const double flat_angle, const std::optional<SummedWith> &summed_with)
  {
    check(D, "disc diameter");
    check(t, "disc thickness");
    check(dx, "particle spacing");
    if (!(flat_angle >= 0 && flat_angle <= max_flat_angle))
      throw std::invalid_argument("sph fitted disc: flat loading angle must be in [0, " +
                                  std::to_string(max_flat_angle) + "] rad, got " +
                                  std::to_string(flat_angle));
    Lattice<3> out;
    out.spacing    = dx;
    const double R = 0.5 * D;
    double       dr = 0;
    std::vector<RingPoint> layer = ring_layer(R, dx, dr);
    if (flat_angle > 0)
      {
        const int n_rings = ring_count(R, dx);
        align_outer_ring_with_flats(layer, static_cast<std::size_t>(ring_points(n_rings)),
                                    n_rings * dr, 0.5 * flat_angle);
      }
    // flats at v = -+ R cos(alpha): the round layer pulled in along its radii onto the
    // flattened boundary rho(theta) = min(R, R cos(alpha) / |cos theta|), theta from the load
    // axis v. The map (r, theta) -> (r rho / R, theta) keeps every ring's particle on the
    // loaded diameter and puts the outer ring's flat part on a line parallel to the flat,
    // cos(alpha) dr / 2 inside it. Each particle's area is its annulus sector's image: the
    // sector's area times the mean of the map's Jacobian (rho / R)^2 over the sector's angles,
    // so the images tile the flattened face exactly.
    const double cos_a = std::cos(0.5 * flat_angle);
    if (flat_angle > 0)
      {
        const FlattenedJacobian jac{0.5 * flat_angle};
        for (RingPoint &p : layer)
          {
            const double theta = std::atan2(p.u, p.v), r = std::hypot(p.u, p.v);
            p.area *= jac.mean(theta - p.half_angle, theta + p.half_angle);
            if (std::abs(p.v) > cos_a * r) // on the flats' side of the corner rays
              {
                const double s = cos_a * r / std::abs(p.v);
                p.u *= s;
                p.v *= s;
              }
          }
      }
    const int    ny = n_cells(t, dx);
    const double dy = t / ny;
    if (summed_with)
      make_areas_consistent(layer, dy, dr, *summed_with, [&](const double u, const double v) {
        const double margin = 2 * summed_with->h;
        return std::hypot(u, v) <= R - margin && std::abs(v) <= R * cos_a - margin;
      });
    stack_layers(out, layer, ny, dy, [&](const int k, const RingPoint &p) {
      return Vector<3>(p.u, centred(k, ny, dy), R + p.v);
    });
    // the splitting plane x = 0 spans the height between the flats; the face is the circle less
    // the two segments the flats cut off (each R^2 (2 alpha - sin 2 alpha) / 2)
    const double alpha       = 0.5 * flat_angle;
    out.true_section_area    = D * cos_a * t;
    out.lattice_section_area = out.true_section_area;
    out.true_volume          = (pi - (2 * alpha - std::sin(2 * alpha))) * R * R * t;
    scale_volumes(out); // round-off only: the sectors' images tile the face
    // along the load: the outer particles lie cos(alpha) dr / 2 inside the flats (dr / 2 inside
    // a round disc's top and bottom), so that a contact radius of half of it reaches the face
    out.cell_size = Vector<3>(dr, dy, dr * cos_a);
    order_along_morton_curve(out, Vector<3>(0.5 * dr, dy, 0.5 * dr));
    return out;
  }
} // namespace sph
