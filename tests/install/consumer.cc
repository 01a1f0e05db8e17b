// A program outside cosim's tree built against the installed package: an SPH lattice of the
// UCS cylinder and one short coupled run through coupling::run_case. Exit 0 when both answer as
// they must.
#include <coupling/run_case.h>
#include <sph/lattice.h>

#include <cmath>
#include <cstdio>
#include <numeric>

int main()
{
  constexpr double pi = 3.14159265358979323846;
  // the lattice's volumes are scaled to the true cylinder's (sph/lattice.h): round-off only
  const auto lattice = sph::make_cylinder<3>(0.05, 0.1, 0.005);
  const double volume = std::accumulate(lattice.volumes.begin(), lattice.volumes.end(), 0.0);
  const double exact  = pi * 0.025 * 0.025 * 0.1;
  std::printf("consumer: %zu particles, volume %.6e m^3 (cylinder %.6e)\n", lattice.positions.size(), volume,
              exact);
  if (lattice.positions.empty() || std::abs(volume - exact) > 1e-9 * exact)
    return 1;

  // an elastic UCS at 8 mm spacing (the coarsest the specimen allows: a sixth of its diameter), stopped at 0.05 % strain: a few hundred steps
  coupling::CaseParameters parameters;
  parameters.rock.model           = sph::RockModel::elastic;
  parameters.sph.spacing          = 0.008;
  parameters.loading.end_strain   = 5e-4;
  parameters.output.progress      = false;
  coupling::RunObserver observer;
  const coupling::Summary summary = coupling::run_case(parameters, observer);
  std::printf("consumer: %zu steps, final stress %.3f MPa\n", summary.n_steps, summary.peak_stress / 1e6);
  return summary.n_steps > 0 && summary.peak_stress > 0 ? 0 : 1;
}
