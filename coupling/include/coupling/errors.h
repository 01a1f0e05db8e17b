#pragma once
/// @file
/// The exceptions a run can end with. The app maps them to exit status: InputError 2,
/// InstabilityError 3; RunInterrupted leaves a checkpoint to continue from.

#include <stdexcept>

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
} // namespace coupling
