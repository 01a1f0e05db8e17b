/// @file
/// run_case: one run of any test type, dispatched to its driver (SpecimenDriver for UCS, BTS,
/// CTCS; CuttingDriver for indentation and linear cutting), both run by RunLoop.

#include "cutting_driver.h"
#include "driver_common.h"
#include "specimen_driver.h"

#include <coupling/errors.h>
#include <coupling/run_case.h>

namespace coupling
{
  Summary run_case(const CaseParameters &parameters, RunObserver &observer,
                   const StateArrays *resume)
  {
    const ThreadLimit threads(parameters.sph.n_threads);
    // more than one MPI rank: the SPH body is split into subdomains whose ghosts stay those of
    // the reference configuration (total Lagrangian); particles do not migrate between ranks
    const int n_ranks = mpi_ranks();
    if (n_ranks > 1)
    {
      const std::string n         = std::to_string(n_ranks) + " MPI ranks given";
      const sph::Formulation form = parameters.sph.form;
      if (form != sph::Formulation::total_lagrangian &&
          form != sph::Formulation::total_lagrangian_corrected)
        throw InputError("SPH/FORM: the updated Lagrangian forms (0, 1) run on one MPI rank only (" +
                         n + "); use FORM 7 or 8, or run without mpirun");
    }
    if (parameters.test == "indentation" || parameters.test == "linear-cutting")
    {
      CuttingDriver test(parameters);
      return test.run(observer, resume);
    }
    SpecimenDriver test(parameters);
    return test.run(observer, resume);
  }
} // namespace coupling
