#include <diagnose/csv.h>
#include <diagnose/material_table.h>

#include <cmath>
#include <diagnose/text_input.h>
#include <coupling/run_case.h>

#include <filesystem>

namespace diagnose
{
  using coupling::InputError;

  namespace
  {
    void check(bool ok, const CsvTable &t, std::size_t row, const std::string &what)
    {
      if (!ok)
        throw InputError(t.where(row) + ": " + what);
    }
  } // namespace

  MaterialTable MaterialTable::read(const std::string &directory)
  {
    namespace fs = std::filesystem;
    if (!fs::is_directory(directory))
      throw InputError(clip(directory) + ": no such data folder; Rock/Data directory must name a folder "
                                   "with table3_fitted_parameters.csv (default cases/data)");
    MaterialTable table;
    const CsvTable t3 = CsvTable::read(directory + "/table3_fitted_parameters.csv");
    t3.require_columns({"group", "E_GPa", "nu", "c_MPa", "phi_deg", "UCS_MPa", "BTS_MPa"});
    for (std::size_t r = 0; r < t3.n_rows(); ++r)
    {
      MaterialGroup g;
      g.group = t3.text(r, "group");
      g.source = t3.where(r);
      check(!g.group.empty(), t3, r, "empty group name; every row needs one (e.g. M1)");
      check(table.lookup(g.group) == nullptr, t3, r, "group " + clip(g.group) + " appears twice; group names must be unique");
      const double e = t3.number(r, "E_GPa");
      // plausible rock (and steel) values: a value the case file later refuses is blamed here,
      // on the table's line, not on the case file that named the group
      check(e > 0 && e <= 1000, t3, r, "E_GPa = " + clip(t3.text(r, "E_GPa")) + " must be in (0, 1000]");
      g.youngs_modulus = e * 1e9;
      g.poissons_ratio = t3.number(r, "nu");
      check(g.poissons_ratio >= 0 && g.poissons_ratio < 0.5, t3, r,
            "nu = " + clip(t3.text(r, "nu")) + " must be in [0, 0.5)");
      const double ucs = t3.number(r, "UCS_MPa"), bts = t3.number(r, "BTS_MPa");
      check(bts > 0 && ucs > bts && ucs <= 1e4, t3, r,
            "UCS_MPa = " + clip(t3.text(r, "UCS_MPa")) + ", BTS_MPa = " + clip(t3.text(r, "BTS_MPa")) +
              ": need 0 < BTS < UCS <= 10000");
      g.ucs = ucs * 1e6;
      g.bts = bts * 1e6;
      const auto c = t3.optional_number(r, "c_MPa");
      const auto phi = t3.optional_number(r, "phi_deg");
      check(c.has_value() == phi.has_value(), t3, r, "give both c_MPa and phi_deg or leave both empty");
      if (c)
      {
        check(*c > 0 && *c <= 1e4, t3, r, "c_MPa = " + clip(t3.text(r, "c_MPa")) + " must be in (0, 10000]");
        check(*phi > 0 && *phi < 90, t3, r, "phi_deg = " + clip(t3.text(r, "phi_deg")) + " must be in (0, 90)");
        g.measured_cohesion = *c * 1e6;
        g.measured_friction_angle = *phi;
      }
      table.groups_.push_back(g);
    }
    if (table.groups_.empty())
      throw InputError(t3.file() + ": no data rows; expected one row per material group");

    table.read_c_phi(directory + "/table4_calibrated.csv", &MaterialGroup::calibrated_cohesion,
                     &MaterialGroup::calibrated_friction_angle);
    table.read_c_phi(directory + "/simulator_calibrated.csv", &MaterialGroup::simulated_cohesion,
                     &MaterialGroup::simulated_friction_angle, &MaterialGroup::simulated_cutoff,
                     &MaterialGroup::simulated_mb);
    return table;
  }

  void MaterialTable::read_c_phi(const std::string &path, std::optional<double> MaterialGroup::*cohesion,
                                 std::optional<double> MaterialGroup::*friction_angle,
                                 std::optional<double> MaterialGroup::*cutoff,
                                 std::optional<double> MaterialGroup::*mb)
  {
    if (!std::filesystem::exists(path))
      return;
    const CsvTable t = CsvTable::read(path);
    t.require_columns({"group", "c_MPa", "phi_deg"});
    for (std::size_t r = 0; r < t.n_rows(); ++r)
    {
      const std::string name = t.text(r, "group");
      MaterialGroup *g = nullptr;
      for (auto &candidate : groups_)
        if (candidate.group == name)
          g = &candidate;
      check(g != nullptr, t, r, "group '" + clip(name) + "' is not in table3_fitted_parameters.csv (" +
                                  group_names() + ")");
      check(!(g->*cohesion), t, r, "group " + name + " appears twice");
      const double c = t.number(r, "c_MPa"), phi = t.number(r, "phi_deg");
      check(c > 0 && c <= 1e4, t, r, "c_MPa = " + clip(t.text(r, "c_MPa")) + " must be in (0, 10000]");
      check(phi > 0 && phi < 90, t, r, "phi_deg = " + clip(t.text(r, "phi_deg")) + " must be in (0, 90)");
      g->*cohesion       = c * 1e6;
      g->*friction_angle = phi;
      if (cutoff && t.has_column("cutoff_MPa"))
        if (const auto f = t.optional_number(r, "cutoff_MPa"))
        {
          check(*f > 0 && *f * 1e6 < g->ucs, t, r,
                "cutoff_MPa = " + clip(t.text(r, "cutoff_MPa")) + " must be in (0, UCS of the group)");
          g->*cutoff = *f * 1e6;
        }
      if (mb && t.has_column("mb"))
        if (const auto m = t.optional_number(r, "mb"))
        {
          check(*m > 0 && *m <= 1000, t, r, "mb = " + clip(t.text(r, "mb")) + " must be in (0, 1000]");
          g->*mb = *m;
        }
    }
  }

  const MaterialGroup *MaterialTable::lookup(const std::string &name) const
  {
    for (const auto &g : groups_)
      if (g.group == name)
        return &g;
    return nullptr;
  }

  const MaterialGroup &MaterialTable::find(const std::string &name) const
  {
    if (const auto *g = lookup(name))
      return *g;
    throw InputError("unknown rock group '" + clip(name) + "'; known groups: " + group_names());
  }

  std::string MaterialTable::group_names() const
  {
    std::string out;
    for (const auto &g : groups_)
      out += (out.empty() ? "" : ", ") + g.group;
    return out;
  }

  std::string MaterialTable::groups_with_measured_strength() const
  {
    std::string out;
    for (const auto &g : groups_)
      if (g.measured_cohesion)
        out += (out.empty() ? "" : ", ") + g.group;
    return out.empty() ? "none" : out;
  }

  std::vector<TriaxialStrength> triaxial_strengths(const MaterialGroup &group)
  {
    std::vector<TriaxialStrength> t;
    if (!group.measured_cohesion || !group.measured_friction_angle)
      return t;
    const double phi = *group.measured_friction_angle * 3.14159265358979323846 / 180.0;
    const double N   = (1 + std::sin(phi)) / (1 - std::sin(phi));
    for (const double s3 : {10e6, 30e6, 50e6})
      t.push_back({s3, 2 * *group.measured_cohesion * std::sqrt(N) + N * s3});
    return t;
  }
} // namespace diagnose
