#pragma once
/// @file
/// The hidden truths the discovery tests draw, in one place: the base rock of a seed, the range of
/// each effect's parameters, and the seeds to run (COSIM_DISCOVERY_SEEDS=3,4 runs others, a local
/// study). Each draw has its own stream (seed * 7919 + 17, offset per parameter), so adding an
/// effect moves no other draw.

#include "generator.h"

#include <cstdlib>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace discovery
{
  /// A number drawn uniformly from [lo, hi) by the stream of `seed`.
  inline double uniform(unsigned seed, double lo, double hi)
  {
    std::mt19937 rng(seed * 7919u + 17u);
    return std::uniform_real_distribution<double>(lo, hi)(rng);
  }

  /// The base rock of a seed: Mohr-Coulomb c in [20, 40) MPa, phi in [35, 50) deg.
  inline Truth base(unsigned seed)
  {
    Truth t;
    t.c   = uniform(seed, 20, 40);
    t.phi = uniform(seed + 100, 35, 50);
    return t;
  }

  /// Draws the truths of `effect` into `t` (t.effects left as it is: the cut-off is a fraction of
  /// the tensile strength of the rock that t.effects describes) and returns its tested parameter:
  /// T0 [MPa] (0.35-0.6 of the tensile strength), m_i (10-25, sigma_ci 100-200 MPa), k_machine
  /// (200-800 kN/mm), E0_ratio (0.3-0.5, sigma_cc 10-30 MPa), rate_A (0.04-0.08), mu (0.3-0.6),
  /// weibull_m (6-12). The ranges keep each effect several noise levels above the 2 % strength
  /// scatter and the 0.2 % curve noise.
  inline double draw(Truth &t, const std::string &effect, unsigned seed)
  {
    if (effect == "tension_cutoff")
      return t.T0 = uniform(seed + 200, 0.35, 0.6) * true_tensile(t);
    if (effect == "envelope_curvature")
    {
      t.sigma_ci = uniform(seed + 300, 100, 200);
      return t.m_i = uniform(seed + 400, 10, 25);
    }
    if (effect == "machine_compliance")
      return t.k_machine = uniform(seed + 500, 200, 800);
    if (effect == "crack_closure")
    {
      t.sigma_cc = uniform(seed + 700, 10, 30);
      return t.E0_ratio = uniform(seed + 600, 0.3, 0.5);
    }
    if (effect == "loading_rate")
      return t.rate_A = uniform(seed + 800, 0.04, 0.08);
    if (effect == "end_friction")
      return t.mu = uniform(seed + 900, 0.3, 0.6);
    if (effect == "heterogeneity")
      return t.weibull_m = uniform(seed + 1000, 6, 12);
    throw std::invalid_argument("draw: no effect '" + effect + "'");
  }

  /// The seeds of a test: COSIM_DISCOVERY_SEEDS (comma separated) where set, else `fixed`.
  inline std::vector<unsigned> seeds(const std::vector<unsigned> &fixed)
  {
    const char *e = std::getenv("COSIM_DISCOVERY_SEEDS");
    if (e == nullptr)
      return fixed;
    std::vector<unsigned> v;
    std::istringstream in(e);
    for (std::string item; std::getline(in, item, ',');)
      v.push_back(static_cast<unsigned>(std::stoul(item)));
    return v;
  }
} // namespace discovery
