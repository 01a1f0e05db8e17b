// sph_bench: particle-steps per second and peak RSS of a 3-D cylinder in uniaxial compression
// (FORM 8, Mohr-Coulomb, artificial viscosity, hourglass control). Not a test.
// Usage: sph_bench [spacing_m = 1.2e-3] [steps = 200] [threads = 0 (all)] [mixed|double = mixed]
//                  [chunks = 0 (automatic)]
// (the pair force's precision, Parameters::single_precision; the work units, Parameters::chunks)
#include <sph/body.h>
#include <sph/lattice.h>

#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>

int main(int argc, char **argv)
{
  const double dx      = argc > 1 ? std::atof(argv[1]) : 1.2e-3;
  const int    n_steps = argc > 2 ? std::atoi(argv[2]) : 200;
  const int    threads = argc > 3 ? std::atoi(argv[3]) : 0;
  const std::string precision = argc > 4 ? argv[4] : "mixed";
  if (precision != "mixed" && precision != "double")
    {
      std::fprintf(stderr, "sph_bench: pair force precision '%s' is not one of mixed, double\n",
                   precision.c_str());
      return 2;
    }
  const bool single = precision == "mixed";
  const int  chunks = argc > 5 ? std::atoi(argv[5]) : 0;

  sph::Parameters prm;
  prm.spacing   = dx;
  prm.n_threads = threads;
  prm.single_precision = single;
  prm.chunks           = chunks;
  sph::MaterialParameters mat; // defaults: M1 basalt, Mohr-Coulomb
  mat.softening_strain = 2e-3;

  const auto  t_setup = std::chrono::steady_clock::now();
  const auto  lat     = sph::make_cylinder<3>(0.05, 0.1, dx);
  sph::Body<3> body(prm, mat, lat.positions, lat.volumes);
  const double setup =
    std::chrono::duration<double>(std::chrono::steady_clock::now() - t_setup).count();
  const unsigned n = body.n_particles();
  for (unsigned i = 0; i < n; ++i)
    {
      const double z = lat.positions[i][2];
      if (z < dx)
        body.constrain(i, 2, 0.0);
      else if (z > 0.1 - dx)
        body.constrain(i, 2, -0.5); // 0.5 m/s: plastic flow within the run
    }
  timespec c0, c1;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &c0);
  const auto t0 = std::chrono::steady_clock::now();
  for (int s = 0; s < n_steps; ++s)
    {
      body.compute_forces();
      body.integrate(body.stable_time_step());
    }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &c1);
  const double cpu = (c1.tv_sec - c0.tv_sec) + 1e-9 * (c1.tv_nsec - c0.tv_nsec);
  struct rusage usage;
  getrusage(RUSAGE_SELF, &usage);
  const double rss_kb = static_cast<double>(usage.ru_maxrss);
  std::printf("particles %u  pairs %zu  steps %d  setup %.2f s  wall %.2f s  pair force %s\n", n,
              body.n_pairs(), n_steps, setup, wall, body.single_precision() ? "mixed" : "double");
  std::printf("particle-steps/s %.3g  peak RSS %.0f MB  (%.0f bytes/particle incl. process)\n",
              n * static_cast<double>(n_steps) / wall, rss_kb / 1024, rss_kb * 1024 / n);
  // CPU seconds of all threads in the time loop: on a shared machine the wall clock measures the
  // load of others; per CPU second is the per-core rate (spin-waiting threads count as busy)
  std::printf("cpu %.2f s  particle-steps per CPU second %.3g  (load average: see /proc/loadavg)\n",
              cpu, n * static_cast<double>(n_steps) / cpu);
  // fingerprint of the final state: equal across builds and runs iff the results are bitwise equal
  double checksum = 0;
  for (unsigned i = 0; i < n; ++i)
    checksum += body.positions()[i].sum() + 1e-9 * body.stress3(i).sum();
  std::printf("state checksum %a\n", checksum);
  return 0;
}
