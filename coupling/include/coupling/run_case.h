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

  /// Runs one case to its stop criterion, reporting to `observer`. Throws InputError for
  /// inconsistent parameters and InstabilityError when the run goes unstable.
  Summary run_case(const CaseParameters &parameters, RunObserver &observer);
} // namespace coupling
