// Distributed bodies without MPI: the bisection split, the ghost layers against a brute-force
// search, and the property the distributed runs rest on: a body built from one part's local
// particles (sph::local_particles, three hops) computes its owned particles' forces with the
// serial body's bits (same neighbours, same chunk order, same reference centre).
#include <sph/body.h>
#include <sph/domain.h>
#include <sph/lattice.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <set>

namespace
{
  using namespace sph;

  Parameters numerics(const bool single_precision)
  {
    Parameters p;
    p.spacing          = 0.005;
    p.n_threads        = 2;
    p.single_precision = single_precision;
    return p;
  }

  MaterialParameters rock_material()
  {
    MaterialParameters m;
    m.model          = RockModel::mohr_coulomb;
    m.youngs_modulus = 50e9;
    m.poissons_ratio = 0.25;
    m.cohesion       = 1e6; // low: the deformation below yields somewhere
    m.friction_angle = 0.5;
    return m;
  }

  /// A velocity field with shear and a non-affine part [m/s].
  Vector<3> velocity(const Vector<3> &x)
  {
    return Vector<3>(0.3 * x[2] + 2.0 * x[0] * x[1], -0.2 * x[0], -1.0 * x[2] + 40.0 * x[0] * x[0]);
  }
} // namespace

TEST(Domain, BisectionSplitsEvenlyAlongTheLongestSide)
{
  const Lattice<3>       lattice = make_cylinder<3>(0.05, 0.1, 0.005);
  const std::size_t      n       = lattice.positions.size();
  for (const int parts : {2, 3, 4})
    {
      const std::vector<int> owners = bisection_owners<3>(lattice.positions, parts);
      EXPECT_EQ(owners, bisection_owners<3>(lattice.positions, parts)); // deterministic
      std::vector<std::size_t> count(parts, 0);
      for (const int o : owners)
        ++count[o];
      for (const std::size_t c : count) // each part within one particle of n / parts
        EXPECT_LE(std::abs(static_cast<double>(c) - static_cast<double>(n) / parts), 1.0);
    }
  // two parts of a cylinder twice as long as wide: cut across its axis z
  const std::vector<int> two = bisection_owners<3>(lattice.positions, 2);
  double top_of_0 = -1, bottom_of_1 = 1;
  for (std::size_t i = 0; i < n; ++i)
    (two[i] == 0 ? top_of_0 : bottom_of_1) =
      two[i] == 0 ? std::max(top_of_0, lattice.positions[i][2]) :
                    std::min(bottom_of_1, lattice.positions[i][2]);
  EXPECT_LE(top_of_0, bottom_of_1);
}

TEST(Domain, GhostLayersAreTheNeighbourHops)
{
  const Lattice<3>             lattice = make_cylinder<3>(0.05, 0.1, 0.005);
  const auto                  &x       = lattice.positions;
  const std::vector<int>       owners  = bisection_owners<3>(x, 3);
  const double                 radius  = 2.0 * 1.2 * 0.005;
  std::set<std::int32_t>       expected;
  for (std::size_t i = 0; i < x.size(); ++i)
    if (owners[i] == 1)
      expected.insert(static_cast<std::int32_t>(i));
  for (int layers = 1; layers <= 3; ++layers)
    {
      // brute force: everything within `radius` of the set so far
      std::set<std::int32_t> next = expected;
      for (std::size_t j = 0; j < x.size(); ++j)
        for (const std::int32_t i : expected)
          if ((x[j] - x[i]).norm() <= radius)
            {
              next.insert(static_cast<std::int32_t>(j));
              break;
            }
      expected.swap(next);
      const std::vector<std::int32_t> local = local_particles<3>(x, owners, 1, radius, layers);
      EXPECT_EQ(local, std::vector<std::int32_t>(expected.begin(), expected.end())) << layers;
    }
}

class DomainForces : public ::testing::TestWithParam<bool>
{};

TEST_P(DomainForces, PartOfTheBodyGivesItsParticlesTheSerialForces)
{
  const bool       single = GetParam(); // the pair force in mixed or in double precision
  const Lattice<3> lattice = make_cylinder<3>(0.05, 0.1, 0.005);
  const auto      &X       = lattice.positions;
  const double     dt      = 1e-4; // one step of a strain ~1e-4: past the yield stress
  Body<3>          whole(numerics(single), rock_material(), X, lattice.volumes);
  whole.add_loaded_face(Vector<3>(0, 0, 1));
  whole.add_loaded_face(Vector<3>(0, 0, -1));
  whole.set_surface_pressure(5e6);
  // the serial chunks, as a distributed driver derives them from the parts' pair counts
  std::vector<std::int64_t> pair_begin(X.size() + 1, 0);
  for (unsigned i = 0; i < X.size(); ++i)
    pair_begin[i + 1] = pair_begin[i] + whole.n_pairs_as_first(i);
  const std::vector<std::int32_t> starts = Body<3>::work_chunks(pair_begin, 0);
  ASSERT_GT(starts.size(), 3u); // several chunks: the order across them matters
  Vector<3> lo = X[0], hi = X[0];
  for (const auto &p : X)
    {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }

  const std::vector<int> owners = bisection_owners<3>(X, 3);
  for (int rank = 0; rank < 3; ++rank)
    {
      SCOPED_TRACE(rank);
      const std::vector<std::int32_t> local =
        local_particles<3>(X, owners, rank, 2.0 * 1.2 * 0.005, 3);
      std::vector<Vector<3>>    x;
      std::vector<double>       v;
      std::vector<std::int32_t> chunk_of;
      std::vector<std::uint8_t> owned;
      for (const std::int32_t g : local)
        {
          x.push_back(X[g]);
          v.push_back(lattice.volumes[g]);
          chunk_of.push_back(
            static_cast<std::int32_t>(std::upper_bound(starts.begin(), starts.end(), g) - starts.begin()) - 1);
          owned.push_back(owners[g] == rank);
        }
      Body<3> part(numerics(single), rock_material(), x, v);
      part.set_chunks(chunk_of);
      part.set_owned(owned);
      part.set_reference_centre(0.5 * (lo + hi));
      part.add_loaded_face(Vector<3>(0, 0, 1), hi[2]);
      part.add_loaded_face(Vector<3>(0, 0, -1), -lo[2]);
      part.set_surface_pressure(5e6);
      // one step of the same motion on both (from rest: no forces yet, so the ghosts move as
      // their owners do; later steps need Body::exchange_ghosts)
      Body<3> &serial = whole;
      if (rank == 0) // the whole body once, for all three parts
        {
          for (unsigned i = 0; i < X.size(); ++i)
            serial.set_velocity(i, velocity(serial.positions()[i]));
          serial.integrate(dt);
          serial.compute_forces();
        }
      for (unsigned k = 0; k < local.size(); ++k)
        part.set_velocity(k, velocity(part.positions()[k]));
      part.integrate(dt);
      part.compute_forces();
      std::size_t n_owned = 0;
      for (unsigned k = 0; k < local.size(); ++k)
        {
          if (!owned[k])
            continue;
          ++n_owned;
          const std::int32_t g = local[k];
          ASSERT_EQ(std::memcmp(part.internal_forces()[k].data(), serial.internal_forces()[g].data(),
                                3 * sizeof(double)),
                    0)
            << "particle " << g;
          ASSERT_EQ(std::memcmp(part.pressure_forces()[k].data(), serial.pressure_forces()[g].data(),
                                3 * sizeof(double)),
                    0)
            << "particle " << g;
          ASSERT_EQ(std::memcmp(part.stress3(k).data(), serial.stress3(g).data(), 9 * sizeof(double)), 0);
        }
      EXPECT_GT(n_owned, 0u);
    }
  EXPECT_GT(whole.energies().plastic, 0.0); // the motion did reach the yield surface
}

INSTANTIATE_TEST_SUITE_P(Domain, DomainForces, ::testing::Bool());
