#pragma once
/// @file
/// Generator of measured-looking data folders for the discovery tests: strength tables with
/// replicate scatter and load-frame curves with noise, with hidden effects switched on. It is
/// written apart from coupling/src/diagnose*: no shared code path (its own envelope formulas, a
/// bisection for the Hoek-Brown tensile strength, a numerical integration of the toe compliance).
///
/// The test programme (what a laboratory would run; every specimen draws its own scatter):
/// - strength.csv, always: standard 50 x 100 mm specimens (L/D = 2) at the quasi-static rate
///   1e-5 /s, three each of BTS, UCS and CTCS at 5, 10, 20 and 40 MPa confinement (18 rows);
/// - curves/, load-frame records, displacement at the platen, quasi-static UCS of 50 x 100 mm
///   specimens unless the study is of
///   - loading rate: three UCS specimens at each of six strain rates a decade apart, 1e-6 to
///     1e-1 /s (18 curves; a rate study spans the quasi-static range with replicates at every
///     rate, not one specimen at the highest);
///   - end friction: specimens of two slenderness ratios at one volume, six at L/D = 2
///     (50 x 100 mm) and twelve at L/D = 1/2 (79.4 x 39.7 mm), the short ones where friction
///     shows (how platen friction is identified in practice); friction holds the end faces, so
///     its curves are stiffer by the held ends' elastic confinement (held_ends.h);
///   - size (heterogeneity): three specimens of each of four diameters 25, 50, 100 and 150 mm at
///     L/D = 2 (a volume ratio of 216 for the Weibull modulus);
///   - otherwise: two UCS and one CTCS at 10 MPa.
///   With two of these effects hidden, both studies are written.
/// Noise: 2 % relative scatter of every specimen's strength (Truth::strength_scatter) and 0.2 % of
/// the peak displacement on every curve row (Truth::curve_noise).

#include "held_ends.h"

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <string>
#include <vector>

namespace discovery
{
  /// The hidden truth of one synthetic data set (compression +, MPa, mm, kN, s).
  struct Truth
  {
    std::set<std::string> effects;
    double c = 30, phi = 45;           ///< Mohr-Coulomb [MPa, deg]
    double E        = 60e3;            ///< [MPa]
    double T0       = 0;               ///< tension cut-off [MPa]
    double sigma_ci = 0, m_i = 0;      ///< Hoek-Brown (s = 1, a = 1/2) [MPa, -]
    double k_machine = 0;              ///< frame stiffness [kN/mm]
    double E0_ratio = 1, sigma_cc = 1; ///< crack closure [-, MPa]
    double rate_A           = 0;       ///< strength gain per decade of strain rate [-]
    double mu               = 0;       ///< platen friction: apparent strength 1 + mu D / (3 L) [-]
    double weibull_m        = 0;       ///< size effect: strength ~ (volume / 50x100 mm)^(-1/m) [-]
    double strength_scatter = 0.02;    ///< relative SD of replicate strengths [-]
    double curve_noise      = 0.002;   ///< displacement noise / peak displacement [-]
  };

  inline double deg(double d)
  {
    return d * 3.14159265358979323846 / 180.0;
  }

  /// Compressive strength sigma1 at confinement s3 [MPa].
  inline double true_sigma1(const Truth &t, double s3)
  {
    if (t.effects.count("envelope_curvature"))
      return s3 + std::sqrt(t.sigma_ci * t.sigma_ci + t.m_i * t.sigma_ci * s3);
    const double N = std::pow(std::tan(deg(45 + t.phi / 2)), 2); // passive coefficient
    return 2 * t.c * std::sqrt(N) + N * s3;
  }

  /// Uniaxial tensile strength [MPa] (positive).
  inline double true_tensile(const Truth &t)
  {
    double T;
    if (t.effects.count("envelope_curvature"))
    {
      // sigma1 = 0 on the Hoek-Brown envelope: bisection on g(T) = -T + sqrt(sci^2 - m sci T)
      double lo = 0, hi = t.sigma_ci / t.m_i;
      for (int i = 0; i < 200; ++i)
      {
        const double mid = 0.5 * (lo + hi);
        ((-mid + std::sqrt(t.sigma_ci * t.sigma_ci - t.m_i * t.sigma_ci * mid)) > 0 ? lo : hi) =
          mid;
      }
      T = 0.5 * (lo + hi);
    }
    else
    {
      const double N = std::pow(std::tan(deg(45 + t.phi / 2)), 2);
      T              = 2 * t.c / std::sqrt(N);
    }
    if (t.effects.count("tension_cutoff"))
      T = std::min(T, t.T0);
    return T;
  }

  /// Axial specimen strain under deviatoric stress q at confinement s3, by the trapezoidal rule on
  /// the tangent compliance (crack closure) or q / E.
  inline double true_strain(const Truth &t, double q, double s3)
  {
    if (!t.effects.count("crack_closure"))
      return q / t.E;
    const int n           = 400;
    double eps            = 0;
    const auto compliance = [&](double p) {
      const double E0 = t.E0_ratio * t.E;
      return 1 / t.E + (1 / E0 - 1 / t.E) * std::exp(-p / t.sigma_cc);
    };
    for (int i = 0; i < n; ++i)
    {
      const double a = s3 + q * i / n, b = s3 + q * (i + 1) / n;
      eps += 0.5 * (compliance(a) + compliance(b)) * (b - a);
    }
    return eps;
  }

  /// Writes DIR/material.csv, strength.csv and (with curves) curves/*.csv.
  inline void write_folder(const Truth &t, const std::string &dir, unsigned seed, bool with_curves)
  {
    namespace fs = std::filesystem;
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::mt19937 rng(seed);
    std::normal_distribution<double> unit(0.0, 1.0);
    {
      std::ofstream m(dir + "/material.csv");
      m << "group,E_GPa,nu,density_kg_m3,UCS_MPa,BTS_MPa,c_MPa,phi_deg\n";
      m << "A," << t.E / 1e3 << ",0.25,2700,,,,\n";
    }
    {
      std::ofstream s(dir + "/strength.csv");
      s << "# synthetic\ntest,group,sigma1_MPa,sigma3_MPa\n";
      for (int r = 0; r < 3; ++r)
        s << "BTS,A,0," << -true_tensile(t) * (1 + t.strength_scatter * unit(rng)) << "\n";
      for (double s3 : {0.0, 5.0, 10.0, 20.0, 40.0})
        for (int r = 0; r < 3; ++r)
          s << (s3 == 0 ? "UCS" : "CTCS") << ",A,"
            << s3 + (true_sigma1(t, s3) - s3) *
                      (t.effects.count("end_friction") ? 1 + t.mu / 6 : 1.0) *
                      (1 + t.strength_scatter * unit(rng))
            << "," << s3 << "\n"; // rows: standard 50 x 100 mm specimens (L/D = 2)
    }
    if (!with_curves)
      return;
    fs::create_directories(dir + "/curves");
    int k = 0;
    // (confinement, strain rate, diameter, length): the curve programme (file comment)
    std::vector<std::array<double, 4>> tests;
    const auto replicates = [&tests](const std::array<double, 4> &condition, const int n) {
      for (int i = 0; i < n; ++i)
        tests.push_back(condition);
    };
    // the study of every hidden effect that has one (a laboratory looking for two effects runs
    // both studies), in this order
    if (t.effects.count("loading_rate"))
      for (double rate : {1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 1e-1})
        replicates({{0, rate, 50, 100}}, 3);
    if (t.effects.count("end_friction"))
    { // L/D = 2 and 1/2 at one volume (no size effect mixed in)
      replicates({{0, 1e-5, 50, 100}}, 6);
      replicates({{0, 1e-5, 79.37, 39.69}}, 12);
    }
    if (t.effects.count("heterogeneity"))
      for (double D : {25.0, 50.0, 100.0, 150.0})
        replicates({{0, 1e-5, D, 2 * D}}, 3);
    if (tests.empty())
    {
      replicates({{0, 1e-5, 50, 100}}, 2);
      replicates({{10, 1e-5, 50, 100}}, 1);
    }
    for (auto [s3, rate, D, L] : tests)
    {
      const double A = 3.14159265358979323846 * D * D / 4;
      double q_peak  = true_sigma1(t, s3) - s3;
      if (t.effects.count("end_friction"))
        q_peak *= 1 + t.mu * D / (3 * L);
      if (t.effects.count("heterogeneity"))
        q_peak *= std::pow(D * D * L / (50.0 * 50.0 * 100.0), -1 / t.weibull_m);
      if (t.effects.count("loading_rate"))
        q_peak *= 1 + t.rate_A * std::log10(rate / 1e-5);
      q_peak *= 1 + t.strength_scatter * unit(rng);
      const double F_peak = q_peak * A / 1e3;
      // platens whose friction holds the end faces (mu 0.3 and more) confine an end zone and
      // shorten the platen-read compliance (held_ends.h; Poisson's ratio 0.25, material.csv)
      const double held = t.effects.count("end_friction") ? held_shortening(L / D, 0.25) * D : 0;
      const auto disp_of = [&](double F) {
        double d = true_strain(t, F * 1e3 / A, s3) * (L - held);
        if (t.effects.count("machine_compliance"))
          d += F / t.k_machine;
        return d;
      };
      const double d_peak = disp_of(F_peak);
      // the frame moves at constant platen speed v = rate L; time follows from the displacement
      const double v = rate * L;
      std::ofstream c(dir + "/curves/c" + std::to_string(k++) + ".csv");
      c << "# test: " << (s3 > 0 ? "CTCS" : "UCS") << "\n# group: A\n# diameter_mm: " << D
        << "\n# length_mm: " << L << "\n# confining_MPa: " << s3
        << "\n# displacement: platen\ntime_s,displacement_mm,force_kN\n";
      const int n   = 120;
      double t_last = -1;
      for (int i = 0; i <= n; ++i)
      {
        const double F = F_peak * i / n, d = disp_of(F);
        double time = d / v;
        if (time <= t_last)
          time = t_last + 1e-9 * (1 + t_last);
        t_last = time;
        c << time << "," << d + t.curve_noise * d_peak * unit(rng) << "," << F << "\n";
      }
      for (int i = 1; i <= 5; ++i) // post-peak drop
      {
        const double d = d_peak * (1 + 0.01 * i);
        c << d / v << "," << d << "," << F_peak * (1 - 0.06 * i) << "\n";
      }
    }
  }
} // namespace discovery
