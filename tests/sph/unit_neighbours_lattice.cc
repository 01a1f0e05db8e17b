#include <sph/lattice.h>
#include <sph/neighbour_search.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace
{
  using namespace sph;

  template <int dim>
  void check_against_brute_force(const int n, const unsigned seed)
  {
    std::mt19937                           rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<Vector<dim>>               x(n);
    for (auto &p : x)
      for (int d = 0; d < dim; ++d)
        p[d] = u(rng) * (d == 0 ? 3.0 : 1.0);
    // some coincident and boundary-distance points
    x[1] = x[0];
    PairList a, b;
    const double radius = dim == 2 ? 0.08 : 0.2;
    find_pairs<dim>(x, radius, a);
    find_pairs_brute_force<dim>(x, radius, b);
    ASSERT_GT(b.n_pairs(), 100u) << "the fixture must have many pairs";
    EXPECT_EQ(a.first, b.first);
    EXPECT_EQ(a.second, b.second);
    EXPECT_EQ(a.offsets, b.offsets);
    EXPECT_EQ(a.incidence, b.incidence);
  }

  TEST(SphNeighbours, CellListEqualsBruteForce2d) { check_against_brute_force<2>(3000, 1); }
  TEST(SphNeighbours, CellListEqualsBruteForce3d) { check_against_brute_force<3>(3000, 2); }

  TEST(SphLattice, CylinderVolumesAndSections)
  {
    const double       D = 0.05, L = 0.1, dx = 0.0025;
    const Lattice<3>   lat = make_cylinder<3>(D, L, dx);
    double             v   = 0;
    Vector<3>          lo  = lat.positions[0], hi = lat.positions[0];
    for (std::size_t i = 0; i < lat.positions.size(); ++i)
      {
        v += lat.volumes[i];
        lo = lo.cwiseMin(lat.positions[i]);
        hi = hi.cwiseMax(lat.positions[i]);
      }
    // sum of scaled volumes: round-off only
    EXPECT_NEAR(v, M_PI * D * D / 4 * L, 1e-12 * v);
    EXPECT_NEAR(lat.true_section_area, M_PI * D * D / 4, 1e-15);
    // the lattice section of a 20 x 20 cell cylinder is within a few % of the disc (staircase)
    EXPECT_NEAR(lat.lattice_section_area / lat.true_section_area, 1.0, 0.05);
    // cell centres: half a spacing inside the ends
    EXPECT_NEAR(lo[2], 0.5 * dx, 1e-12);
    EXPECT_NEAR(hi[2], L - 0.5 * dx, 1e-12);
    EXPECT_NEAR(lo[0] + hi[0], 0.0, 1e-12); // centred on the axis
  }

  TEST(SphLattice, DiscRestsOnZeroAndIsCentred)
  {
    const double     D = 0.05, t = 0.025, dx = 0.0025;
    const Lattice<3> lat = make_disc<3>(D, t, dx);
    double           v = 0, zmin = 1, ysum = 0;
    for (std::size_t i = 0; i < lat.positions.size(); ++i)
      {
        v += lat.volumes[i];
        zmin = std::min(zmin, lat.positions[i][2]);
        ysum += lat.positions[i][1];
      }
    EXPECT_NEAR(v, M_PI * D * D / 4 * t, 1e-12 * v);
    EXPECT_NEAR(zmin, 0.5 * dx, 1e-12); // lowest cell centre half a spacing above z = 0
    EXPECT_NEAR(ysum, 0.0, 1e-12);      // symmetric about y = 0
    EXPECT_NEAR(lat.true_section_area, D * t, 1e-15);
    EXPECT_NEAR(lat.lattice_section_area / lat.true_section_area, 1.0, 0.05);
  }

  // A flattened disc (loading angle 2 alpha = 20 deg): at every spacing its outer rows reach the
  // flats at D/2 -+ R cos(alpha) exactly (the platens rest there), the flats are 2 R sin(alpha)
  // wide to within the chord of one row (d(width)/dz = 2 cot(alpha) dz / 2 at the flat's edge,
  // plus a cell for the staircase), and the volumes sum to the circle less its two segments.
  TEST(SphLattice, FlattenedDiscHasItsFlatsAtEverySpacing)
  {
    const double D = 0.05, t = 0.025, R = 0.5 * D, angle = 20 * M_PI / 180, a = 0.5 * angle;
    for (const double dx : {0.0025, 0.0022, 0.00125})
      {
        const Lattice<3> lat = make_disc<3>(D, t, dx, angle);
        const double     dz  = lat.cell_size[2];
        double           v = 0, zmax = -1, zmin = 1;
        for (std::size_t i = 0; i < lat.positions.size(); ++i)
          {
            v += lat.volumes[i];
            zmax = std::max(zmax, lat.positions[i][2]);
            zmin = std::min(zmin, lat.positions[i][2]);
          }
        EXPECT_NEAR(zmax + 0.5 * dz, R + R * std::cos(a), 1e-12) << dx;
        EXPECT_NEAR(zmin - 0.5 * dz, R - R * std::cos(a), 1e-12) << dx;
        // rows H / round(H / dx) apart, H = D cos(alpha): round() moves H / dx by at most 1/2,
        // so |dz / dx - 1| <= dx / (2 H - dx) (2.6 % at 2.5 mm)
        const double H = D * std::cos(a);
        EXPECT_LE(std::abs(dz / dx - 1.0), dx / (2 * H - dx) * (1 + 1e-12)) << dx;
        double xmax = 0;
        for (const auto &x : lat.positions)
          if (x[2] == zmax)
            xmax = std::max(xmax, std::abs(x[0]));
        const double half_width = xmax + 0.5 * dx; // the top row's extent
        EXPECT_GT(half_width, R * std::sin(a)) << dx;
        EXPECT_LT(half_width, R * std::sin(a) + dz / std::tan(a) + dx) << dx;
        const double face = M_PI * R * R - R * R * (angle - std::sin(angle));
        EXPECT_NEAR(v, face * t, 1e-12 * v) << dx;
        EXPECT_NEAR(lat.true_section_area, 2 * R * std::cos(a) * t, 1e-15) << dx;
      }
    // 0: the round disc, unchanged; beyond 60 deg or negative: refused
    EXPECT_EQ(make_disc<3>(D, t, 0.0025, 0.0).positions.size(), make_disc<3>(D, t, 0.0025).positions.size());
    EXPECT_THROW(make_disc<3>(D, t, 0.0025, -0.1), std::invalid_argument);
    EXPECT_THROW(make_disc<3>(D, t, 0.0025, 1.1), std::invalid_argument);
  }

  TEST(SphLattice, RejectsNonPositiveSizes)
  {
    EXPECT_THROW(make_cylinder<3>(-0.05, 0.1, 0.001), std::invalid_argument);
    EXPECT_THROW(make_disc<2>(0.05, 0.02, 0.0), std::invalid_argument);
  }
} // namespace
