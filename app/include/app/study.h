#pragma once
/// @file
/// `cosim study`: a parameter sweep over one case. Every combination of the varied keys (and
/// rock groups) is a `cosim run` into a subfolder of OUTDIR; the results go into study.csv (one
/// row per run: the varied values, peak stress, the reference strength and the error against it,
/// moduli, strain and displacement at peak, steps, wall time, quasi-static checks) and study.png
/// (tools/plot_study.py). OUTDIR is written through a staging sibling, as `cosim run` does.

#include <coupling/run_output.h>

#include <string>
#include <vector>

namespace app
{
  /// The strength a run is compared with, in compression-positive Pa (BTS: the tensile strength).
  struct StudyReference
  {
    double measured = 0; ///< the data: Table 3 UCS / BTS; CTCS: the envelope of Table 3's measured
                         ///< c, phi where the group has them, else of the c, phi in use [Pa]
    double envelope =
      0; ///< the closed form for the c, phi in use (Eqs. 14-15; CTCS:
         ///< 2c cos(phi)/(1 - sin(phi)) + sigma3 (1 + sin(phi))/(1 - sin(phi))) [Pa]
    std::string description; ///< where `measured` comes from, e.g. "Table 3 UCS"
  };

  /// `cosim study CASE.prm --key K --values a,b,... [--vary "K=a,b"] [--groups M1,M2|all] [-o
  /// OUTDIR]
  /// [--set "S/K=v"] [--force] [--quiet]` (arguments after the subcommand). Returns the exit
  /// status: 0 done, 2 bad input (nothing written), 3 some runs unstable (the table marks them), 1
  /// other.
  int study_main(const std::vector<std::string> &args);
  /// Help text of `cosim study`.
  std::string study_help();
} // namespace app
