// `cosim calibrate`: Mohr-Coulomb c, phi from UCS and BTS (diagnose/calibrate.h), for one pair of
// strengths or for every group of a data folder.
#include <app/calibrate_command.h>
#include "calibrate_simulate.h"
#include <app/cli.h>
#include <diagnose/text_input.h>
#include <app/paths.h>
#include <coupling/errors.h>
#include <diagnose/calibrate.h>
#include <diagnose/material_table.h>

#include <cstdio>

namespace app
{

  using coupling::InputError;
  using diagnose::calibrate_mohr_coulomb;
  using diagnose::calibrate_mohr_coulomb_brazilian;
  using diagnose::MaterialTable;

  std::string calibrate_help()
  {
    return "usage: cosim calibrate [--group Mx] [--ucs MPa --bts MPa] [--brazilian | --envelope] [--data DIR] [--csv]\n"
           "       cosim calibrate --simulate UCS_CASE [--set S/K=V] [--seeds N] [--ucs MPa] [--tolerance PCT]\n"
           "                       [--check BTS_CASE | --with-bts BTS_CASE [--bts MPa] | --cutoff-from BTS_CASE [--bts MPa] |\n"
           "                        --mb-from BTS_CASE [--bts MPa]]\n"
           "\n"
           "Back-calculates the Mohr-Coulomb cohesion c and friction angle phi that reproduce a\n"
           "uniaxial compressive strength (UCS) and a Brazilian tensile strength (BTS), with\n"
           "Eqs. 14-15 of Yang et al. (2022):\n"
           "  UCS = 2c cos(phi)/(1 - sin(phi)),  BTS = 2c cos(phi)/(1 + sin(phi))\n"
           "  =>  sin(phi) = (UCS - BTS)/(UCS + BTS),  c = UCS (1 - sin(phi))/(2 cos(phi))\n"
           "\n"
           "\n"
           "With --brazilian the BTS is put where a Brazilian disc fails, at its centre's elastic\n"
           "stress state (compression 3 BTS, tension BTS) instead of in uniaxial tension:\n"
           "  N = (1 + sin(phi))/(1 - sin(phi)) = UCS/BTS - 3,  c = UCS / (2 sqrt(N))\n"
           "A Mohr-Coulomb disc calibrated by Eqs. 14-15 splits at UCS BTS/(UCS + 3 BTS) (M1:\n"
           "13.26 MPa against 15.43; the coupled BTS at 1-1.25 mm gives 13.5); with these c, phi at\n"
           "the measured BTS (M1 at 1.25 mm: 15.62 MPa). Runs use them with\n"
           "--set \"Rock/Strength parameters=brazilian\".\n"
           "\n"
           "With --envelope it fits the curved envelope of Rock/Strength parameters = envelope\n"
           "(Rock/Model = hoek-brown) to all of a group's strengths: generalised Hoek-Brown\n"
           "  sigma1 = sigma3 + sigma_ci (m_b sigma3 / sigma_ci + 1)^a,  sigma_ci = UCS,\n"
           "with a tension cut-off at the BTS; m_b and a minimise the squared relative misses of the\n"
           "triaxial strengths (Table 3's measured envelope at 10, 30, 50 MPa, groups M8-M10) and of\n"
           "the BTS (the disc centre's state 3 t, -t on the envelope or the cut-off); without\n"
           "triaxial strengths a = 0.5 and m_b puts the disc centre's state at failure on it. It\n"
           "prints the fit and its misses.\n"
           "\n"
           "With --simulate CASE (a UCS case file, Rock/Model = mohr-coulomb or mohr-coulomb-cutoff)\n"
           "it calibrates through the coupled simulator instead: it scales the case's cohesion and\n"
           "tension cut-off by one factor until the simulated UCS, the mean over --seeds rocks\n"
           "(Rock/Scatter seed, seed + 1, ...; a homogeneous rock runs once) of a scattered strength,\n"
           "is the group's Table 3 UCS\n"
           "(or --ucs) within --tolerance, and prints the --set lines that run the calibrated rock.\n"
           "A heterogeneous rock (Rock/Strength scatter > 0) fails below its particles' mean\n"
           "strength, so Eqs. 14-15 do not hold for it; this calibration does, at the case's spacing.\n"
           "--check BTS_CASE runs a BTS case with the same overrides and the calibrated strength.\n"
           "--with-bts BTS_CASE fits c and phi together, Eqs. 14-15's unknowns, so that the mean\n"
           "simulated UCS and BTS are both the measured ones (the group's Table 3, or --ucs and\n"
           "--bts), by Broyden's method on their logarithms: a heterogeneous rock loses more UCS\n"
           "than BTS, so its UCS/BTS ratio asks for another phi.\n"
           "--cutoff-from BTS_CASE is for Rock/Model = hoek-brown (Rock/Strength parameters =\n"
           "envelope): it scales the tension cut-off alone until the simulated BTS is the measured\n"
           "one, leaving the envelope that sets the UCS and the triaxial strengths as fitted, then\n"
           "runs the UCS case once as a check. The disc's peak under a cut-off follows its softening\n"
           "and spacing, not the centre's stress state: run the disc where it has converged\n"
           "(cases/bts/bts-flattened.prm).\n"
           "--mb-from BTS_CASE is its counterpart for a group without triaxial data (envelope gives\n"
           "a = 1/2 and m_b through the disc centre's closed-form state): it divides m_b alone until\n"
           "the simulated BTS is the measured one, with no cut-off but the envelope's own tensile\n"
           "apex sigma_ci / m_b, sigma_ci still the UCS, then runs the UCS case once as a check.\n"
           "\n"
           "Without options it prints the table for every group of the data folder (Table 3's UCS\n"
           "and BTS) next to the calibrated values stored there (Table 4).\n"
           "\n"
           "options:\n"
           "  --group Mx     only this group\n"
           "  --ucs MPa      a UCS of your own (with --bts)\n"
           "  --bts MPa      a BTS of your own (with --ucs)\n"
           "  --data DIR     data folder (default: the data cosim ships)\n"
           "  --brazilian    calibrate to the disc centre's stress state (see above)\n"
           "  --envelope     the Hoek-Brown envelope with cut-off through all strengths (see above)\n"
           "  --csv          print comma-separated values instead of an aligned table\n"
           "  --simulate CASE  calibrate through the simulator on this UCS case (see above), with\n"
           "                 --set \"S/K=V\" (repeatable), --seeds N (default 3), --ucs MPa,\n"
           "                 --tolerance PCT (default 0.5), --check BTS_CASE, --with-bts BTS_CASE,\n"
           "                 --cutoff-from BTS_CASE, --mb-from BTS_CASE, --bts MPa\n"
           "\n"
           "Exit status: 0 done, 2 bad input.\n";
  }

  namespace
  {
    /// `cosim calibrate --envelope`: the Hoek-Brown envelope with cut-off of each group (or of a
    /// UCS and BTS) and its misses [%] of the UCS, the BTS (the disc) and the triaxial strengths.
    int envelope_table(const std::string &group, const bool has_ucs, const double ucs, const double bts,
                       const std::string &data, const bool csv)
    {
      const char *head = csv ? "%s,%s,%s,%s,%s,%s,%s,%s,%s\n" : "%-8s %9s %9s %9s %8s %7s %9s %8s  %s\n";
      std::printf(head, "group", "UCS_MPa", "BTS_MPa", "sigma_ci", "m_b", "a", "cutoff", "BTS_err%",
                  "triaxial sigma3:err% (sigma1 measured -> envelope)");
      const auto row = [&](const std::string &name, const double u, const double b,
                           const std::vector<diagnose::TriaxialStrength> &t) {
        if (!(b > 0 && u > 4 * b))
          throw InputError("cosim calibrate --envelope: group " + name + ": need UCS > 4 BTS > 0 (MPa)");
        const auto h = diagnose::calibrate_hoek_brown(u, b, t);
        std::string misses;
        for (const auto &x : t)
        {
          char m[96];
          std::snprintf(m, sizeof m, "%s%g:%+.2f (%.1f -> %.1f)", misses.empty() ? "" : (csv ? ";" : " "),
                        x.sigma3, 100 * (diagnose::hoek_brown_sigma1(h, x.sigma3) / x.sigma1 - 1), x.sigma1,
                        diagnose::hoek_brown_sigma1(h, x.sigma3));
          misses += m;
        }
        const char *fmt = csv ? "%s,%.2f,%.2f,%.2f,%.3f,%.4f,%.2f,%+.2f,%s\n"
                              : "%-8s %9.2f %9.2f %9.2f %8.3f %7.4f %9.2f %+8.2f  %s\n";
        std::printf(fmt, name.c_str(), u, b, h.sigma_ci, h.m_b, h.a, h.tensile,
                    100 * (diagnose::hoek_brown_disc_strength(h) / b - 1), misses.empty() ? "-" : misses.c_str());
      };
      if (has_ucs)
      {
        row(group.empty() ? "-" : group, ucs, bts, {});
        return 0;
      }
      const MaterialTable table = MaterialTable::read(data);
      if (!group.empty())
        table.find(group);
      for (const auto &g : table.groups())
        if (group.empty() || g.group == group)
        {
          std::vector<diagnose::TriaxialStrength> t = diagnose::triaxial_strengths(g);
          for (auto &x : t)
            x = {x.sigma3 / 1e6, x.sigma1 / 1e6};
          row(g.group, g.ucs / 1e6, g.bts / 1e6, t);
        }
      return 0;
    }
  } // namespace

  int calibrate_main(const std::vector<std::string> &args)
  {
    if (is_simulated_calibration(args))
      return calibrate_simulate_main(args);
    std::string group, data = data_directory().string();
    double ucs = 0, bts = 0;
    bool has_ucs = false, has_bts = false, csv = false, brazilian = false, envelope = false;
    ArgumentCursor cursor("calibrate", args);
    while (!cursor.done())
    {
      const std::string a = cursor.next();
      if (a == "--group")
        group = cursor.value(a);
      else if (a == "--ucs")
        ucs = cursor.number(a), has_ucs = true;
      else if (a == "--bts")
        bts = cursor.number(a), has_bts = true;
      else if (a == "--data")
        data = cursor.value(a);
      else if (a == "--csv")
        csv = true;
      else if (a == "--brazilian")
        brazilian = true;
      else if (a == "--envelope")
        envelope = true;
      else
        throw InputError("cosim calibrate: unknown option '" + diagnose::clip(a) + "'" +
                         did_you_mean(a, {"--group", "--ucs", "--bts", "--brazilian", "--envelope", "--data", "--csv", "--help"}) +
                         "; accepted: --group, --ucs, --bts, --brazilian, --envelope, --data, --csv");
    }
    if (brazilian && envelope)
      throw InputError("cosim calibrate: --brazilian and --envelope are two calibrations; give one");
    if (envelope)
      return envelope_table(group, has_ucs, ucs, bts, data, csv);
    if (has_ucs != has_bts)
      throw InputError("cosim calibrate: give both --ucs and --bts (in MPa), or neither");

    const char *header_format = csv ? "%s,%s,%s,%s,%s,%s,%s\n" : "%-8s %10s %10s %10s %10s %10s %10s\n";
    const char *row_format = csv ? "%s,%.2f,%.2f,%.2f,%.2f,%s,%s\n" : "%-8s %10.2f %10.2f %10.2f %10.2f %10s %10s\n";
    if (has_ucs)
    {
      if (!(bts > 0 && ucs > bts))
        throw InputError("cosim calibrate: --ucs " + std::to_string(ucs) + " --bts " + std::to_string(bts) +
                         ": need 0 < BTS < UCS (MPa)");
      if (brazilian && !(ucs > 4 * bts))
        throw InputError("cosim calibrate --brazilian: --ucs " + std::to_string(ucs) + " --bts " +
                         std::to_string(bts) + ": need UCS > 4 BTS (else phi <= 0)");
      const auto s = brazilian ? calibrate_mohr_coulomb_brazilian(ucs, bts) : calibrate_mohr_coulomb(ucs, bts);
      std::printf(header_format, "group", "UCS_MPa", "BTS_MPa", "c_MPa", "phi_deg", "table_c", "table_phi");
      std::printf(row_format, group.empty() ? "-" : group.c_str(), ucs, bts, s.cohesion, s.friction_angle, "-", "-");
      return 0;
    }

    const MaterialTable table = MaterialTable::read(data);
    if (!group.empty())
      table.find(group);
    std::printf(header_format, "group", "UCS_MPa", "BTS_MPa", "c_MPa", "phi_deg", "table_c", "table_phi");
    for (const auto &g : table.groups())
    {
      if (!group.empty() && g.group != group)
        continue;
      const auto s = brazilian ? calibrate_mohr_coulomb_brazilian(g.ucs / 1e6, g.bts / 1e6)
                               : calibrate_mohr_coulomb(g.ucs / 1e6, g.bts / 1e6);
      char c4[32] = "-", phi4[32] = "-";
      if (g.calibrated_cohesion)
      {
        std::snprintf(c4, sizeof c4, "%.2f", *g.calibrated_cohesion / 1e6);
        std::snprintf(phi4, sizeof phi4, "%.2f", *g.calibrated_friction_angle);
      }
      std::printf(row_format, g.group.c_str(), g.ucs / 1e6, g.bts / 1e6, s.cohesion, s.friction_angle, c4, phi4);
    }
    return 0;
  }
} // namespace app
