// The coupled-simulator check of `cosim diagnose`: one run_case of a strength test per model and
// condition, at a coarse spacing, its peak stress compared with the measured one.
#include "diagnose_model.h"

#include <coupling/case_parameters.h>
#include <coupling/run_case.h>
#include <coupling/run_output.h>

#include <algorithm>

namespace diagnose
{
  using coupling::CaseParameters;
  using coupling::Summary;
  using coupling::RunObserver;
  using coupling::run_case;

  CoupledPeak coupled_peak(const std::string &test, const double s3_MPa, const sph::MaterialParameters &rock,
                           const double spacing, const double end_strain)
  {
    CaseParameters c;
    c.name               = "diagnose-check";
    c.test               = test == "BTS" ? "BTS" : (s3_MPa > 0 ? "CTCS" : "UCS");
    c.diameter           = 0.05;
    c.length             = test == "BTS" ? 0.025 : 0.1;
    c.confining_pressure = s3_MPa * 1e6;
    c.rock               = rock;
    // the 25 mm disc needs at least 10 particles through its thickness (a BTS run at 2.5 mm is
    // seconds); the cylinders take the spacing asked for
    c.sph.spacing        = test == "BTS" ? std::min(spacing, 0.0025) : spacing;
    c.loading.end_strain = end_strain;
    c.output.progress    = false;
    c.output.n_snapshots = 0;
    RunObserver quiet;
    const Summary r = run_case(c, quiet);
    // strain_at_peak is the platen displacement over the length (BTS: over the diameter)
    const double gauge = test == "BTS" ? c.diameter : c.length;
    return {r.peak_stress / 1e6, r.strain_at_peak * gauge * 1e3, r.stop_reason};
  }
} // namespace diagnose
