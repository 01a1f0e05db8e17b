#pragma once
/// @file
/// The entry point of the coupled drivers: one UCS / BTS / CTCS run.

#include <coupling/case_parameters.h>
#include <coupling/run_output.h>

#include <stdexcept>
#include <string>

namespace coupling
{
  /// A mistake in what a user gave (parameters, data files): the app prints what() on one line
  /// and exits with status 2.
  class InputError : public std::runtime_error
  {
  public:
    using std::runtime_error::runtime_error;
  };

  /// A run that went unstable (non-finite value, particle leaving the domain, energy blow-up).
  class InstabilityError : public std::runtime_error
  {
  public:
    using std::runtime_error::runtime_error;
  };

  /// A run that stopped on request (signal, or Output/Stop after steps) after writing a final
  /// checkpoint through RunObserver::checkpoint; the state given there continues it.
  class RunInterrupted : public std::runtime_error
  {
  public:
    using std::runtime_error::runtime_error;
  };

  /// Runs one case to its stop criterion, reporting to `observer`. With `resume` (a state from
  /// RunObserver::checkpoint of a run with the same parameters), continues that run: the history
  /// rows it had are reported again first, then the run goes on as if never stopped. Throws
  /// InputError for inconsistent parameters or a state of another case, InstabilityError when the
  /// run goes unstable, RunInterrupted when it stopped on request.
  Summary run_case(const CaseParameters &parameters, RunObserver &observer,
                   const StateArrays *resume = nullptr);
} // namespace coupling
