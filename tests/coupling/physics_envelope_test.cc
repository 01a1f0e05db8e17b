// The curved envelope (Rock/Strength parameters = envelope: Hoek-Brown with sigma_ci = UCS, m_b
// and a fitted to the BTS and Table 3's measured triaxial envelope, cut-off at the BTS) in the
// coupled simulator: group M10's UCS against Table 3 and its CTCS at 30 MPa against the measured
// envelope (Table 3's c, phi), the shipped case files at 5 mm (10 particles across), one thread.
// (Table 4's Mohr-Coulomb, the default, is 2.3x the measured strength at 30 MPa: 979.7 MPa.)
#include "run_helpers.h"

#include <app/case_file.h>
#include <coupling/run_case.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

using namespace coupling;
using namespace coupling::test;

namespace
{
  // Measured at 5 mm: UCS +0.26 % (206.63 against 206.10 MPa), CTCS 30 MPa +1.1 % (433.6 against
  // 428.7; the fitted envelope itself is +0.92 % there). 1 % and 2 % are the acceptance numbers
  // of a default model (UCS within 1 %, triaxial within 5 %) with the fit's own miss added.
  constexpr double TOL_UCS  = 0.01;
  constexpr double TOL_CTCS = 0.02;

  Summary run_m10(const std::string &name, std::vector<std::string> settings)
  {
    settings.insert(settings.end(), {"Rock/Group=M10", "Rock/Model=hoek-brown",
                                     "Rock/Strength parameters=envelope", "SPH/Particle spacing=0.005"});
    CaseParameters p =
      app::read_case_file(std::string(COSIM_SOURCE_DIR) + "/cases/" + name, settings).parameters;
    p.sph.n_threads   = 1;
    p.output.progress = false;
    Keep rows;
    return run_case(p, rows);
  }
} // namespace

TEST(EnvelopeStrength, M10UcsAndTriaxialOnTheMeasuredStrengths)
{
  const Summary ucs = run_m10("ucs/ucs.prm", {});
  std::printf("envelope M10: UCS %.2f MPa (Table 3 206.10)\n", ucs.peak_stress / 1e6);
  EXPECT_NEAR(ucs.peak_stress / 206.10e6, 1.0, TOL_UCS);
  EXPECT_EQ(ucs.stop_reason, "post-peak drop");

  const Summary ctcs = run_m10("ctcs/ctcs.prm", {"Test/Confining pressure=30e6"});
  // Table 3's measured envelope of M10: c 41.37 MPa, phi 48.58 deg
  const double N        = (1 + std::sin(48.58 * M_PI / 180)) / (1 - std::sin(48.58 * M_PI / 180));
  const double measured = 2 * 41.37e6 * std::sqrt(N) + N * 30e6;
  std::printf("envelope M10: CTCS 30 MPa %.2f MPa (measured envelope %.2f)\n", ctcs.peak_stress / 1e6,
              measured / 1e6);
  EXPECT_NEAR(ctcs.peak_stress / measured, 1.0, TOL_CTCS);
  EXPECT_EQ(ctcs.stop_reason, "post-peak drop");
}
