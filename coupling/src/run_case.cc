// Placeholder while the drivers are written (replaced in the coupling commit).
#include <coupling/run_case.h>

namespace coupling
{
  Summary run_case(const CaseParameters &, RunObserver &)
  {
    throw std::logic_error("run_case: the coupled drivers are not built yet");
  }
} // namespace coupling
