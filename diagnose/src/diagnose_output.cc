// The diagnosis as files: diagnosis.json, report.md and the tables the plots are drawn from.
#include <diagnose/csv.h>
#include <diagnose/diagnose.h>
#include <coupling/run_case.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace diagnose
{

  namespace
  {
    namespace fs = std::filesystem;

    using Json = nlohmann::ordered_json; // keys in the order written

    /// A value to 6 significant digits (the precision the diagnosis carries); null when not finite.
    Json num(const double v)
    {
      if (!std::isfinite(v))
        return nullptr;
      char buffer[32];
      std::snprintf(buffer, sizeof buffer, "%.6g", v + 0.0); // + 0.0: no "-0"
      return std::strtod(buffer, nullptr);
    }

    Json values_json(const std::vector<FittedValue> &v)
    {
      Json out = Json::array();
      for (const auto &value : v)
        out.push_back({{"name", value.name},
                       {"unit", value.unit},
                       {"value", num(value.value)},
                       {"standard_error", num(value.standard_error)}});
      return out;
    }

    Json error_json(const ModelError &e)
    {
      Json o = {{"model", e.model},
                {"error_fit", num(e.fit)},
                {"error_heldout", num(e.heldout)},
                {"strength_rms_MPa", num(e.strength_rms_MPa)},
                {"heldout_strength_rms_MPa", num(e.heldout_strength_rms_MPa)},
                {"curve_rms_mm", num(e.curve_rms_mm)},
                {"heldout_curve_rms_mm", num(e.heldout_curve_rms_mm)},
                {"heldout_discrepancy", num(e.discrepancy)}};
      for (const auto &[k, v] : e.coupled)
        o["coupled_" + k] = num(v);
      return o;
    }

    std::string fmt(double v, int p = 3)
    {
      std::ostringstream o;
      o << std::setprecision(p) << v;
      return o.str();
    }

    std::string report_md(const Diagnosis &d, const std::string &data_dir)
    {
      std::ostringstream r;
      std::string ids;
      for (const auto &i : d.identified)
        ids += (ids.empty() ? "" : ", ") + i;
      r << "# cosim diagnose\n\nData: `" << data_dir << "` (" << d.n_strength
        << " strengths incl. curve peaks, " << d.n_curve_points << " pre-peak curve points).\n\n";
      r << "## Named cause: " << ids << "\n\n";
      for (const auto &i : d.indistinguishable)
        r << "Competing explanation the data cannot tell apart from it: `" << i
          << "` (see the candidates table).\n\n";
      if (d.identified.front() == "none")
        r << "No extension earns its parameters: the baseline explains the data within their "
             "noise.\n\n";
      else
      {
        r << "Evidence (Delta BIC against the best model without the effect, > 10 = very strong; "
             "held-out = leave one specimen out):\n\n";
        for (const auto &c : d.candidates)
          for (const auto &i : d.identified)
            if (c.name == i)
              r << "- `" << i << "`: Delta BIC " << fmt(c.delta_bic, 4) << " on its own; error "
                << fmt(c.error_before) << " -> " << fmt(c.error_after) << " (fit), "
                << fmt(c.heldout_before) << " -> " << fmt(c.heldout_after) << " (held-out).\n";
        r << "\nFitted values of the extended model (" << d.extended.model
          << "), +- one standard error:\n\n"
          << "| parameter | value | standard error | unit |\n|---|---|---|---|\n";
        for (const auto &v : d.extended_parameters)
          r << "| " << v.name << " | " << fmt(v.value, 5) << " | " << fmt(v.standard_error, 3)
            << " | " << v.unit << " |\n";
        r << "\n";
      }
      r << "## Gain\n\n| model | error (fit) | error (held-out) | strength RMS fit / held-out "
           "[MPa] | curve RMS "
           "fit / held-out [mm] |\n|---|---|---|---|---|\n";
      for (const auto *e : {&d.baseline, &d.extended})
        r << "| " << e->model << " | " << fmt(e->fit) << " | " << fmt(e->heldout) << " | "
          << fmt(e->strength_rms_MPa) << " / " << fmt(e->heldout_strength_rms_MPa) << " | "
          << fmt(e->curve_rms_mm) << " / " << fmt(e->heldout_curve_rms_mm) << " |\n";
      r << "\nGain (baseline error / extended error): " << fmt(d.gain) << " on the fitted data, "
        << fmt(d.heldout_gain)
        << " on held-out specimens. Errors are RMS residuals divided by the data noise.\n"
        << "\nWhere the baseline is wrong (" << d.n_discrepancy
        << " test conditions or curve points it misses by more than 3 SDs of their replicate "
           "mean): held-out error "
        << fmt(d.baseline.discrepancy) << " -> " << fmt(d.extended.discrepancy) << " SDs, gain "
        << fmt(d.discrepancy_gain)
        << " (the all-data gain above is diluted by the data both models fit to the noise).\n";
      if (!d.simulations.empty())
      {
        const auto coupled = [](const ModelError &e, const char *k) {
          return e.coupled.count(k) ? fmt(e.coupled.at(k)) : std::string("-");
        };
        r << "\n## In the coupled simulator\n\nEach specimen below was run as a case of the "
             "coupled simulator (`simulations/*.prm`, runnable with `cosim run`) with the "
             "baseline and with the extended model, whose parameters were fitted without that "
             "specimen (held out); the specimens are those the baseline misses by more than three "
             "noise SDs, the worst first, then every BTS curve (the surrogate has no disc "
             "displacement). Error: RMS over the specimens of each one's error, the "
             "RMS of its two parts: the peak's residual and the RMS residual of its pre-peak "
             "curve points (displacement at the measured forces), each divided by the data's "
             "noise.\n\n"
          << "| model | error (held-out) | strength RMS [MPa] | curve RMS [mm] |\n|---|---|---|---|\n"
          << "| baseline | " << coupled(d.baseline, "error") << " | "
          << coupled(d.baseline, "strength_rms_MPa") << " | " << coupled(d.baseline, "curve_rms_mm")
          << " |\n| extended | " << coupled(d.extended, "error") << " | "
          << coupled(d.extended, "strength_rms_MPa") << " | " << coupled(d.extended, "curve_rms_mm")
          << " |\n\nCoupled simulator's held-out gain: " << fmt(d.coupled_gain) << "\n\n"
          << "| case files | specimen | test | D x L [mm] | sigma3 [MPa] | spacing [mm] | measured peak "
             "[MPa] | baseline peak | extended peak | curve points | error baseline -> "
             "extended |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
        for (std::size_t i = 0; i < d.simulations.size(); ++i)
        {
          const Simulation &m = d.simulations[i];
          r << "| " << simulation_stem(i) << "_* | " << m.name << " | " << m.test << " | " << fmt(m.diameter_mm, 4) << " x "
            << fmt(m.length_mm, 4) << " | " << fmt(m.confining_MPa, 4) << " | "
            << fmt(1e3 * m.particle_spacing, 3) << " | " << fmt(m.measured_peak_MPa, 4) << " | "
            << fmt(m.baseline.peak_MPa, 4) << " | " << fmt(m.extended.peak_MPa, 4) << " | "
            << m.n_points << " | "
            << (left_out(m) ? std::string("a run unstable, left out (notes)")
                            : fmt(m.baseline.error) + " -> " + fmt(m.extended.error))
            << " |\n";
        }
      }
      r << "\n## Candidates\n\n| effect | applicable | Delta BIC | Delta BIC vs baseline | error "
           "fit before -> after | "
           "held-out before -> after | parameters | note |\n|---|---|---|---|---|---|---|---|\n";
      for (const auto &c : d.candidates)
      {
        std::string prm;
        for (const auto &v : c.parameters)
          if (v.name.rfind("UCS_", 0) != 0 && v.name.rfind("T0_", 0) != 0)
            prm += (prm.empty() ? "" : "; ") + v.name + " = " + fmt(v.value, 4) + " +- " +
                   fmt(v.standard_error, 2);
        if (!c.applicable)
          r << "| " << c.name << " | no | | | | | | " << c.reason << " |\n";
        else
          r << "| " << c.name << " | yes | " << fmt(c.delta_bic, 4) << " | "
            << fmt(c.delta_bic_baseline, 4) << " | " << fmt(c.error_before) << " -> "
            << fmt(c.error_after) << " | " << fmt(c.heldout_before) << " -> "
            << fmt(c.heldout_after) << " | " << prm << " | " << c.reason << " |\n";
      }
      r << "\n## Notes\n\n";
      for (const auto &n : d.notes)
        r << "- " << n << "\n";
      r << "\nPlots: `envelope.png` (strength envelope: baseline, extended, data), `curves.png` "
           "(measured "
           "and modelled pre-peak curves, where there are curves).\n";
      return r.str();
    }

    void write(const fs::path &p, const std::string &text)
    {
      std::ofstream o(p);
      o << text;
      if (!o)
        throw std::runtime_error("cannot write " + p.string());
    }
  } // namespace

  std::string diagnosis_json(const Diagnosis &d)
  {
    Json j;
    j["identified"]        = d.identified;
    j["indistinguishable"] = d.indistinguishable;
    j["candidates"]        = Json::array();
    for (const auto &c : d.candidates)
      j["candidates"].push_back({{"name", c.name},
                                 {"applicable", c.applicable},
                                 {"note", c.reason},
                                 {"evidence", {{"delta_bic", num(c.delta_bic)}, {"delta_bic_vs_baseline", num(c.delta_bic_baseline)}}},
                                 {"parameters", values_json(c.parameters)},
                                 {"error_before", num(c.error_before)},
                                 {"error_after", num(c.error_after)},
                                 {"heldout_error_before", num(c.heldout_before)},
                                 {"heldout_error_after", num(c.heldout_after)}});
    j["baseline"]            = error_json(d.baseline);
    j["extended"]            = error_json(d.extended);
    j["extended_parameters"] = values_json(d.extended_parameters);
    j["gain"]                = num(d.gain);
    j["heldout_gain"]        = num(d.heldout_gain);
    j["discrepancy_gain"]    = num(d.discrepancy_gain);
    j["n_discrepancy"]       = d.n_discrepancy;
    j["coupled_gain"]        = num(d.coupled_gain);
    j["coupled_unstable"]    = coupled_unstable(d);
    j["simulations"]         = Json::array();
    for (std::size_t i = 0; i < d.simulations.size(); ++i)
    {
      const Simulation &m = d.simulations[i];
      const std::string stem = "simulations/" + simulation_stem(i);
      Json o = {{"specimen", m.name},
                {"test", m.test},
                {"group", m.group},
                {"diameter_mm", num(m.diameter_mm)},
                {"length_mm", num(m.length_mm)},
                {"confining_MPa", num(m.confining_MPa)},
                {"particle_spacing_m", num(m.particle_spacing)},
                {"measured_peak_MPa", num(m.measured_peak_MPa)},
                {"curve_points", m.n_points}};
      for (const auto &[k, run] : {std::pair{"baseline", &m.baseline}, std::pair{"extended", &m.extended}})
        o[k] = {{"case_file", stem + "_" + k + ".prm"},
                {"peak_MPa", num(run->peak_MPa)},
                {"error", num(run->error)},
                {"curve_rms_mm", m.n_points > 0 ? num(run->curve_rms_mm) : Json(nullptr)},
                {"stop_reason", run->stop_reason},
                {"unstable", run->unstable}};
      j["simulations"].push_back(o);
    }
    j["noise"]               = Json::object();
    for (const auto &[k, v] : d.noise)
      j["noise"][k] = num(v);
    j["notes"] = d.notes;
    // invalid UTF-8 (a file name in a note) becomes U+FFFD rather than an exception
    return j.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
  }

  void write_report(const std::filesystem::path &out, const Diagnosis &d, const std::string &data_dir)
  {
    fs::create_directories(out);
    write(out / "diagnosis.json", diagnosis_json(d));
    write(out / "report.md", report_md(d, data_dir));
    write(out / "envelope.csv", d.envelope_table);
    write(out / "points.csv", d.points_table);
    if (d.simulations.empty())
      return;
    // the cases the coupled simulator ran and their curves beside the measured ones
    fs::create_directories(out / "simulations");
    std::ostringstream curves;
    curves << "specimen,source,displacement_mm,force_kN\n";
    for (std::size_t i = 0; i < d.simulations.size(); ++i)
    {
      const Simulation &m = d.simulations[i];
      const std::string stem = simulation_stem(i);
      write(out / "simulations" / (stem + "_baseline.prm"), m.baseline.case_text);
      write(out / "simulations" / (stem + "_extended.prm"), m.extended.case_text);
      const auto rows = [&](const char *source, const std::vector<double> &x,
                            const std::vector<double> &f) {
        for (std::size_t k = 0; k < x.size(); ++k)
          curves << stem << ',' << source << ',' << x[k] << ',' << f[k] << '\n';
      };
      rows("measured", m.measured_displacement_mm, m.measured_force_kN);
      rows("baseline", m.baseline.displacement_mm, m.baseline.force_kN);
      rows("extended", m.extended.displacement_mm, m.extended.force_kN);
    }
    write(out / "simulations" / "curves.csv", curves.str());
  }
} // namespace diagnose
