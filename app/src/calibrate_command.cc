// `cosim calibrate`: Mohr-Coulomb c, phi from UCS and BTS (diagnose/calibrate.h), for one pair of
// strengths or for every group of a data folder.
#include <app/calibrate_command.h>
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
    return "usage: cosim calibrate [--group Mx] [--ucs MPa --bts MPa] [--brazilian] [--data DIR] [--csv]\n"
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
           "Without options it prints the table for every group of the data folder (Table 3's UCS\n"
           "and BTS) next to the calibrated values stored there (Table 4).\n"
           "\n"
           "options:\n"
           "  --group Mx     only this group\n"
           "  --ucs MPa      a UCS of your own (with --bts)\n"
           "  --bts MPa      a BTS of your own (with --ucs)\n"
           "  --data DIR     data folder (default: the data cosim ships)\n"
           "  --brazilian    calibrate to the disc centre's stress state (see above)\n"
           "  --csv          print comma-separated values instead of an aligned table\n"
           "\n"
           "Exit status: 0 done, 2 bad input.\n";
  }

  int calibrate_main(const std::vector<std::string> &args)
  {
    std::string group, data = data_directory().string();
    double ucs = 0, bts = 0;
    bool has_ucs = false, has_bts = false, csv = false, brazilian = false;
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
      else
        throw InputError("cosim calibrate: unknown option '" + diagnose::clip(a) + "'" +
                         did_you_mean(a, {"--group", "--ucs", "--bts", "--brazilian", "--data", "--csv", "--help"}) +
                         "; accepted: --group, --ucs, --bts, --brazilian, --data, --csv");
    }
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
