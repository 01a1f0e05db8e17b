// The energy account with artificial viscosity and hourglass control: their powers are summed
// per thread inside the pair loop (no per-pair arrays), so check that the balance closes and
// that the sums do not depend on the thread count beyond round-off.
#include <sph/body.h>
#include <sph/lattice.h>

#include <gtest/gtest.h>

#include <cmath>

namespace
{
  using namespace sph;

  /// A 10 x 10 x 10 elastic block (FORM 8, AV 1/1, hourglass 0.1) with a converging velocity
  /// field plus a non-affine ripple (so both AV and hourglass forces work), 60 steps, no external
  /// forces: everything it dissipates comes out of the initial kinetic energy.
  Energies run(const int threads, double &kinetic0)
  {
    const double dx      = 1e-3;
    const Lattice<3> lat = make_block<3>(Vector<3>(0, 0, 0), Vector<3>(0.01, 0.01, 0.01), dx);
    Parameters prm;
    prm.spacing   = dx;
    prm.av_alpha  = 1.0;
    prm.av_beta   = 1.0;
    prm.hourglass = 0.1;
    prm.n_threads = threads;
    MaterialParameters m;
    m.model = RockModel::elastic;
    Body<3> body(prm, m, lat.positions, lat.volumes);
    for (unsigned i = 0; i < body.n_particles(); ++i)
    {
      const Vector<3> x = lat.positions[i] - Vector<3>(0.005, 0.005, 0.005);
      body.set_velocity(
        i, Vector<3>(-2.0 * x[0] / 0.005, std::sin(1.7e3 * x[0]) * 0.5, -2.0 * x[2] / 0.005));
    }
    kinetic0 = body.energies().kinetic;
    for (int s = 0; s < 60; ++s)
    {
      body.compute_forces();
      body.integrate(body.stable_time_step());
    }
    return body.energies();
  }

  TEST(SphEnergyAccount, ViscousAndHourglassWorkCloseTheBalance)
  {
    double k0        = 0;
    const Energies e = run(1, k0);
    std::cout << "kinetic0 " << k0 << " kinetic " << e.kinetic << " internal " << e.internal
              << " viscous " << e.viscous << " hourglass " << e.hourglass << " plastic "
              << e.plastic << " balance error " << e.balance_error() << std::endl;
    ASSERT_GT(e.viscous, 1e-3 * k0) << "the converging flow must engage the viscosity";
    ASSERT_GT(std::abs(e.hourglass), 1e-6 * k0) << "the ripple must engage the hourglass control";
    // started with kinetic energy k0 and no external work: k0 = kinetic + internal + dissipated
    // up to the time integrator's error. Measured: the sum exceeds k0 by 12.8 % in this violent
    // flow (viscosity takes 93 % of k0 in 60 steps), identical to all printed digits with the
    // per-pair power arrays this replaced (a pre-existing mismatch of the AV power, evaluated at
    // v^n, and the work of the update). A dropped or doubled viscous term moves the closure by
    // e.viscous = 0.93 k0: the bound 0.2 k0 catches that and tolerates the known mismatch.
    const double closure = k0 - (e.kinetic + e.internal + e.dissipated());
    std::cout << "closure " << closure / k0 << " k0" << std::endl;
    EXPECT_LT(std::abs(closure) / k0, 0.2);
  }

  TEST(SphEnergyAccount, DissipationIndependentOfThreadCount)
  {
    double k0        = 0;
    const Energies a = run(1, k0);
    const Energies b = run(2, k0);
    // positions are bitwise equal for any thread count; only the order in which the pair powers
    // are added differs (per-thread chunks): round-off, relative 1e-12 is generous
    EXPECT_NEAR(a.viscous, b.viscous, 1e-12 * std::abs(a.viscous));
    EXPECT_NEAR(a.hourglass, b.hourglass, 1e-12 * std::abs(a.hourglass) + 1e-300);
    EXPECT_NEAR(a.kinetic, b.kinetic, 1e-12 * a.kinetic);
  }
} // namespace
