// Readers of the measured-data folder of cosim diagnose (docs/design.md, Measured data). Every bad
// row throws an InputError naming the file and line, what was wrong and what is accepted.
#include <diagnose/csv.h>
#include <diagnose/diagnose.h>
#include <diagnose/text_input.h>
#include <coupling/run_case.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace diagnose
{
  using coupling::InputError;

  namespace
  {
    namespace fs = std::filesystem;

    std::vector<MaterialRow> read_material(const std::string &path)
    {
      const CsvTable t = CsvTable::read(path);
      t.require_columns({"group"});
      std::vector<MaterialRow> rows;
      const auto get = [&](std::size_t r, const char *col) -> std::optional<double> {
        return t.has_column(col) ? t.optional_number(r, col) : std::nullopt;
      };
      for (std::size_t r = 0; r < t.n_rows(); ++r)
      {
        MaterialRow m;
        m.group = t.text(r, "group");
        if (m.group.empty())
          throw InputError(t.where(r) + ": empty group; give a group name (e.g. M1)");
        for (const auto &o : rows)
          if (o.group == m.group)
            throw InputError(t.where(r) + ": group '" + clip(m.group) +
                             "' listed twice; one row per group");
        m.E_GPa             = get(r, "E_GPa");
        m.nu                = get(r, "nu");
        m.density           = get(r, "density_kg_m3");
        m.UCS_MPa           = get(r, "UCS_MPa");
        m.BTS_MPa           = get(r, "BTS_MPa");
        m.c_MPa             = get(r, "c_MPa");
        m.phi_deg           = get(r, "phi_deg");
        const auto positive = [&](const std::optional<double> &v, const char *col) {
          if (v && !(*v > 0))
            throw InputError(t.where(r) + ": " + col + " = " + std::to_string(*v) +
                             "; accepted: a positive number or an empty cell");
        };
        positive(m.E_GPa, "E_GPa");
        positive(m.density, "density_kg_m3");
        positive(m.UCS_MPa, "UCS_MPa");
        positive(m.BTS_MPa, "BTS_MPa");
        positive(m.c_MPa, "c_MPa");
        if (m.nu && !(*m.nu > -1 && *m.nu < 0.5))
          throw InputError(t.where(r) + ": nu = " + std::to_string(*m.nu) +
                           "; accepted: -1 < nu < 0.5 or an empty cell");
        if (m.phi_deg && !(*m.phi_deg > 0 && *m.phi_deg < 90))
          throw InputError(t.where(r) + ": phi_deg = " + std::to_string(*m.phi_deg) +
                           "; accepted: 0 < phi_deg < 90 or an empty cell");
        if (m.c_MPa.has_value() != m.phi_deg.has_value())
          throw InputError(t.where(r) +
                           ": c_MPa and phi_deg must be given together or both left empty");
        if (m.UCS_MPa && m.BTS_MPa && !(*m.BTS_MPa < *m.UCS_MPa))
          throw InputError(t.where(r) + ": BTS_MPa must be below UCS_MPa");
        rows.push_back(m);
      }
      return rows;
    }

    std::vector<StrengthRow> read_strength(const std::string &path)
    {
      const CsvTable t = CsvTable::read(path);
      t.require_columns({"test", "group", "sigma1_MPa", "sigma3_MPa"});
      std::vector<StrengthRow> rows;
      for (std::size_t r = 0; r < t.n_rows(); ++r)
      {
        StrengthRow s;
        s.where  = t.where(r);
        s.test   = t.text(r, "test");
        s.group  = t.text(r, "group");
        s.sigma1 = t.number(r, "sigma1_MPa");
        s.sigma3 = t.number(r, "sigma3_MPa");
        if (s.test != "UCS" && s.test != "BTS" && s.test != "CTCS" && s.test != "TXE")
          throw InputError(s.where + ": test '" + clip(s.test) + "'; accepted: UCS, BTS, CTCS, TXE");
        if (s.group.empty())
          throw InputError(s.where + ": empty group; give the material group (e.g. M1)");
        if (s.test == "BTS" && !(s.sigma1 == 0 && s.sigma3 < 0))
          throw InputError(s.where + ": a BTS row needs sigma1_MPa = 0 and sigma3_MPa = -BTS < 0");
        if (s.test == "UCS" && !(s.sigma3 == 0 && s.sigma1 > 0))
          throw InputError(s.where + ": a UCS row needs sigma3_MPa = 0 and sigma1_MPa > 0");
        // CTCS: sigma3 is the confining fluid's pressure, which cannot pull. TXE: the fluid's
        // pressure is sigma1 (= sigma2) and sigma3 the axial stress, which may be tensile
        // (extension under low confinement: tensile and hybrid tensile-shear fractures)
        if (s.test == "CTCS" && !(s.sigma3 >= 0 && s.sigma1 > s.sigma3))
          throw InputError(s.where + ": a CTCS row needs sigma3_MPa >= 0 (the confining pressure: "
                                     "a fluid cannot pull) and sigma1_MPa > sigma3_MPa");
        if (s.test == "TXE" && !(s.sigma1 >= 0 && s.sigma1 > s.sigma3))
          throw InputError(s.where + ": a TXE row needs sigma1_MPa >= 0 (the confining pressure: a "
                                     "fluid cannot pull) and sigma1_MPa > sigma3_MPa (sigma3, the "
                                     "axial stress, may be tensile)");
        rows.push_back(s);
      }
      return rows;
    }

    Curve read_curve(const std::string &path)
    {
      const CsvTable t = CsvTable::read(path);
      Curve c;
      c.file = path;
      const std::string shown = clip(path);
      std::map<std::string, std::string> keys;
      for (const auto &line : t.comments())
      {
        const auto colon = line.find(':');
        if (colon == std::string::npos)
          continue; // free comment
        keys[trim(line.substr(0, colon))] = trim(line.substr(colon + 1));
      }
      const auto key = [&](const std::string &k) -> std::string {
        const auto it = keys.find(k);
        if (it == keys.end())
          throw InputError(shown + ": header line '# " + k +
                           ": ...' missing (curves need test, group, "
                           "diameter_mm, length_mm or thickness_mm, displacement)");
        return it->second;
      };
      const auto number = [&](const std::string &k) {
        const auto v = parse_finite_double(key(k));
        if (!v || *v < 0)
          throw InputError(shown + ": header '" + k + ": " + clip(key(k)) +
                           "' is not a non-negative number");
        return *v;
      };
      c.test  = key("test");
      c.group = key("group");
      if (c.test != "UCS" && c.test != "CTCS" && c.test != "BTS")
        throw InputError(shown + ": header 'test: " + clip(c.test) + "'; accepted: UCS, CTCS, BTS");
      c.diameter          = number("diameter_mm");
      c.length            = keys.count("length_mm") ? number("length_mm") : number("thickness_mm");
      c.confining         = keys.count("confining_MPa") ? number("confining_MPa") : 0.0;
      const std::string d = key("displacement");
      if (d != "platen" && d != "specimen")
        throw InputError(shown + ": header 'displacement: " + clip(d) + "'; accepted: platen, specimen");
      c.platen_displacement = d == "platen";
      if (keys.count("failure"))
      {
        const std::string f = keys.at("failure");
        if (f != "yes" && f != "no")
          throw InputError(shown + ": header 'failure: " + clip(f) +
                           "'; accepted: yes (loaded to failure, the default), no (a curve only)");
        c.failed = f == "yes";
      }
      if (!(c.diameter > 0 && c.length > 0))
        throw InputError(shown + ": diameter and length/thickness must be positive");
      t.require_columns({"time_s", "displacement_mm", "force_kN"});
      for (std::size_t r = 0; r < t.n_rows(); ++r)
      {
        const double ti = t.number(r, "time_s"), di = t.number(r, "displacement_mm"),
                     fi = t.number(r, "force_kN");
        if (!c.time.empty() && !(ti > c.time.back()))
          throw InputError(t.where(r) + ": time_s must increase row by row");
        c.time.push_back(ti);
        c.displacement.push_back(di);
        c.force.push_back(fi);
      }
      // fewer than 5 rows: the peak only; a curve without failure is its points, so needs them
      if (c.time.empty())
        throw InputError(shown + ": no rows; give at least the peak row (time_s,displacement_mm,force_kN)");
      if (!c.failed && c.peak_only())
        throw InputError(shown + ": a curve without failure ('failure: no') needs at least 5 rows; "
                                 "it has no peak, so its points are all it gives");
      // a load frame records compression as a positive force; a curve that never loads, or
      // loads the wrong way, cannot be fitted (only tare noise may dip below zero)
      double peak = 0;
      for (const double f : c.force)
        peak = std::max(peak, f);
      if (!(peak > 0))
        throw InputError(shown + ": force_kN is never positive (peak " + std::to_string(peak) +
                         " kN); give the compressive load as a positive force");
      for (std::size_t r = 0; r < t.n_rows(); ++r)
        if (c.force[r] < -0.05 * peak)
          throw InputError(t.where(r) + ": force_kN = " + clip(t.text(r, "force_kN")) +
                           " is negative beyond tare noise (5 % of the peak " + std::to_string(peak) +
                           " kN); give the compressive load as a positive force");
      for (std::size_t r = 0; r < t.n_rows(); ++r)
        if (!(c.force[r] < 1e6 && c.displacement[r] > -1e3 && c.displacement[r] < 1e3))
          throw InputError(t.where(r) + ": force_kN or displacement_mm out of range (|F| < 1e6 kN, |d| < 1000 mm)");
      return c;
    }
  } // namespace

  Data read_data(const std::string &folder)
  {
    if (!fs::is_directory(folder))
      throw InputError(clip(folder) + ": not a folder; give the measured-data folder (docs/design.md)");
    Data data;
    const fs::path root(folder);
    if (fs::exists(root / "material.csv"))
      data.materials = read_material((root / "material.csv").string());
    if (fs::exists(root / "strength.csv"))
      data.strengths = read_strength((root / "strength.csv").string());
    if (fs::is_directory(root / "curves"))
    {
      std::vector<std::string> files;
      for (const auto &e : fs::directory_iterator(root / "curves"))
        if (e.is_regular_file() && e.path().extension() == ".csv")
          files.push_back(e.path().string());
      std::sort(files.begin(), files.end());
      for (const auto &f : files)
        data.curves.push_back(read_curve(f));
    }
    if (data.materials.empty() && data.strengths.empty() && data.curves.empty())
      throw InputError(clip(folder) + ": no material.csv, strength.csv or curves/*.csv with rows");
    return data;
  }
} // namespace diagnose
