#pragma once
/// @file
/// The entry point of the coupled drivers: one run of any test type (UCS, BTS, CTCS, indentation, linear cutting).

#include <coupling/case_parameters.h>
#include <coupling/errors.h>
#include <coupling/run_output.h>


namespace coupling
{
  /// Runs one case to its stop criterion, reporting to `observer`. With `resume` (a state from
  /// RunObserver::checkpoint of a run with the same parameters), continues that run: the history
  /// rows it had are reported again first, then the run goes on as if never stopped. Throws
  /// InputError for inconsistent parameters or a state of another case, InstabilityError when the
  /// run goes unstable, RunInterrupted when it stopped on request.
  Summary run_case(const CaseParameters &parameters, RunObserver &observer,
                   const StateArrays *resume = nullptr);
} // namespace coupling
