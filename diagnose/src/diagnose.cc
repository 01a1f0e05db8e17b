// `cosim diagnose`: baseline, candidates, evidence (BIC and held-out error), selection.
//
// Evidence: every datum's residual is divided by its noise (strength: a relative scatter from
// replicate specimens, else from the residuals of the richest model; curve points: the scatter of
// second differences along each curve). BIC = chi2 + k ln n with k the fitted parameters (the
// baseline fits none: it takes c, phi, E from the measurements). An effect is named when it lowers
// BIC by more than Options::bic_threshold against the best model without it (the baseline or the
// baseline with its strength refitted), its parameters are not pinned at a bound of their box, and
// the extended model also predicts held-out specimens (leave one specimen or curve out) better.
#include "diagnose_model.h"

#include <diagnose/calibrate.h>
#include <diagnose/diagnose.h>
#include <coupling/errors.h>
#include <sph/rock_models.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <sstream>

namespace diagnose
{
  using coupling::InputError;

  const std::vector<std::string> &effect_names()
  {
    static const std::vector<std::string> names = {
      "tension_cutoff", "envelope_curvature", "crack_closure", "machine_compliance",
      "end_friction",   "heterogeneity",      "loading_rate"};
    return names;
  }

  namespace
  {
    constexpr double pi = 3.14159265358979323846;

    /// Index of the peak force and pre-peak rows of a curve.
    std::size_t peak_index(const Curve &c)
    {
      return static_cast<std::size_t>(std::max_element(c.force.begin(), c.force.end()) -
                                      c.force.begin());
    }

    /// Nominal strain rate of a curve: slope of displacement over time between 10 and 90 % of the
    /// peak force, over the length [1/s].
    double strain_rate_of(const Curve &c)
    {
      const std::size_t ip = peak_index(c);
      const double fp      = c.force[ip];
      std::size_t a = 0, b = ip;
      for (std::size_t i = 0; i <= ip; ++i)
        if (c.force[i] < 0.1 * fp)
          a = i;
      for (std::size_t i = ip + 1; i-- > 0;)
        if (c.force[i] > 0.9 * fp)
          b = i;
      if (b <= a || c.time[b] <= c.time[a])
        return 0;
      return (c.displacement[b] - c.displacement[a]) / (c.time[b] - c.time[a]) / c.length;
    }

    /// Secant modulus 40-60 % of peak of a compressive curve [MPa].
    double secant_modulus(const Curve &c)
    {
      const std::size_t ip = peak_index(c);
      const double fp = c.force[ip], area = pi * c.diameter * c.diameter / 4;
      auto at = [&](double frac) {
        for (std::size_t i = 1; i <= ip; ++i)
          if (c.force[i] >= frac * fp)
          {
            const double w = (frac * fp - c.force[i - 1]) / (c.force[i] - c.force[i - 1]);
            return c.displacement[i - 1] + w * (c.displacement[i] - c.displacement[i - 1]);
          }
        return c.displacement[ip];
      };
      const double de = (at(0.6) - at(0.4)) / c.length;
      return de > 0 ? 0.2 * fp * 1e3 / area / de : 0;
    }

    /// Noise of a curve's displacement from second differences of its pre-peak rows [mm].
    double curve_noise(const Curve &c)
    {
      const std::size_t ip = peak_index(c);
      double s             = 0;
      int n                = 0;
      for (std::size_t i = 1; i + 1 <= ip; ++i)
      {
        const double e = c.displacement[i] - 0.5 * (c.displacement[i - 1] + c.displacement[i + 1]);
        s += e * e;
        ++n;
      }
      const double sd = n > 0 ? std::sqrt(s / n / 1.5) : 0;
      return std::max(sd,
                      2e-3 * std::abs(c.displacement[ip])); // floor: 0.2 % of the peak displacement
    }

    /// The rows of a curve nearest to `n` forces evenly between 5 and 90 % of its peak force,
    /// before the peak, a row taken once.
    std::vector<std::size_t> pre_peak_rows(const Curve &c, const int n)
    {
      const std::size_t ip = peak_index(c);
      std::vector<std::size_t> rows;
      for (int k = 0; k < n; ++k)
      {
        const double target = c.force[ip] * (0.05 + 0.85 * k / (n - 1.0));
        std::size_t best    = 0;
        for (std::size_t i = 0; i <= ip; ++i)
          if (std::abs(c.force[i] - target) < std::abs(c.force[best] - target))
            best = i;
        if (rows.empty() || rows.back() != best)
          rows.push_back(best);
      }
      return rows;
    }

    struct Study
    {
      const Data &data;
      Options options;
      std::vector<GroupBase> groups;
      std::vector<Datum> all;
      std::vector<std::string> notes;
      double strength_rel_noise = 0.05;
      std::map<int, double> curve_sd; // per curve source
      std::set<std::string> applicable;
      std::map<std::string, std::string> not_applicable;

      double noise(const Datum &d) const
      {
        if (d.kind == Datum::curve_point)
          return curve_sd.at(d.source);
        return std::max(strength_rel_noise * std::abs(d.measured), 1e-3);
      }
    };

    void add_group(std::vector<std::string> &g, const std::string &name)
    {
      if (std::find(g.begin(), g.end(), name) == g.end())
        g.push_back(name);
    }

    /// Baseline values of each group from the measurements (report says which).
    std::vector<GroupBase> baseline_groups(const Data &data, std::vector<std::string> &notes)
    {
      std::vector<std::string> names;
      for (const auto &m : data.materials)
        add_group(names, m.group);
      for (const auto &s : data.strengths)
        add_group(names, s.group);
      for (const auto &c : data.curves)
        add_group(names, c.group);
      std::vector<GroupBase> groups;
      for (const auto &name : names)
      {
        GroupBase g;
        g.group              = name;
        const MaterialRow *m = nullptr;
        for (const auto &r : data.materials)
          if (r.group == name)
            m = &r;
        // strength: measured c, phi; else calibrated from UCS and BTS (Eqs. 14-15)
        auto mean_of = [&](const char *test) {
          double s = 0;
          int n    = 0;
          for (const auto &r : data.strengths)
            if (r.group == name && r.test == test)
            {
              s += test == std::string("BTS") ? -r.sigma3 : r.sigma1;
              ++n;
            }
          return n ? std::optional<double>(s / n) : std::nullopt;
        };
        std::optional<double> ucs = m ? m->UCS_MPa : std::nullopt,
                              bts = m ? m->BTS_MPa : std::nullopt;
        if (!ucs)
          ucs = mean_of("UCS");
        if (!bts)
          bts = mean_of("BTS");
        if (!ucs)
          for (const auto &c : data.curves)
            if (c.group == name && c.test == "UCS" && c.failed)
              ucs = c.force[peak_index(c)] * 1e3 / (pi * c.diameter * c.diameter / 4);
        if (!bts)
          for (const auto &c : data.curves)
            if (c.group == name && c.test == "BTS" && c.failed)
              bts = 2 * c.force[peak_index(c)] * 1e3 / (pi * c.diameter * c.length);
        if (m && m->c_MPa && m->phi_deg)
        {
          const double s = std::sin(*m->phi_deg * pi / 180), c = std::cos(*m->phi_deg * pi / 180);
          g.ucs    = 2 * *m->c_MPa * c / (1 - s);
          g.phi    = *m->phi_deg;
          g.source = "measured c, phi";
        }
        else if (ucs && bts && *bts < *ucs)
        {
          const auto mc = calibrate_mohr_coulomb(*ucs, *bts);
          g.ucs         = *ucs;
          g.phi         = mc.friction_angle;
          g.source      = "c, phi calibrated from UCS and BTS (Eqs. 14-15)";
        }
        else if (ucs)
        {
          g.ucs    = *ucs;
          g.phi    = 30;
          g.source = "UCS measured, phi = 30 deg assumed (no BTS, c or phi)";
          notes.push_back("group " + name +
                          ": no BTS or c, phi; the baseline assumes phi = 30 deg");
        }
        else
        {
          // stiffness data only (curves stopped before failure, a modulus): nothing of the group
          // measures strength, so its strength enters no residual; a typical UCS = E / 400
          // keeps the model defined (set below, once E is known)
          g.phi    = 30;
          g.source = "no strength measured (stiffness only): strength not diagnosed";
          notes.push_back("group " + name +
                          ": no strength (UCS, BTS, c, phi or a curve to failure); only its "
                          "stiffness is diagnosed");
        }
        if (m && m->nu)
          g.nu = *m->nu;
        // stiffness: measured E; else from specimen-displacement curves; else platen curves
        double E = m && m->E_GPa ? *m->E_GPa * 1e3 : 0;
        for (int pass = 0; pass < 2 && E <= 0; ++pass)
        {
          double s = 0;
          int n    = 0;
          for (const auto &c : data.curves)
            if (c.group == name && c.test != "BTS" && !c.peak_only() &&
                c.platen_displacement == (pass == 1))
              if (const double e = secant_modulus(c); e > 0)
              {
                s += e;
                ++n;
              }
          if (n)
          {
            E = s / n;
            if (pass == 1)
              notes.push_back("group " + name +
                              ": E from platen-displacement curves (no measured E): a "
                              "machine compliance cannot be told from the rock's E");
          }
        }
        g.E = E > 0 ? E : 50e3;
        if (!(g.ucs > 0))
          g.ucs = g.E / 400;
        groups.push_back(g);
      }
      return groups;
    }

    std::vector<Datum> make_data(const Data &data, std::map<int, double> &curve_sd)
    {
      std::vector<Datum> all;
      int source = 0;
      for (const auto &r : data.strengths)
      {
        Datum d;
        d.kind     = Datum::strength;
        d.test     = r.test;
        d.group    = r.group;
        d.sigma3   = r.sigma3;
        d.measured = r.test == "BTS" ? -r.sigma3 : r.sigma1;
        d.source   = source++;
        d.where    = r.where;
        all.push_back(d);
      }
      const auto n_compressive =
        std::count_if(data.curves.begin(), data.curves.end(),
                      [](const Curve &c) { return c.test != "BTS" && !c.peak_only(); });
      const int n_points =
        std::clamp(160 / static_cast<int>(std::max<std::ptrdiff_t>(n_compressive, 1)), 8, 20);
      for (const auto &c : data.curves)
      {
        const int src        = source++;
        const std::size_t ip = peak_index(c);
        const double fp      = c.force[ip];
        Datum p;
        p.kind   = Datum::strength;
        p.test   = c.test;
        p.group  = c.group;
        p.source = src;
        p.where  = c.file;
        if (c.test == "BTS")
        {
          if (!c.failed)
            continue; // a BTS curve gives its peak only, and this one has none (reported)
          p.area     = c.diameter * c.length;
          p.measured = 2 * fp * 1e3 / (pi * c.diameter * c.length);
          p.sigma3   = -p.measured;
          all.push_back(p);
          continue; // BTS curves: the peak only (the disc's displacement is not a material point)
        }
        p.area         = pi * c.diameter * c.diameter / 4;
        p.sigma3       = c.confining;
        p.measured     = c.confining + fp * 1e3 / p.area;
        p.slenderness  = c.length / c.diameter;
        p.volume_ratio = c.diameter * c.diameter * c.length / (50.0 * 50.0 * 100.0);
        p.strain_rate  = strain_rate_of(c);
        if (c.failed) // its largest force is the strength
          all.push_back(p);
        if (c.peak_only())
          continue; // the peak only: too few rows for curve points
        curve_sd[src] = curve_noise(c);
        // pre-peak points between 5 and 90 % of the peak force, evenly in force: about 20 a
        // curve, fewer (down to 8) where a long programme would give more than 160 in all (its
        // information is in the peaks; the fit's cost grows with the points)
        for (const std::size_t best : pre_peak_rows(c, n_points))
        {
          Datum q    = p;
          q.kind     = Datum::curve_point;
          q.force    = c.force[best];
          q.length   = c.length;
          q.platen   = c.platen_displacement;
          q.measured = c.displacement[best];
          all.push_back(q);
        }
      }
      // test conditions: replicate specimens (same test, group, confinement; for curves also
      // slenderness, volume and strain rate within 10 %) share one; curve points share their
      // curve's
      std::vector<std::string> keys;
      std::map<int, int> of_source;
      for (auto &d : all)
      {
        // a curve point shares its curve's condition; a curve without failure has no peak datum,
        // and its first point (the same test, group, confinement, size and rate) names it
        if (d.kind == Datum::curve_point && of_source.count(d.source))
        {
          d.condition = of_source.at(d.source);
          continue;
        }
        const auto bin = [](double v) {
          return v > 0 ? std::to_string(std::lround(std::log(v) / std::log(1.1))) : "-";
        };
        const std::string key =
          d.test + '|' + d.group + '|' + std::to_string(std::lround(d.sigma3 * 10)) + '|' +
          bin(d.slenderness) + '|' + bin(d.volume_ratio) + '|' + bin(d.strain_rate);
        auto it     = std::find(keys.begin(), keys.end(), key);
        d.condition = static_cast<int>(it - keys.begin());
        if (it == keys.end())
          keys.push_back(key);
        of_source[d.source] = d.condition;
      }
      return all;
    }

    /// Which effects these data can inform.
    void check_applicability(Study &s)
    {
      std::set<double> levels;
      bool tension = false, compression = false;
      std::vector<double> slender, volume, rates;
      bool curves = false, platen = false;
      for (const auto &d : s.all)
        if (d.kind == Datum::strength)
        {
          levels.insert(std::round(d.test == "BTS" ? -1e9 : d.sigma3 * 10) / 10);
          // a TXE row with a tensile sigma3 (hybrid fracture) informs the tensile side too
          (d.test == "BTS" || d.sigma3 < 0 ? tension : compression) = true;
          if (d.test != "BTS" && d.strain_rate > 0)
          {
            slender.push_back(d.slenderness);
            volume.push_back(d.volume_ratio);
            rates.push_back(d.strain_rate);
          }
        }
        else
        {
          curves = true;
          platen = platen || d.platen;
        }
      const auto spread = [](const std::vector<double> &v) {
        return v.empty()
                 ? 1.0
                 : *std::max_element(v.begin(), v.end()) / *std::min_element(v.begin(), v.end());
      };
      auto na = [&](const char *e, const std::string &why) { s.not_applicable[e] = why; };
      if (!(tension && compression))
        na("tension_cutoff", "needs tensile (BTS) and compressive strengths");
      if (levels.size() < 3)
        na("envelope_curvature", "needs strengths at three or more stress levels");
      if (!curves)
        na("crack_closure", "needs UCS/CTCS load-frame curves");
      if (!platen)
        na("machine_compliance", "needs curves with displacement read at the platen");
      bool e_known = true;
      for (const auto &n : s.notes)
        if (n.find("machine compliance cannot") != std::string::npos)
          e_known = false;
      if (platen && !e_known)
        na("machine_compliance", "E of the rock was not measured independently of the frame");
      if (spread(slender) < 1.2)
        na("end_friction",
           "needs compressive curves of two or more slenderness ratios L/D (friction and "
           "strength are one factor at a single L/D)");
      if (spread(volume) < 1.5)
        na("heterogeneity",
           "needs compressive curves of specimens of different volume (weakest-link size "
           "effect)");
      if (spread(rates) < 3.0)
        na("loading_rate", "needs compressive curves at strain rates half a decade or more apart");
      for (const auto &e : effect_names())
        if (!s.not_applicable.count(e))
          s.applicable.insert(e);
    }

    struct Fitted
    {
      EffectSet effects;
      bool refit = false;
      std::vector<Parameter> parameters;
      FitResult result;
      double bic    = 0;
      bool at_bound = false;
    };

    int n_strength(const std::vector<Datum> &d)
    {
      return static_cast<int>(std::count_if(
        d.begin(), d.end(), [](const Datum &x) { return x.kind == Datum::strength; }));
    }

    /// Fits `effects` (with the base strength refitted or not) to `data`, from the warm values
    /// given and across the effects' boxes; `polish` as in fit().
    Fitted fit_model(const Study &s, const EffectSet &effects, const bool refit,
                     const std::vector<Datum> &data, const std::map<std::string, double> &warm = {},
                     const bool polish = true)
    {
      const Surrogate model(s.groups, effects, refit);
      Fitted f;
      f.effects    = effects;
      f.refit      = refit;
      f.parameters = model.parameters();
      std::vector<std::vector<double>> starts;
      std::vector<double> base = model.initial();
      for (std::size_t i = 0; i < base.size(); ++i)
        if (auto it = warm.find(f.parameters[i].name); it != warm.end())
          base[i] = it->second;
      starts.push_back(base);
      if (warm.empty() || effects.size() > 0)
        for (double t : {0.15, 0.5, 0.85}) // effect parameters across their box (local optimiser)
        {
          std::vector<double> st = base;
          bool changed           = false;
          for (std::size_t i = 0; i < st.size(); ++i)
            if (f.parameters[i].name.rfind("UCS_", 0) != 0 && f.parameters[i].name != "phi" &&
                !warm.count(f.parameters[i].name))
            {
              const auto &q = f.parameters[i];
              st[i]         = q.log ? q.lo * std::pow(q.hi / q.lo, t) : q.lo + (q.hi - q.lo) * t;
              changed       = true;
            }
          if (changed)
            starts.push_back(st);
        }
      f.result = fit(
        model, data, [&s](const Datum &d) { return s.noise(d); }, starts, polish);
      f.bic = f.result.chi2 +
              static_cast<double>(f.parameters.size()) * std::log(static_cast<double>(data.size()));
      for (std::size_t i = 0; i < f.parameters.size(); ++i)
      {
        const auto &q = f.parameters[i];
        if (q.name.rfind("UCS_", 0) == 0 || q.name == "phi")
          continue;
        const double v = f.result.values[i];
        const double t =
          q.log ? std::log(v / q.lo) / std::log(q.hi / q.lo) : (v - q.lo) / (q.hi - q.lo);
        if (t < 0.005 || t > 0.995)
          f.at_bound = true;
      }
      return f;
    }

    std::map<std::string, double> values_of(const Fitted &f)
    {
      std::map<std::string, double> v;
      for (std::size_t i = 0; i < f.parameters.size(); ++i)
        v[f.parameters[i].name] = f.result.values[i];
      return v;
    }

    /// RMS of normalised residuals, and in MPa / mm, of a model on `data`.
    struct Rms
    {
      double norm = 0, strength = 0, curve = 0;
    };

    /// Noise-normalised RMS over all data, and plain RMS over strengths and curve points, of the
    /// residuals predictions[i] - data[i].measured.
    Rms rms_of(const Study &s, const std::vector<Datum> &data,
               const std::vector<double> &predictions)
    {
      double a = 0, b = 0, c = 0;
      int nb = 0, nc = 0;
      for (std::size_t i = 0; i < data.size(); ++i)
      {
        const double r = predictions[i] - data[i].measured;
        a += std::pow(r / s.noise(data[i]), 2);
        if (data[i].kind == Datum::strength)
        {
          b += r * r;
          ++nb;
        }
        else
        {
          c += r * r;
          ++nc;
        }
      }
      return {data.empty() ? 0 : std::sqrt(a / data.size()), nb ? std::sqrt(b / nb) : 0,
              nc ? std::sqrt(c / nc) : 0};
    }

    Rms rms_of(const Study &s, const Surrogate &m, const std::vector<double> &p,
               const std::vector<Datum> &data)
    {
      std::vector<double> predictions;
      predictions.reserve(data.size());
      for (const auto &d : data)
        predictions.push_back(m.predict(d, p));
      return rms_of(s, data, predictions);
    }

    /// Held-out predictions of every datum of s.all (same order): leave one specimen out (each
    /// strength row or curve is one fold) up to 20 specimens; beyond, 20 folds of every 20th.
    /// (Leaving a whole condition out instead makes the extreme L/D, volume or rate of a curve
    /// series an extrapolation that two or three curves cannot pin down.)
    std::vector<double> heldout_predictions(const Study &s, const EffectSet &effects,
                                            const bool refit, const Fitted *full)
    {
      std::set<int> sources;
      for (const auto &d : s.all)
        sources.insert(d.source);
      const int n_folds = std::min<int>(20, static_cast<int>(sources.size()));
      std::vector<double> pred(s.all.size());
      const Surrogate model(s.groups, effects, refit);
      for (int k = 0; k < n_folds; ++k)
      {
        std::vector<Datum> train;
        for (const auto &d : s.all)
          if (d.source % n_folds != k)
            train.push_back(d);
        std::vector<double> p = model.initial();
        // from the all-data optimum, one pass: a fold moves it by a fraction of its SE
        if (full != nullptr && !full->parameters.empty())
          p = fit_model(s, effects, refit, train, values_of(*full), false).result.values;
        for (std::size_t i = 0; i < s.all.size(); ++i)
          if (s.all[i].source % n_folds == k)
            pred[i] = model.predict(s.all[i], p);
      }
      return pred;
    }

    Rms heldout(const Study &s, const EffectSet &effects, const bool refit, const Fitted *full)
    {
      return rms_of(s, s.all, heldout_predictions(s, effects, refit, full));
    }

    /// The discrepancy: the test conditions the baseline misses by more than `z` noise SDs of their
    /// replicate mean (strength data; each curve point is its own condition). The RMS error of
    /// `base` and of the held-out predictions `ext` on them, in SDs of the replicate means, and
    /// their count.
    struct Discrepancy
    {
      double before = 0, after = 0;
      int n = 0;
    };

    Discrepancy discrepancy(const Study &s, const std::vector<double> &base,
                            const std::vector<double> &ext, const double z)
    {
      struct Mean
      {
        double measured = 0, base = 0, ext = 0, var = 0;
        int n = 0;
      };
      std::map<std::pair<int, int>, Mean> means; // (condition, point) -> replicate means
      for (std::size_t i = 0; i < s.all.size(); ++i)
      {
        const Datum &d  = s.all[i];
        const int point = d.kind == Datum::strength ? -1 : static_cast<int>(i);
        Mean &m         = means[{d.condition, point}];
        m.measured += d.measured;
        m.base += base[i];
        m.ext += ext[i];
        m.var += std::pow(s.noise(d), 2);
        ++m.n;
      }
      Discrepancy r;
      for (const auto &[k, m] : means)
      {
        const double sd = std::sqrt(m.var) / m.n; // SD of the mean of n specimens
        const double rb = (m.base - m.measured) / m.n / sd;
        if (std::abs(rb) <= z)
          continue;
        r.before += rb * rb;
        r.after += std::pow((m.ext - m.measured) / m.n / sd, 2);
        ++r.n;
      }
      if (r.n > 0)
      {
        r.before = std::sqrt(r.before / r.n);
        r.after  = std::sqrt(r.after / r.n);
      }
      return r;
    }

    std::vector<FittedValue> fitted_values(const Study &s, const Fitted &f)
    {
      std::vector<FittedValue> v;
      for (std::size_t i = 0; i < f.parameters.size(); ++i)
        v.push_back({f.parameters[i].name, f.parameters[i].unit, f.result.values[i],
                     f.result.standard_errors[i]});
      // derived: the cut-off stress per group
      const auto vals = values_of(f);
      if (vals.count("T0_ratio"))
        for (const auto &g : s.groups)
        {
          const double ucs = vals.count("UCS_" + g.group) ? vals.at("UCS_" + g.group) : g.ucs;
          double se        = 0;
          for (std::size_t i = 0; i < f.parameters.size(); ++i)
            if (f.parameters[i].name == "T0_ratio")
              se = f.result.standard_errors[i] * ucs;
          v.push_back({"T0_" + g.group, "MPa", vals.at("T0_ratio") * ucs, se});
        }
      return v;
    }
    /// The rock of a simulated case of specimen `d` of group `g`: the baseline (Mohr-Coulomb
    /// with the group's UCS and phi, measured E, rigid frictionless platens) with `effects` at
    /// `v` (the fitted values).
    SimulatedRock simulated_rock(const Study &s, const GroupBase &g, const Datum &d,
                                 const EffectSet &effects, const std::map<std::string, double> &v)
    {
      SimulatedRock r;
      r.E = g.E;
      for (const auto &m : s.data.materials)
        if (m.group == g.group)
        {
          if (m.nu)
            r.nu = *m.nu;
          if (m.density)
            r.density = *m.density;
        }
      r.ucs = v.count("UCS_" + g.group) ? v.at("UCS_" + g.group) : g.ucs;
      r.phi = v.count("phi") ? v.at("phi") : g.phi;
      const auto has = [&effects](const char *e) { return effects.count(e) > 0; };
      if (has("envelope_curvature"))
      {
        r.hoek_brown = true;
        r.m_i        = v.at("m_i");
      }
      if (has("tension_cutoff"))
        r.tensile = v.at("T0_ratio") * r.ucs;
      if (has("crack_closure"))
      {
        r.closure_ratio  = v.at("E0_ratio");
        r.closure_stress = v.at("sigma_cc");
      }
      if (has("machine_compliance"))
        r.k_frame = v.at("k_machine");
      if (has("end_friction"))
      {
        // a homogeneous Mohr-Coulomb cylinder held at its ends fails at its rims first and is
        // weakened by friction (README, Known limitations); a rock that fails through its weak
        // cells, with crack-band softening, is confined by it (Weibull m 10 on 5 mm cells, a
        // rock's 5-20: CoupledUcs.EndFrictionStrengthensAHeterogeneousRock)
        r.friction  = v.at("mu");
        r.weibull_m = 10;
        r.notes.push_back("end friction: mu " + std::to_string(r.friction) +
                          " on a heterogeneous rock (Weibull m 10, crack-band softening) whose "
                          "brittleness (Rock/Fracture energy) and strengths the simulator fitted "
                          "to the extended model's standard and shortest specimens; the mean of "
                          "three rocks (Rock/Scatter seed 1-3), of which this file is the first");
      }
      if (has("heterogeneity"))
      {
        const double f = sph::rock::weakest_link_strength_factor(d.volume_ratio, v.at("weibull_m"));
        r.strength_factor *= f;
        r.notes.push_back("heterogeneity: strengths x " + std::to_string(f) +
                          " for this specimen's volume (" + std::to_string(d.volume_ratio) +
                          " x a 50 x 100 mm core), Weibull m " + std::to_string(v.at("weibull_m")));
      }
      if (has("loading_rate") && d.strain_rate > 0)
      {
        const double f = sph::rock::rate_strength_factor(d.strain_rate, 1e-5, v.at("rate_A"));
        r.strength_factor *= f;
        r.notes.push_back("loading rate: strengths x " + std::to_string(f) +
                          " at this specimen's strain rate " + std::to_string(d.strain_rate) +
                          " /s (A " + std::to_string(v.at("rate_A")) +
                          " per decade from 1e-5 /s); the simulator loads at its own "
                          "quasi-static rate");
      }
      return r;
    }

    /// The measured points of a BTS curve for the simulator's disc, which the surrogate cannot
    /// model (the disc's displacement is not a material point's): the platen displacement at
    /// forces of 5-90 % of the peak, about 20 pre-peak points, noise that of the curve; a
    /// peak-only curve gives its displacement at the peak, as uncertain as its strength (the
    /// data's relative strength noise).
    void disc_points(const Study &s, const Curve &c, SimulatorTarget &t)
    {
      const std::size_t ip = peak_index(c);
      const double fp      = c.force[ip];
      const auto add = [&](const double force, const double displacement, const double noise) {
        Datum p;
        p.kind     = Datum::curve_point;
        p.test     = "BTS";
        p.group    = c.group;
        p.force    = force;
        p.measured = displacement;
        p.where    = c.file;
        t.points.push_back(p);
        t.point_noise.push_back(noise);
      };
      if (c.peak_only())
      {
        if (c.failed && c.displacement[ip] > 0)
          add(fp, c.displacement[ip], s.strength_rel_noise * c.displacement[ip]);
        return;
      }
      const double noise = curve_noise(c);
      for (const std::size_t best : pre_peak_rows(c, 20)) // as the curve points of make_data
        add(c.force[best], c.displacement[best], noise);
    }

    /// The specimens the coupled simulator runs: the first specimen of each curve condition and
    /// of each strength condition of the group whose datum the baseline misses most, where the
    /// baseline misses it (its peak or a curve point) by more than three noise SDs, the worst
    /// missed first, Options::max_simulations in all.
    /// Each carries its baseline rock and its extended rock fitted without it.
    std::vector<SimulatorTarget> simulator_targets(const Study &s, const Surrogate &base_model,
                                                   const Fitted &current, const bool extended)
    {
      const int n_rows = static_cast<int>(s.data.strengths.size());
      const auto miss  = [&](const Datum &d) {
        return std::abs(base_model.predict(d, {}) - d.measured) / s.noise(d);
      };
      const Datum *worst = nullptr;
      for (const auto &d : s.all)
        if (d.kind == Datum::strength && (worst == nullptr || miss(d) > miss(*worst)))
          worst = &d;
      // the conditions (of curves, and of the worst-missed group's strength rows) and their misses
      std::map<int, const Datum *> first_of_condition; // condition -> its first specimen's datum
      std::map<int, double> condition_miss;
      for (const auto &d : s.all)
      {
        const bool curve = d.source >= n_rows;
        if (!curve && (d.kind != Datum::strength || worst == nullptr || d.group != worst->group))
          continue;
        if (d.test == "TXE")
          continue; // the simulator runs no triaxial extension test

        if (!first_of_condition.count(d.condition))
          first_of_condition[d.condition] = &d;
        if (first_of_condition[d.condition]->source == d.source)
          condition_miss[d.condition] = std::max(condition_miss[d.condition], miss(d));
      }
      // only where the baseline is wrong, by more than three of the data's noise (a specimen
      // both models meet measures the simulator's discretisation, not the effect), the worst
      // missed first
      // A BTS curve is kept whatever the surrogate says, after the missed ones: the surrogate
      // has no disc displacement, only the simulator can tell whether it is right.
      std::vector<std::pair<double, const Datum *>> order;
      for (const auto &[c, d] : first_of_condition)
        if (condition_miss[c] > 3)
          order.push_back({-condition_miss[c], d});
        else if (d->source >= n_rows && d->test == "BTS")
          order.push_back({0.0, d});
      std::sort(order.begin(), order.end(),
                [](const auto &a, const auto &b) { return a.first < b.first; });
      if (static_cast<int>(order.size()) > s.options.max_simulations)
        order.resize(static_cast<std::size_t>(s.options.max_simulations));

      std::vector<SimulatorTarget> targets;
      for (const auto &[key, d] : order)
      {
        SimulatorTarget t;
        t.test  = d->test;
        t.group = d->group;
        const GroupBase *g = nullptr;
        for (const auto &x : s.groups)
          if (x.group == d->group)
            g = &x;
        if (g == nullptr || g->ucs <= 0)
          continue; // a group without strength: nothing to simulate to failure
        double surrogate_peak = 0; // sigma1 [MPa] the baseline surrogate expects
        if (d->source >= n_rows)
        {
          const Curve &c = s.data.curves[static_cast<std::size_t>(d->source - n_rows)];
          t.name         = c.file;
          t.curve        = &c;
          t.diameter     = c.diameter;
          t.length       = c.length;
          t.sigma3       = c.test == "BTS" ? 0 : c.confining;
          t.platen       = c.platen_displacement;
          t.has_peak     = c.failed;
          for (const auto &p : s.all)
            if (p.source == d->source)
            {
              if (p.kind == Datum::curve_point)
              {
                t.points.push_back(p);
                t.point_noise.push_back(s.noise(p));
              }
              else
              {
                t.measured_peak = p.measured;
                t.peak_noise    = s.noise(p);
              }
            }
          if (c.test == "BTS")
            disc_points(s, c, t);
        }
        else
        {
          t.name          = d->where;
          t.sigma3        = d->test == "BTS" ? 0 : d->sigma3;
          t.measured_peak = d->measured;
          t.peak_noise    = s.noise(*d);
          if (d->test == "BTS")
            t.length = 25; // a standard disc, 50 x 25 mm
        }
        if (d->kind == Datum::strength)
          surrogate_peak = base_model.predict(*d, {});
        // a compressive run goes on to twice the larger of the measured and the expected strain
        // at failure (a steep baseline envelope is not cut short); a disc to d / D = 0.006
        double eps = 2.0 * (std::max(surrogate_peak, t.measured_peak) - t.sigma3) / g->E;
        if (t.curve != nullptr && !t.curve->displacement.empty())
          eps = std::max(eps, 1.5 * *std::max_element(t.curve->displacement.begin(),
                                                     t.curve->displacement.end()) /
                                t.length);
        t.end_strain = t.test == "BTS" ? 0.006 : std::clamp(eps, 0.01, 0.5);
        t.baseline   = simulated_rock(s, *g, *d, {}, {});
        if (extended)
        {
          // the extended model fitted without this specimen, from the all-data optimum
          std::vector<Datum> train;
          for (const auto &x : s.all)
            if (x.source != d->source)
              train.push_back(x);
          const Fitted f = fit_model(s, current.effects, current.refit, train, values_of(current), false);
          t.extended = simulated_rock(s, *g, *d, current.effects, values_of(f));
          if (t.extended.weibull_m > 0)
          {
            // what the extended model says a standard 50 x 100 mm specimen of the group and the
            // data's shortest compressive specimen (at the reference volume and rate) carry
            const Surrogate model(s.groups, current.effects, current.refit);
            Datum standard;
            standard.test               = "UCS";
            standard.group              = g->group;
            t.extended.calibration_peak = model.predict(standard, f.result.values);
            Datum shortest              = standard;
            for (const auto &c : s.data.curves)
              if (c.test != "BTS" && c.length / c.diameter < shortest.slenderness)
              {
                shortest.slenderness      = c.length / c.diameter;
                t.extended.short_diameter = c.diameter;
                t.extended.short_length   = c.length;
              }
            if (t.extended.short_length > 0) // else no specimen shorter than L/D 2: mu as fitted
              t.extended.short_peak = model.predict(shortest, f.result.values);
          }
        }
        else
          t.extended = t.baseline;
        targets.push_back(t);
      }
      return targets;
    }

  } // namespace

  Diagnosis diagnose(const Data &data, const Options &options)
  {
    Study s{data, options, {}, {}, {}, 0.05, {}, {}, {}};
    s.groups = baseline_groups(data, s.notes);
    s.all    = make_data(data, s.curve_sd);
    check_applicability(s);
    Diagnosis out;
    out.n_strength          = n_strength(s.all);
    out.n_curve_points      = static_cast<int>(s.all.size()) - out.n_strength;
    const bool has_strength = out.n_strength > 0;

    // strength noise: the relative scatter of replicate specimens if there are enough: strength
    // rows of one test, group and confinement (BTS: of one group), and curve peaks of one test
    // condition (also L/D, volume and strain rate)
    {
      std::map<std::string, std::vector<double>> reps;
      for (const auto &d : s.all)
        if (d.kind == Datum::strength)
        {
          std::ostringstream k;
          if (d.source < static_cast<int>(data.strengths.size()))
            k << d.test << '|' << d.group << '|'
              << (d.test == "BTS" ? 0L : std::lround(d.sigma3 * 10));
          else
            k << "curves|" << d.condition;
          reps[k.str()].push_back(d.measured);
        }
      double ss = 0;
      int dof   = 0;
      for (const auto &[k, v] : reps)
        if (v.size() > 1)
        {
          const double mean = std::accumulate(v.begin(), v.end(), 0.0) / v.size();
          for (double x : v)
            ss += std::pow(x / mean - 1, 2);
          dof += static_cast<int>(v.size()) - 1;
        }
      if (dof >= 3)
      {
        s.strength_rel_noise = std::max(std::sqrt(ss / dof), 2e-3);
        out.notes.push_back("strength noise " + std::to_string(100 * s.strength_rel_noise) +
                            " % from " + std::to_string(dof) +
                            " degrees of freedom of replicate specimens");
      }
      else if (has_strength)
      {
        // from the residuals of the richest applicable strength model (all strength effects on)
        EffectSet rich;
        for (const auto *e : {"tension_cutoff", "envelope_curvature"})
          if (s.applicable.count(e))
            rich.insert(e);
        s.strength_rel_noise = 1.0;
        std::vector<Datum> sd;
        for (const auto &d : s.all)
          if (d.kind == Datum::strength)
            sd.push_back(d);
        const Fitted f = fit_model(s, rich, true, sd);
        const int dofr = static_cast<int>(sd.size()) - static_cast<int>(f.parameters.size());
        if (dofr >= 2)
        {
          s.strength_rel_noise = std::max(std::sqrt(f.result.chi2 / dofr), 2e-3);
          out.notes.push_back(
            "strength noise " + std::to_string(100 * s.strength_rel_noise) +
            " % from the residuals of the richest strength model (no replicates)");
        }
        else
        {
          s.strength_rel_noise = 0.05;
          out.notes.push_back(
            "strength noise 5 % assumed (no replicates, too few rows to estimate it)");
        }
      }
    }
    out.noise["strength_relative"] = s.strength_rel_noise;
    if (!s.curve_sd.empty())
    {
      double m = 0;
      for (const auto &[k, v] : s.curve_sd)
        m += v / s.curve_sd.size();
      out.noise["curve_displacement_mm"] = m;
    }
    for (const auto &n : s.notes)
      out.notes.push_back(n);

    // baseline (nothing fitted) and its strength refit
    const Fitted base = fit_model(s, {}, false, s.all);
    Fitted reference  = base;
    if (has_strength)
    {
      const Fitted refit = fit_model(s, {}, true, s.all);
      if (refit.bic < base.bic)
        reference = refit;
    }
    const Surrogate base_model(s.groups, {}, false);
    const Rms base_rms = rms_of(s, base_model, {}, s.all);
    const Rms base_ho  = heldout(s, {}, false, nullptr);

    // single candidates
    std::map<std::string, Fitted> single;
    std::map<std::string, std::vector<double>> single_heldout; // held-out predictions, by effect
    for (const auto &e : effect_names())
    {
      Candidate c;
      c.name           = e;
      c.error_before   = base_rms.norm;
      c.heldout_before = base_ho.norm;
      if (!s.applicable.count(e))
      {
        c.applicable = false;
        c.reason     = s.not_applicable[e];
        out.candidates.push_back(c);
        continue;
      }
      const Fitted f = fit_model(s, {e}, true, s.all);
      single[e]      = f;
      const Surrogate m(s.groups, {e}, true);
      c.parameters         = fitted_values(s, f);
      c.delta_bic          = reference.bic - f.bic;
      c.delta_bic_baseline = base.bic - f.bic;
      c.error_after        = rms_of(s, m, f.result.values, s.all).norm;
      // held-out check only where the effect has positive evidence (it is the costly part)
      c.heldout_after = std::nan("");
      if (c.delta_bic > 0)
      {
        single_heldout[e] = heldout_predictions(s, {e}, true, &f);
        c.heldout_after   = rms_of(s, s.all, single_heldout[e]).norm;
      }
      if (f.at_bound)
        c.reason = "a parameter sits at a bound of its range: the data do not show the effect";
      out.candidates.push_back(c);
    }

    // forward selection by BIC
    Fitted current = reference;
    EffectSet chosen;
    while (true)
    {
      std::string best_e;
      Fitted best_f;
      for (const auto &e : s.applicable)
      {
        if (chosen.count(e))
          continue;
        EffectSet trial = chosen;
        trial.insert(e);
        Fitted f =
          chosen.empty() ? single[e] : fit_model(s, trial, true, s.all, values_of(current));
        if (!chosen.empty())
        {
          // also from the single-effect optimum of e (a warm start for its own parameters)
          auto warm = values_of(current);
          for (const auto &[k, v] : values_of(single[e]))
            if (!warm.count(k))
              warm[k] = v;
          Fitted g = fit_model(s, trial, true, s.all, warm);
          if (g.bic < f.bic)
            f = g;
        }
        if (f.at_bound)
          continue;
        if (best_e.empty() || f.bic < best_f.bic)
        {
          best_e = e;
          best_f = f;
        }
      }
      if (best_e.empty() || current.bic - best_f.bic <= options.bic_threshold)
        break;
      chosen.insert(best_e);
      out.identified.push_back(best_e);
      current = best_f;
    }

    // the extended model's errors; an extension that does not predict held-out specimens better
    // is not kept
    const Surrogate ext_model(s.groups, current.effects, current.refit);
    Rms ext_rms = rms_of(s, ext_model, current.result.values, s.all);
    std::vector<double> base_pred;
    for (const auto &d : s.all)
      base_pred.push_back(base_model.predict(d, {}));
    // (one effect named: its candidate's held-out predictions, the same fit from the same optimum)
    std::vector<double> ext_ho_pred = base_pred;
    if (chosen.size() == 1 && single_heldout.count(*chosen.begin()))
      ext_ho_pred = single_heldout.at(*chosen.begin());
    else if (!current.parameters.empty())
      ext_ho_pred = heldout_predictions(s, current.effects, current.refit, &current);
    Rms ext_ho             = rms_of(s, s.all, ext_ho_pred);
    const Discrepancy disc = discrepancy(s, base_pred, ext_ho_pred, 3.0);

    if (!out.identified.empty() && !(ext_ho.norm < base_ho.norm))
    {
      out.notes.push_back("the BIC-selected extension (" + out.identified.front() +
                          ", ...) did not predict held-out specimens better; answer none");
      out.identified.clear();
    }
    if (out.identified.empty())
    {
      out.identified = {"none"};
      if (chosen.size() > 0 || reference.refit)
        out.notes.push_back(
          reference.refit && chosen.empty()
            ? "the baseline's strength refitted (no extension) explains the data better than "
              "the measured c, phi: they are inconsistent with the strength rows"
            : "");
    }
    // competing explanations of the first named effect
    if (out.identified.front() != "none")
    {
      double best = 0;
      for (const auto &c : out.candidates)
        if (c.name == out.identified.front())
          best = c.delta_bic;
      for (const auto &c : out.candidates)
        if (c.applicable && c.reason.empty() && c.delta_bic > options.bic_threshold &&
            std::find(out.identified.begin(), out.identified.end(), c.name) ==
              out.identified.end() &&
            c.delta_bic > best - options.bic_threshold)
        {
          out.indistinguishable.push_back(c.name);
          out.notes.push_back(c.name + " explains the data about as well as " +
                              out.identified.front() + " (Delta BIC " +
                              std::to_string(c.delta_bic) + " vs " + std::to_string(best) +
                              "): these data cannot tell them apart");
        }
    }
    std::string model_name =
      "linear Mohr-Coulomb (c, phi measured or calibrated from UCS and BTS), measured E, "
      "rigid frictionless platens, platen displacement";
    out.baseline         = {model_name,
                            base_rms.norm,
                            base_ho.norm,
                            base_rms.strength,
                            base_ho.strength,
                            base_rms.curve,
                            base_ho.curve,
                            0,
                            {}};
    std::string ext_name = current.refit ? "baseline, strength refitted" : "baseline";
    for (const auto &e : current.effects)
      ext_name += " + " + e;
    if (out.identified == std::vector<std::string>{"none"})
    {
      ext_rms  = base_rms;
      ext_ho   = base_ho;
      ext_name = model_name;
    }
    else
      out.extended_parameters = fitted_values(s, current);
    out.extended     = {ext_name,
                        ext_rms.norm,
                        ext_ho.norm,
                        ext_rms.strength,
                        ext_ho.strength,
                        ext_rms.curve,
                        ext_ho.curve,
                        0,
                        {}};
    out.gain         = ext_rms.norm > 0 ? base_rms.norm / ext_rms.norm : 1;
    out.heldout_gain = ext_ho.norm > 0 ? base_ho.norm / ext_ho.norm : 1;
    if (out.identified != std::vector<std::string>{"none"} && disc.n > 0)
    {
      out.n_discrepancy        = disc.n;
      out.baseline.discrepancy = disc.before;
      out.extended.discrepancy = disc.after;
      out.discrepancy_gain     = disc.after > 0 ? disc.before / disc.after : 1;
    }
    else if (disc.n > 0)
    {
      out.n_discrepancy        = disc.n;
      out.baseline.discrepancy = out.extended.discrepancy = disc.before;
    }
    out.notes.erase(std::remove(out.notes.begin(), out.notes.end(), std::string()),
                    out.notes.end());
    // the coupled simulator on held-out specimens, baseline and extended case (optional: tens of
    // seconds a run at 2.5 mm)
    if (options.coupled_spacing > 0 && has_strength)
      simulate(simulator_targets(s, base_model, current,
                                 out.identified != std::vector<std::string>{"none"}),
               options, out);
    // tables for the plots: envelopes from the largest tension to the largest confinement
    {
      const bool ext_on            = out.identified != std::vector<std::string>{"none"};
      const Surrogate &em          = ext_on ? ext_model : base_model;
      const std::vector<double> ep = ext_on ? current.result.values : std::vector<double>{};
      double s3max                 = 10;
      for (const auto &d : s.all)
        if (d.kind == Datum::strength)
          s3max = std::max(s3max, d.sigma3);
      std::ostringstream env;
      env << "group,sigma3_MPa,baseline_sigma1_MPa,extended_sigma1_MPa\n";
      for (const auto &g : s.groups)
      {
        const double tb = base_model.tensile_strength(g.group, {}),
                     te = em.tensile_strength(g.group, ep);
        env << g.group << ',' << -tb << ",0,\n" << g.group << ',' << -te << ",,0\n";
        for (int i = 0; i <= 40; ++i)
        {
          const double s3 = 1.2 * s3max * i / 40.0;
          env << g.group << ',' << s3 << ',' << base_model.envelope(g.group, s3, {}) << ','
              << em.envelope(g.group, s3, ep) << '\n';
        }
      }
      out.envelope_table = env.str();
      std::ostringstream pts;
      pts << "kind,source,group,test,sigma3_MPa,force_kN,measured,baseline,extended\n";
      for (const auto &d : s.all)
        pts << (d.kind == Datum::strength ? "strength" : "curve") << ',' << d.source << ','
            << d.group << ',' << d.test << ',' << d.sigma3 << ',' << d.force << ',' << d.measured
            << ',' << base_model.predict(d, {}) << ',' << em.predict(d, ep) << '\n';
      out.points_table = pts.str();
    }
    for (const auto &g : s.groups)
      out.notes.push_back("group " + g.group + ": baseline UCS " + std::to_string(g.ucs) +
                          " MPa, phi " + std::to_string(g.phi) + " deg (" + g.source + "), E " +
                          std::to_string(g.E / 1e3) + " GPa");
    return out;
  }
} // namespace diagnose
