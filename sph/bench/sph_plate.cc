// sph_plate: our solver on PySPH's solid_mech/oscillating_plate example (Gray, Monaghan & Swift
// 2001), particle for particle: the same plate and wall positions (dx = 2 mm or the dx given, plate
// 0.2 m x 0.02 m
// plus L/4 inside a 3-layer wall), the same first-mode velocity profile, the same fixed dt and
// number of steps. Differences, by design: our wall and the plate part inside it are clamped
// (velocity 0) where PySPH's wall holds the plate through the SPH sums; FORM 8 (TL + correction)
// instead of PySPH's updated-Lagrangian scheme with XSPH and artificial stress. Not a test; run by
// tools/bench --pysph.
// Usage: sph_plate [steps = 15000] [dt = 1e-5] [vf = 0.01] [threads = 1] [dx = 0.002]
// Prints particles, steps, wall and CPU seconds, particle-steps/s and the period measured from
// the tip's first downward zero crossing (t = T/2 for y = A sin(omega t)) against thin-plate
// theory.
#include <sph/body.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <vector>

namespace
{
  double cpu_seconds()
  {
    timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
  }

  /// numpy.mgrid[a:b:s] along one axis: a, a+s, ... while < b (s > 0) or > b (s < 0).
  std::vector<double> mgrid(const double a, const double b, const double s)
  {
    std::vector<double> r;
    const long n = static_cast<long>(std::ceil((b - a) / s));
    for (long k = 0; k < n; ++k)
      r.push_back(a + k * s);
    return r;
  }
} // namespace

int main(int argc, char **argv)
{
  using namespace sph;
  const int n_steps = argc > 1 ? std::atoi(argv[1]) : 15000;
  const double dt   = argc > 2 ? std::atof(argv[2]) : 1e-5;
  const double vf   = argc > 3 ? std::atof(argv[3]) : 0.01;
  const int threads = argc > 4 ? std::atoi(argv[4]) : 1;
  const double dx   = argc > 5 ? std::atof(argv[5]) : 0.002;
  if (!(dx > 0 && dx <= 0.01))
  {
    std::fprintf(stderr, "sph_plate: dx must be in (0, 0.01] m\n");
    return 2;
  }

  // PySPH's geometry (oscillating_plate.py: create_plate, create_wall)
  const double L = 0.2, H = 0.02, inside = L / 4;
  const int layers = 3;
  std::vector<Vector<2>> x;
  std::vector<bool> wall;
  for (const double xp : mgrid(-inside, L + dx / 2, dx))
    for (const double yp : mgrid(-H / 2, H / 2 + dx / 2, dx))
    {
      x.emplace_back(xp, yp);
      wall.push_back(false);
    }
  const double y_min = -H / 2, y_max = mgrid(-H / 2, H / 2 + dx / 2, dx).back();
  for (const double xw : mgrid(-inside, dx / 2, dx)) // lower
    for (const double yw : mgrid(y_min - dx, y_min - dx - (layers - 1) * dx - dx / 2, -dx))
    {
      x.emplace_back(xw, yw);
      wall.push_back(true);
    }
  for (const double xw : mgrid(-inside, dx / 2, dx)) // upper
    for (const double yw : mgrid(y_max + dx, y_max + dx + (layers - 1) * dx + dx / 2, dx))
    {
      x.emplace_back(xw, yw);
      wall.push_back(true);
    }
  for (const double xw : mgrid(-inside - dx, -inside - dx - (layers - 1) * dx - dx / 2, -dx))
    for (const double yw :
         mgrid(y_min - dx - (layers - 1) * dx, y_max + dx + (layers - 1) * dx + dx / 2, dx))
    {
      x.emplace_back(xw, yw);
      wall.push_back(true);
    }

  const double E = 2e6, nu = 0.3975, rho = 1000;
  Parameters prm;
  prm.spacing   = dx;
  prm.cslh      = 1.3; // PySPH: h = 1.3 dx
  prm.av_alpha  = 1.0; // PySPH: alpha = beta = 1
  prm.av_beta   = 1.0;
  prm.n_threads = threads;
  MaterialParameters m;
  m.model          = RockModel::elastic;
  m.density        = rho;
  m.youngs_modulus = E;
  m.poissons_ratio = nu;
  Body<2> body(prm, m, x, std::vector<double>(x.size(), dx * dx));

  const double kL = 1.875, k = kL / L;
  const double M = std::sin(kL) + std::sinh(kL), N = std::cos(kL) + std::cosh(kL);
  const double Q  = 2 * (std::cos(kL) * std::sinh(kL) - std::sin(kL) * std::cosh(kL));
  const double c0 = std::sqrt(E / (3 * (1 - 2 * nu) * rho)); // PySPH's plate.cs
  int tip         = -1;
  for (unsigned i = 0; i < body.n_particles(); ++i)
  {
    const double xi = x[i][0];
    if (wall[i] || xi < 0)
    {
      body.constrain(i, 0, 0.0);
      body.constrain(i, 1, 0.0);
    }
    else if (xi > 0)
    {
      const double f =
        M * (std::cos(k * xi) - std::cosh(k * xi)) - N * (std::sin(k * xi) - std::sinh(k * xi));
      body.set_velocity(i, Vector<2>(0.0, vf * c0 * f / Q));
    }
    if (!wall[i] && std::abs(xi - L) < 1e-9 && std::abs(x[i][1]) < 1e-9)
      tip = static_cast<int>(i); // PySPH's amplitude_idx: middle of the last column
  }
  if (tip < 0)
  {
    std::fprintf(stderr, "sph_plate: no tip particle\n");
    return 1;
  }

  const double omega  = std::sqrt(E * H * H * std::pow(k, 4) / (12 * rho * (1 - nu * nu)));
  const double period = 2 * M_PI / omega;
  double t = 0, y_old = 0, t_half = -1;
  const double c_start = cpu_seconds();
  const auto w_start   = std::chrono::steady_clock::now();
  for (int s = 0; s < n_steps; ++s)
  {
    body.compute_forces();
    body.integrate(dt);
    t += dt;
    const double y = body.positions()[tip][1] - x[tip][1];
    if (t_half < 0 && y_old > 0 && y <= 0)
      t_half = t - dt * y / (y - y_old);
    y_old = y;
    if (!std::isfinite(y))
    {
      std::fprintf(stderr, "sph_plate: unstable at step %d\n", s);
      return 1;
    }
  }
  const double cpu = cpu_seconds() - c_start;
  const double wall_s =
    std::chrono::duration<double>(std::chrono::steady_clock::now() - w_start).count();
  const double ps = static_cast<double>(body.n_particles()) * n_steps;
  std::printf("particles %u\nsteps %d\ndt %g\ndx %g\nwall_s %.3f\ncpu_s %.3f\n", body.n_particles(),
              n_steps, dt, dx, wall_s, cpu);
  std::printf("particle_steps_per_s %.4g\nparticle_steps_per_cpu_s %.4g\n", ps / wall_s, ps / cpu);
  std::printf("analytic_period_s %.5f\nmeasured_period_s %.5f\n", period,
              t_half > 0 ? 2 * t_half : -1.0);
  return 0;
}
