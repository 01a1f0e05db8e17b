// The coupled simulator in `cosim diagnose`: each held-out specimen run as a case of the coupled
// simulator (run_case) with the baseline rock and with the extended one, its curve and peak put
// against the measured ones (see diagnose_model.h, simulate()).
#include "diagnose_model.h"

#include <coupling/run_case.h>
#include <coupling/run_output.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <stdexcept>

namespace diagnose
{
  namespace
  {
    constexpr double pi = 3.14159265358979323846;

    std::string num(const double v)
    {
      char b[32];
      std::snprintf(b, sizeof b, "%.7g", v);
      return b;
    }

    /// Particle spacing of a specimen's run [m]: the one asked for, coarsened so that a cylinder
    /// has at most 20 particles across (a 150 mm core at 2.5 mm would be 1.3 million particles;
    /// the rock model has no length scale of its own in its strength), and fine enough that 10
    /// span the specimen's smallest dimension (the case reader's rule).
    double spacing_of(const SimulatorTarget &t, const double spacing)
    {
      const double dx = std::max(spacing, t.diameter * 1e-3 / 20.0);
      return std::min(dx, std::min(t.diameter, t.length) * 1e-3 / 10.0);
    }

    /// The case file's "Section/Key=value" lines of a specimen with a rock.
    std::vector<std::string> overrides_of(const SimulatorTarget &t, const SimulatedRock &r,
                                          const double dx)
    {
      const bool bts = t.test == "BTS";
      std::vector<std::string> o = {
        std::string("Test/Type=") + (bts ? "BTS" : (t.sigma3 > 0 ? "CTCS" : "UCS")),
        "Test/Diameter=" + num(t.diameter * 1e-3),
        "Test/Length=" + num(t.length * 1e-3),
        "Test/Confining pressure=" + num(bts ? 0.0 : t.sigma3 * 1e6),
        "Rock/Youngs modulus=" + num(r.E * 1e6),
        "Rock/Poissons ratio=" + num(r.nu),
        "Rock/Density=" + num(r.density)};
      const double ucs = r.ucs * r.strength_factor;
      const double sp = std::sin(r.phi * pi / 180), cp = std::cos(r.phi * pi / 180);
      const double c = ucs * (1 - sp) / (2 * cp);
      o.push_back("Rock/Cohesion=" + num(c * 1e6));
      o.push_back("Rock/Friction angle=" + num(r.phi));
      if (r.hoek_brown)
      {
        o.push_back("Rock/Model=hoek-brown");
        o.push_back("Rock/UCS=" + num(ucs * 1e6));
        o.push_back("Rock/Hoek-Brown mi=" + num(r.m_i));
      }
      else
        o.push_back(std::string("Rock/Model=") +
                    (r.tensile > 0 ? "mohr-coulomb-cutoff" : "mohr-coulomb"));
      if (r.tensile > 0)
      {
        // Mohr-Coulomb with a cut-off above its apex c / tan(phi) is Mohr-Coulomb: held there
        const double t0 = r.tensile * r.strength_factor;
        o.push_back("Rock/Tensile strength=" +
                    num(1e6 * (r.hoek_brown ? t0 : std::min(t0, c / std::tan(r.phi * pi / 180)))));
      }
      if (r.closure_ratio < 1)
      {
        o.push_back("Rock/Closure modulus ratio=" + num(r.closure_ratio));
        o.push_back("Rock/Closure stress=" + num(r.closure_stress * 1e6));
      }
      if (r.k_frame > 0)
        o.push_back("Platens/Frame stiffness=" + num(r.k_frame * 1e6)); // kN/mm -> N/m
      if (r.friction > 0)
        o.push_back("Platens/Friction coefficient=" + num(r.friction));
      o.push_back("SPH/Particle spacing=" + num(dx));
      o.push_back("Loading/End strain=" + num(t.end_strain));
      o.push_back("Output/Snapshots=0");
      return o;
    }

    /// Keeps the history rows of a run.
    class Recorder : public coupling::RunObserver
    {
    public:
      void history(const coupling::HistoryRow &row) override { rows.push_back(row); }
      std::vector<coupling::HistoryRow> rows;
    };

    /// Displacement [mm] at which `curve` first carries `force` [kN] before its peak; the
    /// displacement at its peak where it never does.
    double displacement_at(const SimulatedRun &run, const double force)
    {
      const auto &f       = run.force_kN;
      const auto &d       = run.displacement_mm;
      const std::size_t n = f.size();
      if (n == 0)
        return 0;
      const std::size_t ip = static_cast<std::size_t>(std::max_element(f.begin(), f.end()) - f.begin());
      for (std::size_t i = 1; i <= ip; ++i)
        if (f[i] >= force && f[i] > f[i - 1])
        {
          const double w = std::clamp((force - f[i - 1]) / (f[i] - f[i - 1]), 0.0, 1.0);
          return d[i - 1] + w * (d[i] - d[i - 1]);
        }
      return force <= f.front() ? d.front() : d[ip];
    }

    /// Runs a case: its case file (without the header), curve and peak; no errors yet.
    SimulatedRun execute(const SimulatorTarget &t, const SimulatedRock &r, const Options &options,
                         const double dx)
    {
      SimulatedRun out;
      coupling::CaseParameters c;
      options.read_case(overrides_of(t, r, dx), c, out.case_text); // Output/Snapshots=0 among them
      c.output.progress = false;
      Recorder rec;
      const coupling::Summary s = coupling::run_case(c, rec);
      out.peak_MPa              = s.peak_stress / 1e6;
      out.stop_reason           = s.stop_reason;
      // the curve from the start of the deviatoric load (CTCS: after the confinement), in the
      // data's units: deviatoric force (BTS: the load) and the displacement where it was read
      const bool bts    = t.test == "BTS";
      const double area = pi * t.diameter * t.diameter / 4; // [mm^2]
      std::vector<double> q, d;
      for (const auto &row : rec.rows)
      {
        q.push_back(bts ? row.force / 1e3 : (row.stress / 1e6 - t.sigma3) * area / 1e3);
        d.push_back(t.platen || bts ? row.displacement * 1e3 : row.axial_gauge_strain * t.length);
      }
      if (q.empty())
        return out;
      const std::size_t ip = static_cast<std::size_t>(std::max_element(q.begin(), q.end()) - q.begin());
      std::size_t i0       = 0;
      for (std::size_t i = 0; i < ip; ++i)
        if (q[i] <= 2e-3 * q[ip])
          i0 = i;
      for (std::size_t i = i0; i < q.size(); ++i)
      {
        out.force_kN.push_back(q[i]);
        out.displacement_mm.push_back(d[i] - d[i0]);
      }
      return out;
    }

    /// The errors of a run against the measured specimen, and its case file's header.
    void score(const SimulatorTarget &t, const SimulatedRock &r, SimulatedRun &run)
    {
      std::string head = "# written by cosim diagnose for specimen " + t.name +
                         ": the rock's values are set below (Rock/Group names the data "
                         "tables' group only for what is not)\n";
      for (const auto &n : r.notes)
        head += "# " + n + "\n";
      run.case_text = head + run.case_text;
      // a specimen gives two measurements, its strength and its deformation curve: its error is
      // the RMS of the two parts (peak residual / noise; RMS over the curve's points of residual
      // / noise), so twenty points of one curve do not outweigh the strength
      double ss_parts = 0, ss_points = 0, ss_curve = 0;
      int parts       = 0;
      if (t.has_peak)
      {
        ss_parts += std::pow((run.peak_MPa - t.measured_peak) / t.peak_noise, 2);
        ++parts;
      }
      for (std::size_t k = 0; k < t.points.size(); ++k)
      {
        const double e = displacement_at(run, t.points[k].force) - t.points[k].measured;
        ss_points += std::pow(e / t.point_noise[k], 2);
        ss_curve += e * e;
      }
      if (!t.points.empty())
      {
        ss_parts += ss_points / t.points.size();
        ++parts;
      }
      run.error        = parts > 0 ? std::sqrt(ss_parts / parts) : 0;
      run.curve_rms_mm = t.points.empty() ? 0 : std::sqrt(ss_curve / t.points.size());
    }
  } // namespace

  void simulate(const std::vector<SimulatorTarget> &targets, const Options &options,
                Diagnosis &out)
  {
    if (!options.read_case)
      throw std::logic_error("diagnose: Options::read_case is needed to run the coupled simulator");
    if (targets.empty())
    {
      out.notes.push_back("coupled simulator: not run; the baseline misses no specimen by more "
                          "than three of the data's noise SDs");
      return;
    }
    // a case runs once (the baselines of one geometry and confinement repeat)
    std::map<std::string, SimulatedRun> done;
    const auto run = [&](const SimulatorTarget &t, const SimulatedRock &r, const double dx) {
      std::string key;
      for (const auto &line : overrides_of(t, r, dx))
        key += line + "\n";
      auto it = done.find(key);
      if (it == done.end())
        it = done.emplace(key, execute(t, r, options, dx)).first;
      SimulatedRun result = it->second;
      score(t, r, result);
      return result;
    };
    double ss_b = 0, ss_e = 0, sp_b = 0, sp_e = 0, sc_b = 0, sc_e = 0;
    int n_peak = 0, n_curve = 0;
    for (const auto &t : targets)
    {
      Simulation sim;
      sim.name             = t.name;
      sim.test             = t.test;
      sim.group            = t.group;
      sim.diameter_mm      = t.diameter;
      sim.length_mm        = t.length;
      sim.confining_MPa    = t.test == "BTS" ? 0 : t.sigma3;
      sim.particle_spacing = spacing_of(t, options.coupled_spacing);
      sim.measured_peak_MPa = t.has_peak ? t.measured_peak : std::nan("");
      sim.n_points         = static_cast<int>(t.points.size());
      if (t.curve != nullptr)
      {
        sim.measured_displacement_mm = t.curve->displacement;
        sim.measured_force_kN        = t.curve->force;
      }
      sim.baseline = run(t, t.baseline, sim.particle_spacing);
      sim.extended = run(t, t.extended, sim.particle_spacing);
      ss_b += std::pow(sim.baseline.error, 2);
      ss_e += std::pow(sim.extended.error, 2);
      if (t.has_peak)
      {
        sp_b += std::pow(sim.baseline.peak_MPa - t.measured_peak, 2);
        sp_e += std::pow(sim.extended.peak_MPa - t.measured_peak, 2);
        ++n_peak;
      }
      if (!t.points.empty())
      {
        sc_b += std::pow(sim.baseline.curve_rms_mm, 2);
        sc_e += std::pow(sim.extended.curve_rms_mm, 2);
        ++n_curve;
      }
      out.simulations.push_back(sim);
    }
    const double n = std::max<double>(targets.size(), 1);
    for (auto [e, ss, sp, sc] : {std::tuple{&out.baseline, ss_b, sp_b, sc_b},
                                 std::tuple{&out.extended, ss_e, sp_e, sc_e}})
    {
      e->coupled["error"] = std::sqrt(ss / n);
      if (n_peak > 0)
        e->coupled["strength_rms_MPa"] = std::sqrt(sp / n_peak);
      if (n_curve > 0)
        e->coupled["curve_rms_mm"] = std::sqrt(sc / n_curve);
    }
    out.coupled_gain = ss_e > 0 ? std::sqrt(ss_b / ss_e) : 1;
    out.notes.push_back(
      "coupled simulator: " + std::to_string(targets.size()) + " specimens, " +
      std::to_string(done.size()) + " runs (run_case at spacing " + num(options.coupled_spacing) +
      " m, a cylinder at most 20 particles across); each extended case's parameters fitted "
      "without its specimen; size and rate enter as a strength factor of the specimen (the "
      "simulator loads at its own quasi-static rate)");
    // where the extended case does worse than the baseline, the simulator does not carry what
    // the surrogate named: say where, so that the gain is not read as the surrogate's
    std::string worse;
    for (std::size_t i = 0; i < out.simulations.size(); ++i)
    {
      const Simulation &m = out.simulations[i];
      if (m.extended.error > 1.05 * m.baseline.error + 0.5)
        worse += (worse.empty() ? "" : ", ") + simulation_stem(i) + " (" + m.name + ", " +
                 m.test + ": error " + num(m.baseline.error) + " -> " + num(m.extended.error) + ")";
    }
    if (!worse.empty())
      out.notes.push_back("coupled simulator: the extended case is worse than the baseline on " +
                          worse +
                          ": there the simulator does not reproduce the named effect as the "
                          "surrogate models it (platen friction, for one, weakens the simulated "
                          "cylinder: README, Known limitations)");
  }
} // namespace diagnose
