// sph_gbench: Google Benchmark micro- and whole-step benchmarks of the SPH solver (not a test).
// Run by tools/bench. Counters: particle-steps per second (wall and per CPU second), pair
// interactions per second, and peak heap bytes per particle counted by the allocation hooks below
// (every operator new of the process between the baseline and the end of the measurement, the
// lattice included).
#include <sph/body.h>
#include <sph/kernels.h>
#include <sph/lattice.h>
#include <sph/neighbour_search.h>

#include <benchmark/benchmark.h>
#include <malloc.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <ctime>
#include <new>
#include <random>
#include <vector>

// ---- allocation counting: current and peak bytes of live heap blocks from operator new ----
namespace
{
  std::atomic<long> live_bytes{0};
  std::atomic<long> peak_bytes{0};

  void *counted_alloc(std::size_t size)
  {
    void *p = std::malloc(size == 0 ? 1 : size);
    if (p == nullptr)
      throw std::bad_alloc();
    const long now = live_bytes.fetch_add(static_cast<long>(malloc_usable_size(p))) +
                     static_cast<long>(malloc_usable_size(p));
    long peak = peak_bytes.load();
    while (now > peak && !peak_bytes.compare_exchange_weak(peak, now))
    {}
    return p;
  }

  void counted_free(void *p)
  {
    if (p == nullptr)
      return;
    live_bytes.fetch_sub(static_cast<long>(malloc_usable_size(p)));
    std::free(p);
  }

  /// Starts a peak measurement; returns the baseline (live bytes now).
  long reset_peak()
  {
    const long now = live_bytes.load();
    peak_bytes.store(now);
    return now;
  }

  double cpu_seconds()
  {
    timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
  }
} // namespace

void *operator new(std::size_t size)
{
  return counted_alloc(size);
}
void *operator new[](std::size_t size)
{
  return counted_alloc(size);
}
void operator delete(void *p) noexcept
{
  counted_free(p);
}
void operator delete[](void *p) noexcept
{
  counted_free(p);
}
void operator delete(void *p, std::size_t) noexcept
{
  counted_free(p);
}
void operator delete[](void *p, std::size_t) noexcept
{
  counted_free(p);
}

namespace
{
  using namespace sph;

  // ---- kernels: gradient evaluations per second ----
  template <int dim>
  void bm_grad_w(benchmark::State &state)
  {
    const KernelType type =
      state.range(0) == 0 ? KernelType::cubic_spline : KernelType::wendland_c2;
    const double h = 1.2e-3;
    std::mt19937 gen(7);
    std::uniform_real_distribution<double> u(-2.0 * h, 2.0 * h);
    std::vector<Vector<dim>> x(4096);
    for (auto &xi : x)
      for (int d = 0; d < dim; ++d)
        xi[d] = u(gen);
    for (auto _ : state)
    {
      Vector<dim> s = Vector<dim>::Zero();
      for (const auto &xi : x)
        s += kernels::grad_w<dim>(type, xi, h);
      benchmark::DoNotOptimize(s);
    }
    state.SetItemsProcessed(state.iterations() * static_cast<long>(x.size()));
    state.SetLabel(type == KernelType::cubic_spline ? "cubic spline" : "Wendland C2");
  }

  /// Specimen of about n particles: a 50 x 100 mm cylinder (3-D) or its axial section (2-D).
  template <int dim>
  Lattice<dim> specimen(const double n)
  {
    const double volume = dim == 3 ? M_PI * 0.025 * 0.025 * 0.1 : 0.05 * 0.1;
    return make_cylinder<dim>(0.05, 0.1, std::pow(volume / n, 1.0 / dim));
  }

  // ---- neighbour search: pairs found per second ----
  template <int dim>
  void bm_find_pairs(benchmark::State &state)
  {
    const Lattice<dim> lat = specimen<dim>(static_cast<double>(state.range(0)));
    PairList pairs;
    for (auto _ : state)
      find_pairs<dim>(lat.positions, 2.4 * lat.spacing, pairs);
    state.counters["particles"] = lat.positions.size();
    state.counters["pairs"]     = pairs.n_pairs();
    state.counters["pairs/s"]   = benchmark::Counter(static_cast<double>(pairs.n_pairs()),
                                                     benchmark::Counter::kIsIterationInvariantRate);
  }

  /// The configuration of the speed target: FORM 8 (TL + correction), Mohr-Coulomb with
  /// softening, Monaghan AV (1, 1), hourglass control; ends constrained, the top moving at
  /// 0.5 m/s so that particles yield within the run.
  template <int dim>
  Body<dim> loaded_body(const Lattice<dim> &lat, const int threads)
  {
    Parameters prm;
    prm.spacing   = lat.spacing;
    prm.n_threads = threads;
    MaterialParameters mat; // M1 basalt, Mohr-Coulomb
    mat.softening_strain = 2e-3;
    Body<dim> body(prm, mat, lat.positions, lat.volumes);
    for (unsigned i = 0; i < body.n_particles(); ++i)
    {
      const double z = lat.positions[i][dim - 1];
      if (z < lat.spacing)
        body.constrain(i, dim - 1, 0.0);
      else if (z > 0.1 - lat.spacing)
        body.constrain(i, dim - 1, -0.5);
    }
    return body;
  }

  // ---- one full SPH step (compute_forces + integrate) ----
  // range(0): particles (approximate), range(1): threads.
  template <int dim>
  void bm_step(benchmark::State &state)
  {
    const long baseline = reset_peak();
    const auto lat      = specimen<dim>(static_cast<double>(state.range(0)));
    Body<dim> body      = loaded_body<dim>(lat, static_cast<int>(state.range(1)));
    const double n      = body.n_particles();
    double cpu          = 0;
    for (auto _ : state)
    {
      const double c0 = cpu_seconds();
      body.compute_forces();
      body.integrate(body.stable_time_step());
      cpu += cpu_seconds() - c0;
    }
    const double steps          = static_cast<double>(state.iterations());
    state.counters["particles"] = n;
    state.counters["pairs"]     = static_cast<double>(body.n_pairs());
    state.counters["threads"]   = static_cast<double>(state.range(1));
    state.counters["particle_steps/s"] =
      benchmark::Counter(n, benchmark::Counter::kIsIterationInvariantRate);
    state.counters["pair_interactions/s"] = benchmark::Counter(
      static_cast<double>(body.n_pairs()), benchmark::Counter::kIsIterationInvariantRate);
    // per CPU second of all threads: robust on a shared machine, and per core by construction
    state.counters["particle_steps/cpu_s"] = n * steps / cpu;
    state.counters["bytes/particle"]       = static_cast<double>(peak_bytes.load() - baseline) / n;
  }
} // namespace

BENCHMARK_TEMPLATE(bm_grad_w, 2)->Arg(0)->Arg(1);
BENCHMARK_TEMPLATE(bm_grad_w, 3)->Arg(0)->Arg(1);
BENCHMARK_TEMPLATE(bm_find_pairs, 2)->Arg(100000)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(bm_find_pairs, 3)->Arg(100000)->Unit(benchmark::kMillisecond);
// one step at 100,000 particles, 1 and 2 threads (the speed target's configuration)
BENCHMARK_TEMPLATE(bm_step, 2)
  ->ArgsProduct({{100000}, {1, 2}})
  ->UseRealTime()
  ->Iterations(20)
  ->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(bm_step, 3)
  ->ArgsProduct({{100000}, {1, 2}})
  ->UseRealTime()
  ->Iterations(20)
  ->Unit(benchmark::kMillisecond);
// scaling: cost per particle-step from 1e4 to 1e6 particles (3-D, 1 thread)
BENCHMARK_TEMPLATE(bm_step, 3)
  ->Name("scaling_3d")
  ->ArgsProduct({{10000, 30000, 100000, 300000, 1000000}, {1}})
  ->UseRealTime()
  ->Iterations(5)
  ->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
