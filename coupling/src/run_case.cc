/// @file
/// run_case: one run of any test type, dispatched to its driver (SpecimenDriver for UCS, BTS,
/// CTCS; CuttingDriver for indentation and linear cutting), both run by RunLoop.

#include "cutting_driver.h"
#include "driver_common.h"
#include "specimen_driver.h"

#include <coupling/run_case.h>

namespace coupling
{
  Summary run_case(const CaseParameters &parameters, RunObserver &observer,
                   const StateArrays *resume)
  {
    const ThreadLimit threads(parameters.sph.n_threads);
    if (parameters.test == "indentation" || parameters.test == "linear-cutting")
    {
      CuttingDriver test(parameters);
      return test.run(observer, resume);
    }
    SpecimenDriver test(parameters);
    return test.run(observer, resume);
  }
} // namespace coupling
