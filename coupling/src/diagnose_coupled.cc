// The coupled-simulator check of `cosim diagnose`: one run_case of a chosen test per model, at a
// coarse spacing, its peak stress compared with the measured one.
#include "diagnose_model.h"

#include <coupling/case_parameters.h>
#include <coupling/run_case.h>
#include <coupling/run_output.h>

namespace coupling::diagnose
{
  double coupled_peak_stress(const std::string &test, const double s3_MPa,
                             const RockParameters &rock, const double spacing)
  {
    CaseParameters c;
    c.name               = "diagnose-check";
    c.test               = test == "BTS" ? "BTS" : (s3_MPa > 0 ? "CTCS" : "UCS");
    c.diameter           = 0.05;
    c.length             = test == "BTS" ? 0.025 : 0.1;
    c.confining_pressure = s3_MPa * 1e6;
    c.rock               = rock;
    c.sph.spacing        = spacing;
    c.output.progress    = false;
    c.output.n_snapshots = 0;
    RunObserver quiet;
    return run_case(c, quiet).peak_stress / 1e6;
  }
} // namespace coupling::diagnose
