#include <diagnose/calibrate.h>

#include <coupling/references.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace diagnose
{
  namespace
  {
    constexpr double pi = 3.14159265358979323846;
    double radians(double deg) { return deg * pi / 180.0; }
  } // namespace

  MohrCoulombStrength calibrate_mohr_coulomb(const double ucs, const double bts)
  {
    if (!(bts > 0 && ucs > bts) || !std::isfinite(ucs))
      throw std::invalid_argument("calibrate_mohr_coulomb: need 0 < BTS < UCS");
    const double sin_phi = (ucs - bts) / (ucs + bts);
    const double phi = std::asin(sin_phi);
    return {ucs * (1.0 - sin_phi) / (2.0 * std::cos(phi)), phi * 180.0 / pi};
  }

  MohrCoulombStrength calibrate_mohr_coulomb_brazilian(const double ucs, const double bts)
  {
    if (!(bts > 0 && ucs > 4 * bts) || !std::isfinite(ucs))
      throw std::invalid_argument("calibrate_mohr_coulomb_brazilian: need 0 < 4 BTS < UCS");
    const double n       = ucs / bts - 3.0;
    const double sin_phi = (n - 1.0) / (n + 1.0);
    return {ucs / (2.0 * std::sqrt(n)), std::asin(sin_phi) * 180.0 / pi};
  }

  double mohr_coulomb_ucs(const MohrCoulombStrength &s)
  {
    return coupling::mohr_coulomb_axial_strength(s.cohesion, s.friction_angle, 0.0);
  }

  double mohr_coulomb_bts(const MohrCoulombStrength &s)
  {
    const double phi = radians(s.friction_angle);
    return 2.0 * s.cohesion * std::cos(phi) / (1.0 + std::sin(phi));
  }

  double hoek_brown_sigma1(const HoekBrownStrength &h, const double sigma3)
  {
    const double base = h.m_b * sigma3 / h.sigma_ci + 1.0;
    return sigma3 + h.sigma_ci * std::pow(std::max(base, 0.0), h.a);
  }

  double hoek_brown_disc_strength(const HoekBrownStrength &h)
  {
    // g(t) = sigma1(-t) - 3 t falls from sigma_ci at t = 0 to -4 sigma_ci / m_b at the apex
    double lo = 0, hi = h.sigma_ci / h.m_b;
    for (int i = 0; i < 200 && hi - lo > 1e-14 * h.sigma_ci; ++i)
    {
      const double t = 0.5 * (lo + hi);
      (hoek_brown_sigma1(h, -t) > 3.0 * t ? lo : hi) = t;
    }
    const double envelope = 0.5 * (lo + hi);
    return h.tensile > 0 ? std::min(envelope, h.tensile) : envelope;
  }

  namespace
  {
    /// Sum of the squared relative misses of the triaxial strengths and the BTS.
    double misfit(const HoekBrownStrength &h, const double bts, const std::vector<TriaxialStrength> &t)
    {
      double ss = std::pow(hoek_brown_disc_strength(h) / bts - 1.0, 2);
      for (const auto &x : t)
        ss += std::pow(hoek_brown_sigma1(h, x.sigma3) / x.sigma1 - 1.0, 2);
      return ss;
    }

    /// The x in [lo, hi] where the unimodal f is least, by golden section down to an interval of
    /// `tol` (at most `iterations` steps).
    template <class F>
    double golden_minimum(const F &f, double lo, double hi, const double tol, const int iterations)
    {
      const double g = 0.5 * (std::sqrt(5.0) - 1.0);
      double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
      double f1 = f(x1), f2 = f(x2);
      for (int i = 0; i < iterations && hi - lo > tol; ++i)
        if (f1 < f2)
        {
          hi = x2, x2 = x1, f2 = f1;
          x1 = hi - g * (hi - lo), f1 = f(x1);
        }
        else
        {
          lo = x1, x1 = x2, f1 = f2;
          x2 = lo + g * (hi - lo), f2 = f(x2);
        }
      return 0.5 * (lo + hi);
    }

    /// The m_b in [0.1, 200] of least misfit at the envelope's a, by golden section on log m_b
    /// (the misfit is unimodal in m_b: sigma1 rises and the disc strength falls with it).
    double best_mb(HoekBrownStrength h, const double bts, const std::vector<TriaxialStrength> &t)
    {
      const auto f = [&](const double x) {
        h.m_b = std::exp(x);
        return misfit(h, bts, t);
      };
      return std::exp(golden_minimum(f, std::log(0.1), std::log(200.0), 1e-12, 100));
    }
  } // namespace

  HoekBrownStrength calibrate_hoek_brown(const double ucs, const double bts,
                                         const std::vector<TriaxialStrength> &triaxial)
  {
    if (!(bts > 0 && ucs > 4 * bts) || !std::isfinite(ucs))
      throw std::invalid_argument("calibrate_hoek_brown: need 0 < 4 BTS < UCS");
    for (const auto &x : triaxial)
      if (!(x.sigma3 >= 0 && x.sigma1 > x.sigma3) || !std::isfinite(x.sigma1))
        throw std::invalid_argument("calibrate_hoek_brown: a triaxial strength needs sigma1 > sigma3 >= 0");
    HoekBrownStrength h;
    h.sigma_ci = ucs;
    h.tensile  = bts;
    if (triaxial.empty())
    {
      h.m_b = (ucs * ucs - 16.0 * bts * bts) / (ucs * bts);
      return h;
    }
    if (triaxial.size() == 1)
    {
      h.m_b = best_mb(h, bts, triaxial);
      return h;
    }
    // a over [0.4, 0.95] (m_b the best at each a): a scan, then a golden section near its best
    const double lo = 0.4, hi = 0.95;
    const auto f = [&](const double a) {
      HoekBrownStrength t = h;
      t.a                 = a;
      t.m_b               = best_mb(t, bts, triaxial);
      return misfit(t, bts, triaxial);
    };
    // a coarse scan first: the misfit in a need not be unimodal over the whole range
    double best_a = lo, best_f = f(lo);
    for (int i = 1; i <= 22; ++i)
    {
      const double a = lo + (hi - lo) * i / 22.0, v = f(a);
      if (v < best_f)
        best_a = a, best_f = v;
    }
    h.a   = golden_minimum(f, std::max(lo, best_a - 0.025), std::min(hi, best_a + 0.025), 1e-10, 60);
    h.m_b = best_mb(h, bts, triaxial);
    return h;
  }
} // namespace diagnose
