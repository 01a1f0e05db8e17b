// The quasi-static check's kinetic energy: only the part of the motion that is not a homogeneous
// deformation counts (coupling/src/driver_common.h, non_affine_kinetic_energy).
#include "../../coupling/src/driver_common.h"

#include <sph/body.h>
#include <sph/lattice.h>

#include <gtest/gtest.h>

#include <cmath>

using namespace coupling;

namespace
{
  sph::Body<3> block()
  {
    sph::Parameters prm;
    prm.spacing    = 2e-3;
    const auto lat = sph::make_block<3>(sph::Vector<3>(0, 0, 0), sph::Vector<3>(0.02, 0.016, 0.03),
                                        prm.spacing);
    return sph::Body<3>(prm, sph::MaterialParameters(), lat.positions, lat.volumes);
  }

  double kinetic_energy(const sph::Body<3> &b)
  {
    double e = 0;
    for (unsigned int i = 0; i < b.n_particles(); ++i)
      e += 0.5 * b.masses()[i] * b.velocities()[i].squaredNorm();
    return e;
  }
} // namespace

TEST(NonAffineKineticEnergy, AnAffineVelocityFieldHasNone)
{
  // a rigid translation plus rotation plus a uniform strain rate: affine, so nothing remains but
  // round-off (1e-12 of the whole kinetic energy: the fit's normal equations are 4 x 4)
  sph::Body<3> b = block();
  const auto &x  = b.positions();
  for (unsigned int i = 0; i < b.n_particles(); ++i)
  {
    const sph::Vector<3> &p = x[i];
    b.set_velocity(i, sph::Vector<3>(0.3 - 2.0 * p[1] + 5.0 * p[0], -0.1 + 2.0 * p[0] + 1.0 * p[1],
                                     0.7 - 40.0 * p[2]));
  }
  const double total = kinetic_energy(b);
  ASSERT_GT(total, 0.0);
  EXPECT_LT(non_affine_kinetic_energy(b), 1e-12 * total);
}

TEST(NonAffineKineticEnergy, AWaveOnTopOfTheLoadingKeepsItsOwnEnergy)
{
  // v_z = -40 z (loading at a uniform rate) plus a standing wave a cos(2 pi z / L) over the block
  // height L. On the 15 equal layers of cell centres the wave sums to zero and is even about
  // mid-height, so it is orthogonal to 1, x, y and z: the non-affine energy must be exactly the
  // wave's own kinetic energy (to round-off, 1e-10), however large the loading's
  sph::Body<3> b = block();
  sph::Body<3> w = block();
  const auto &x  = b.positions();
  const double L = 0.03;
  for (unsigned int i = 0; i < b.n_particles(); ++i)
  {
    const double z    = x[i][2];
    const double wave = 0.05 * std::cos(2 * M_PI * z / L);
    b.set_velocity(i, sph::Vector<3>(0, 0, -40.0 * z + wave));
    w.set_velocity(i, sph::Vector<3>(0, 0, wave));
  }
  const double wave_energy = kinetic_energy(w);
  EXPECT_NEAR(non_affine_kinetic_energy(b) / wave_energy, 1.0, 1e-10);
  // the loading alone holds far more than the wave (about 400 times): the quasi-static check
  // would measure the loading rate, not the wave, without removing it
  EXPECT_GT(kinetic_energy(b), 100.0 * wave_energy);
}
