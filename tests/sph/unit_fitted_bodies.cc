#include <sph/fitted_bodies.h>
#include <sph/neighbour_search.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace
{
  using namespace sph;
  constexpr double pi = 3.14159265358979323846;

  double total(const std::vector<double> &v) { return std::accumulate(v.begin(), v.end(), 0.0); }

  /// Distance of each particle to its nearest neighbour [m].
  std::vector<double> nearest_distances(const std::vector<Vector<3>> &x, const double radius)
  {
    PairList pairs;
    find_pairs<3>(x, radius, pairs);
    std::vector<double> d(x.size(), radius);
    for (std::size_t k = 0; k < pairs.n_pairs(); ++k)
      {
        const double r = (x[pairs.first[k]] - x[pairs.second[k]]).norm();
        d[pairs.first[k]]  = std::min(d[pairs.first[k]], r);
        d[pairs.second[k]] = std::min(d[pairs.second[k]], r);
      }
    return d;
  }

  /// True when the mirror image of every particle in the plane `axis` = 0 (about `centre`) is
  /// a particle too.
  bool mirror_symmetric(const std::vector<Vector<3>> &x, const int axis, const double centre, const double tol)
  {
    std::vector<Vector<3>> sorted = x;
    auto less = [](const Vector<3> &a, const Vector<3> &b) {
      return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
    };
    std::sort(sorted.begin(), sorted.end(), less);
    for (const auto &p : x)
      {
        Vector<3> m = p;
        m[axis]     = 2 * centre - p[axis];
        bool found  = false;
        for (const auto &q : sorted)
          if ((q - m).norm() < tol)
            {
              found = true;
              break;
            }
        if (!found)
          return false;
      }
    return true;
  }

  TEST(SphFittedBodies, CylinderVolumeSurfaceAndSpacing)
  {
    const double D = 0.05, L = 0.1, dx = 0.0025, R = 0.5 * D;
    const auto   c = make_fitted_cylinder(D, L, dx);
    // the annuli of the rings add up to the circle exactly: only round-off may separate the
    // volumes' sum from pi R^2 L (a staircase lattice is off by the corners before scaling)
    EXPECT_NEAR(total(c.volumes), pi * R * R * L, 1e-12 * pi * R * R * L);
    EXPECT_NEAR(c.true_section_area, pi * R * R, 1e-15);
    const double dr = c.cell_size[0];
    EXPECT_NEAR(dr, R / (std::lround(R / dx - 0.5) + 0.5), 1e-15);
    // the outer ring lies half a ring spacing inside the true surface, at every angle
    double r_max = 0, r_min_outer = R;
    for (const auto &p : c.positions)
      r_max = std::max(r_max, std::hypot(p[0], p[1]));
    for (const auto &p : c.positions)
      if (std::hypot(p[0], p[1]) > r_max - 0.25 * dr)
        r_min_outer = std::min(r_min_outer, std::hypot(p[0], p[1]));
    EXPECT_NEAR(r_max, R - 0.5 * dr, 1e-12);
    EXPECT_NEAR(r_min_outer, R - 0.5 * dr, 1e-12) << "the outer layer is a circle, not a staircase";
    // near-uniform spacing: every particle's nearest neighbour between 0.9 and 1.1 dx (ring k
    // holds 2 round(pi k) particles, so its arc spacing is within 1/(2k) of dr, 1.05 dr for the
    // first; radial spacing dr = R/(n + 1/2) and axial L/round(L/dx) are within 2 % of dx here)
    const auto d = nearest_distances(c.positions, 2 * dx);
    EXPECT_GT(*std::min_element(d.begin(), d.end()), 0.9 * dx);
    EXPECT_LT(*std::max_element(d.begin(), d.end()), 1.1 * dx);
    // particle volumes near-uniform: the centre particle has pi/4 of a ring particle's area
    const double v_ref = dr * dr * c.cell_size[2];
    for (const double v : c.volumes)
      {
        EXPECT_GT(v, 0.75 * v_ref);
        EXPECT_LT(v, 1.2 * v_ref);
      }
    EXPECT_TRUE(mirror_symmetric(c.positions, 0, 0.0, 1e-9 * dx));
    EXPECT_TRUE(mirror_symmetric(c.positions, 1, 0.0, 1e-9 * dx));
  }

  TEST(SphFittedBodies, DiscIsRoundAndSymmetricAboutTheLoadedDiameter)
  {
    const double D = 0.05, t = 0.025, R = 0.5 * D;
    for (const double dx : {0.0025, 0.00125})
      {
        const auto   b  = make_fitted_disc(D, t, dx);
        const double dr = b.cell_size[0];
        EXPECT_NEAR(total(b.volumes), pi * R * R * t, 1e-12 * pi * R * R * t);
        double top = 0, bottom = D, r_max = 0;
        for (const auto &p : b.positions)
          {
            r_max = std::max(r_max, std::hypot(p[0], p[2] - R));
            if (std::abs(p[0]) < 1e-12)
              top = std::max(top, p[2]), bottom = std::min(bottom, p[2]);
          }
        // a particle of the outer ring sits on the loaded diameter at the top and the bottom,
        // half a ring spacing inside the surface: the platens touch the round disc there
        EXPECT_NEAR(r_max, R - 0.5 * dr, 1e-12);
        EXPECT_NEAR(top, D - 0.5 * dr, 1e-12);
        EXPECT_NEAR(bottom, 0.5 * dr, 1e-12);
        // symmetric about the splitting plane x = 0 and the mid-plane z = R: the split has no
        // side to prefer
        EXPECT_TRUE(mirror_symmetric(b.positions, 0, 0.0, 1e-9 * dx));
        EXPECT_TRUE(mirror_symmetric(b.positions, 2, R, 1e-9 * dx));
        const auto d = nearest_distances(b.positions, 2 * dx);
        EXPECT_GT(*std::min_element(d.begin(), d.end()), 0.9 * dx);
        EXPECT_LT(*std::max_element(d.begin(), d.end()), 1.1 * dx);
      }
  }

  TEST(SphFittedBodies, RejectsBadSizes)
  {
    EXPECT_THROW(make_fitted_cylinder(0.05, 0.1, -1e-3), std::invalid_argument);
    EXPECT_THROW(make_fitted_disc(0.05, std::nan(""), 1e-3), std::invalid_argument);
  }
} // namespace
