// `cosim reference`: reads a UCS case, runs coupling's implicit FE reference of the cylinder and
// writes summary.json, curve.csv, end_face_stress.csv, axis_stress.csv and used_parameters.prm
// into a result folder (staged and published as `cosim run` does).
#include <app/case_file.h>
#include <app/cli.h>
#include <app/output_writer.h>
#include <app/paths.h>
#include <app/reference_command.h>
#include <app/result_folder.h>
#include <coupling/errors.h>
#include <coupling/reference_cylinder.h>
#include <coupling/references.h>
#include <diagnose/text_input.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>

namespace app
{
  using coupling::InputError;
  namespace fs = std::filesystem;

  namespace
  {
    struct ReferenceCommandOptions
    {
      std::string case_file, output;
      std::vector<std::string> overrides;
      coupling::ReferenceOptions reference;
      bool interface_given = false, platens_given = false, force = false, quiet = false,
           end_strain_given = false;
    };

    /// A whole number in [lo, hi] for `option`.
    unsigned int count_option(ArgumentCursor &cursor, const std::string &option,
                              const unsigned int lo, const unsigned int hi)
    {
      const double v = cursor.number(option);
      if (!(v >= lo && v <= hi && v == std::floor(v)))
        throw InputError("cosim reference: " + option + " takes a whole number in [" +
                         std::to_string(lo) + ", " + std::to_string(hi) + "]");
      return static_cast<unsigned int>(v);
    }

    ReferenceCommandOptions parse(const std::vector<std::string> &args)
    {
      ReferenceCommandOptions o;
      ArgumentCursor cursor("reference", args);
      const std::vector<std::string> known = {"--output", "--interface",  "--platens",    "--mesh",
                                              "--degree", "--increments", "--end-strain", "--set",
                                              "--force",  "--quiet",      "--help"};
      while (!cursor.done())
      {
        const std::string a = cursor.next();
        if (a == "-o" || a == "--output")
          o.output = cursor.value(a);
        else if (a == "--interface")
        {
          const std::string v = cursor.value(a);
          if (v == "bonded")
            o.reference.interface = coupling::ReferenceInterface::bonded;
          else if (v == "free-slip")
            o.reference.interface = coupling::ReferenceInterface::free_slip;
          else
            throw InputError("cosim reference: --interface '" + diagnose::clip(v) +
                             "'; accepted: bonded, free-slip");
          o.interface_given = true;
        }
        else if (a == "--platens")
        {
          const std::string v = cursor.value(a);
          if (v == "rigid")
            o.reference.platens = coupling::ReferencePlatens::rigid;
          else if (v == "elastic")
            o.reference.platens = coupling::ReferencePlatens::elastic;
          else
            throw InputError("cosim reference: --platens '" + diagnose::clip(v) +
                             "'; accepted: rigid, elastic");
          o.platens_given = true;
        }
        else if (a == "--mesh")
          o.reference.n_radial = count_option(cursor, a, 1, 256);
        else if (a == "--degree")
          o.reference.degree = count_option(cursor, a, 1, 2);
        else if (a == "--increments")
          o.reference.n_increments = count_option(cursor, a, 1, 100000);
        else if (a == "--end-strain")
        {
          o.reference.end_strain = cursor.number(a);
          if (!(o.reference.end_strain > 0 && o.reference.end_strain < 0.2))
            throw InputError("cosim reference: --end-strain takes a nominal strain in (0, 0.2)");
          o.end_strain_given = true;
        }
        else if (a == "--set")
          o.overrides.push_back(cursor.value(a));
        else if (a == "--force")
          o.force = true;
        else if (a == "--quiet" || a == "-q")
          o.quiet = true;
        else if (!a.empty() && a[0] == '-')
          throw InputError("cosim reference: unknown option '" + diagnose::clip(a) + "'" +
                           did_you_mean(a, known) +
                           "; accepted: -o OUTDIR, --interface, --platens, --mesh N, --degree 1|2, "
                           "--increments N, "
                           "--end-strain X, --set \"Section/Key=value\", --force, --quiet");
        else if (o.case_file.empty())
          o.case_file = a;
        else
          throw InputError("cosim reference: a second case file '" + diagnose::clip(a) +
                           "' (after '" + diagnose::clip(o.case_file) +
                           "'); reference takes one CASE.prm");
      }
      if (o.case_file.empty())
        throw InputError(
          "cosim reference: no case file; usage: cosim reference CASE.prm [-o OUTDIR] "
          "[--interface bonded|free-slip] [--platens rigid|elastic] [--mesh N]");
      return o;
    }

    std::string number(const double v)
    {
      char buffer[64];
      std::snprintf(buffer, sizeof buffer, "%.10g", v + 0.0);
      return buffer;
    }

    /// A value rounded to 10 significant digits (as summary.json of `cosim run`: 282.19, not
    /// 282.19000000000003); null when not finite.
    nlohmann::ordered_json rounded(const double v)
    {
      if (!std::isfinite(v))
        return nullptr;
      return std::strtod(number(v).c_str(), nullptr);
    }

    std::string curve_csv(const coupling::ReferenceResult &r)
    {
      std::ostringstream out;
      out << "platen_displacement_mm,strain,radial_strain,force_kN,stress_MPa,newton_iterations\n";
      for (const auto &row : r.curve)
        out << number(row.platen_displacement * 1e3) << ',' << number(row.strain) << ','
            << number(row.radial_strain) << ',' << number(row.force * 1e-3) << ','
            << number(row.stress * 1e-6) << ',' << row.iterations << '\n';
      return out.str();
    }

    std::string profile_csv(const std::vector<coupling::ReferenceStressSample> &samples)
    {
      std::ostringstream out;
      out << "r_mm,z_mm,axial_stress_MPa,radial_stress_MPa\n";
      for (const auto &s : samples)
        out << number(s.r * 1e3) << ',' << number(s.z * 1e3) << ',' << number(s.axial_stress * 1e-6)
            << ',' << number(s.radial_stress * 1e-6) << '\n';
      return out.str();
    }
  } // namespace

  std::string reference_help()
  {
    return "usage: cosim reference CASE.prm [-o OUTDIR] [--interface bonded|free-slip] [--platens "
           "rigid|elastic]\n"
           "                      [--mesh N] [--degree 1|2] [--increments N] [--end-strain X]\n"
           "                      [--set \"Section/Key=value\" ...] [--force] [--quiet]\n"
           "\n"
           "An independent solution of a UCS case: a quasi-static implicit finite element model of "
           "the\n"
           "rock cylinder between platens (deal.II, axisymmetric, small strain, Newton, "
           "displacement-\n"
           "controlled increments). The rock is the case's, elastic, Mohr-Coulomb (with its "
           "dilation\n"
           "angle and tension cut-off) or Hoek-Brown, with the SPH rock's return mapping, but "
           "perfectly plastic: no\n"
           "softening and no strength scatter. The platens are rigid or elastic steel "
           "(Platens/Youngs\n"
           "modulus, Poissons ratio, Thickness, Diameter; 0 = 1.2 x the specimen's diameter;\n"
           "Loaded face: the ram's face clamped or a roller), tied to the rock's end faces node by "
           "node,\n"
           "on the assumption that the interface stays closed.\n"
           "The coupled solver's numerics (SPH/*, Loading/Strain rate, Platens/Element size, "
           "Contact\n"
           "stiffness scale, Density) do not apply; SPH/Particle spacing only sizes platens of "
           "Diameter 0.\n"
           "\n"
           "Writes into OUTDIR (default results/<case stem>-reference):\n"
           "  summary.json          peak stress and force, strain and platen displacement at the "
           "peak,\n"
           "                        the rock's uniaxial closed form (closed_form_ucs_MPa; "
           "Mohr-Coulomb's\n"
           "                        also as mohr_coulomb_ucs_MPa), mesh, Newton counts, wall time\n"
           "  curve.csv             platen_displacement_mm, strain (specimen), radial_strain "
           "(mid-height),\n"
           "                        force_kN, stress_MPa (force / initial area), "
           "newton_iterations\n"
           "  end_face_stress.csv   axial and radial stress vs r at the Gauss points nearest the "
           "top end\n"
           "                        face, at half the peak load\n"
           "  axis_stress.csv       the same vs z at the Gauss points nearest the axis\n"
           "  used_parameters.prm   the case as read\n"
           "Stresses compression-positive [MPa].\n"
           "\n"
           "options:\n"
           "  -o, --output OUTDIR   result folder; never replaced without --force\n"
           "  --interface I         bonded (no slip) or free-slip (frictionless); default "
           "free-slip, or\n"
           "                        bonded where Platens/Friction coefficient > 0\n"
           "  --platens P           rigid or elastic; default Platens/Model\n"
           "  --mesh N              elements across the specimen radius (square elements) [8]\n"
           "  --degree D            1 (bilinear) or 2 (biquadratic) quadrilaterals [2]\n"
           "  --increments N        load increments to the end strain [50]\n"
           "  --end-strain X        platen displacement / specimen length at the end [Loading/End "
           "strain]\n"
           "  --set \"S/K=value\"     override one case parameter (repeatable)\n"
           "  --force               replace an existing OUTDIR written by cosim\n"
           "  -q, --quiet           no closing line\n"
           "\n"
           "Exit status: 0 done, 2 bad input (one line on stderr, nothing written), 1 other "
           "failure.\n";
  }

  int reference_main(const std::vector<std::string> &args)
  {
    ReferenceCommandOptions o         = parse(args);
    const CaseFile case_file          = read_case_file(o.case_file, o.overrides);
    const coupling::CaseParameters &p = case_file.parameters;
    if (p.test != "UCS")
      throw InputError("cosim reference: " + diagnose::clip(o.case_file) +
                       ": Test/Type = " + p.test + "; the reference models the UCS cylinder only");
    if (!o.platens_given)
      o.reference.platens = p.platens.steel.model == fem::SteelModel::elastic
                              ? coupling::ReferencePlatens::elastic
                              : coupling::ReferencePlatens::rigid;
    if (!o.interface_given)
      o.reference.interface = p.platens.friction > 0 ? coupling::ReferenceInterface::bonded
                                                     : coupling::ReferenceInterface::free_slip;
    if (!o.end_strain_given)
      o.reference.end_strain = p.loading.end_strain;
    const std::string output =
      o.output.empty()
        ? (fs::path("results") / (fs::path(o.case_file).stem().string() + "-reference")).string()
        : o.output;
    const fs::path target = check_result_folder(output, o.force, {fs::path(o.case_file)});

    // what the case says that the reference does not model, said once
    std::vector<std::string> notes;
    if (p.rock.softening_strain > 0)
      notes.push_back("Rock/Softening strain = " + number(p.rock.softening_strain) +
                      " is not used: the reference rock is perfectly plastic");
    if (p.rock_case.strength_scatter > 0)
      notes.push_back("Rock/Strength scatter is not used: the reference rock is homogeneous");
    if (p.platens.friction > 0)
      notes.push_back("Platens/Friction coefficient = " + number(p.platens.friction) +
                      " is not modelled: the interface is bonded or free-slip");
    for (const auto &w : case_file.warnings)
      std::fprintf(stderr, "cosim: warning: %s\n", w.c_str());
    for (const auto &n : notes)
      std::fprintf(stderr, "cosim reference: note: %s\n", n.c_str());

    const coupling::ReferenceResult r = coupling::run_reference_cylinder(p, o.reference);

    using Json              = nlohmann::ordered_json;
    const bool plastic      = p.rock.model != sph::RockModel::elastic;
    const bool hoek_brown   = p.rock.model == sph::RockModel::hoek_brown;
    const bool mohr_coulomb = plastic && !hoek_brown;
    // the rock's uniaxial strength: Mohr-Coulomb's 2c cos(phi) / (1 - sin(phi)), Hoek-Brown's
    // sigma_ci s^a (a cut-off does not reach a compressive test)
    const double closed_form =
      hoek_brown ? p.rock.hb_sigma_ci * std::pow(p.rock.hb_s, p.rock.hb_a)
                 : coupling::mohr_coulomb_axial_strength(p.rock.cohesion,
                                                         p.rock.friction_angle * 180.0 / M_PI, 0.0);
    Json s;
    s["test"]   = "UCS";
    s["solver"] = "reference: implicit axisymmetric FE (deal.II), perfectly plastic rock";
    s["group"]  = p.rock_case.group;
    std::string rock_model = "mohr-coulomb";
    if (hoek_brown)
      rock_model = "hoek-brown";
    else if (!plastic)
      rock_model = "elastic";
    else if (p.rock.model == sph::RockModel::mohr_coulomb_cutoff)
      rock_model = "mohr-coulomb-cutoff";
    s["rock_model"] = rock_model;
    s["platens"] = o.reference.platens == coupling::ReferencePlatens::rigid ? "rigid" : "elastic";
    s["interface"] =
      o.reference.interface == coupling::ReferenceInterface::bonded ? "bonded" : "free-slip";
    s["mesh"]                           = o.reference.n_radial;
    s["degree"]                         = o.reference.degree;
    s["n_cells"]                        = r.n_cells;
    s["n_dofs"]                         = r.n_dofs;
    s["n_increments"]                   = r.curve.size() - 1;
    s["n_newton_iterations"]            = r.n_newton_iterations;
    s["n_cutbacks"]                     = r.n_cutbacks;
    s["end_strain"]                     = rounded(o.reference.end_strain);
    s["peak_stress_MPa"]                = rounded(r.peak_stress * 1e-6);
    s["peak_force_kN"]                  = rounded(r.peak_force * 1e-3);
    s["strain_at_peak"]                 = rounded(r.strain_at_peak);
    s["platen_displacement_at_peak_mm"] = rounded(r.displacement_at_peak * 1e3);
    s["half_peak_force_kN"]             = rounded(r.half_peak_force * 1e-3);
    s["mohr_coulomb_ucs_MPa"] = mohr_coulomb ? rounded(closed_form * 1e-6) : Json(nullptr);
    s["closed_form_ucs_MPa"]  = plastic ? rounded(closed_form * 1e-6) : Json(nullptr);
    s["platen_diameter_mm"]   = rounded(r.platen_diameter * 1e3);
    s["wall_seconds"]         = rounded(r.wall_seconds);
    s["end_reason"]           = r.end_reason;
    s["complete"]             = r.complete();
    s["notes"]                = notes;

    ResultFolder folder(target, "reference");
    const fs::path &out = folder.staging();
    write_text_file((out / "used_parameters.prm").string(), case_file.used_parameters);
    write_text_file((out / "summary.json").string(), s.dump(2) + "\n");
    write_text_file((out / "curve.csv").string(), curve_csv(r));
    write_text_file((out / "end_face_stress.csv").string(), profile_csv(r.end_face));
    write_text_file((out / "axis_stress.csv").string(), profile_csv(r.axis));
    const fs::path published = folder.publish(ResultStatus::complete, o.force);
    if (!r.complete())
      std::fprintf(
        stderr,
        "cosim reference: warning: %s; the curve ends there and its peak is a lower bound\n",
        r.end_reason.c_str());
    if (!o.quiet)
      std::fprintf(stderr,
                   "cosim reference: peak %.2f MPa (%s platens, %s, mesh %u, Q%u), %zu increments, "
                   "%.1f s -> %s\n",
                   r.peak_stress * 1e-6, s["platens"].get<std::string>().c_str(),
                   s["interface"].get<std::string>().c_str(), o.reference.n_radial,
                   o.reference.degree, r.curve.size() - 1, r.wall_seconds,
                   diagnose::clip(published.string()).c_str());
    return 0;
  }
} // namespace app
