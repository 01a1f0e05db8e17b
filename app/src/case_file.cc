// The only translation unit of the app that includes deal.II (ParameterHandler): keep it so.
#include <diagnose/calibrate.h>
#include <app/case_file.h>
#include <app/paths.h>
#include <app/cli.h>
#include <diagnose/csv.h>
#include <diagnose/material_table.h>
#include <coupling/run_case.h>

#include <deal.II/base/parameter_handler.h>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace app
{
  using diagnose::calibrate_mohr_coulomb_brazilian;
  using diagnose::parse_finite_double;
  using diagnose::trim;
  using diagnose::MohrCoulombStrength;
  using diagnose::MaterialGroup;
  using diagnose::MaterialTable;
  using coupling::InputError;
  using coupling::CaseParameters;
  using coupling::RockParameters;
  using coupling::PlatenParameters;
  using coupling::LoadingParameters;
  using coupling::CutterParameters;

  namespace
  {
    enum class Kind
    {
      real,          ///< a finite number
      optional_real, ///< a finite number, or empty for "from Rock/Group"
      integer,
      boolean,
      selection, ///< one of `choices` ("a|b|c")
      text
    };

    struct Key
    {
      const char *section;
      const char *name;
      Kind kind;
      const char *default_value;
      const char *choices;
      const char *doc;

      std::string full() const { return std::string(section) + "/" + name; }
    };

    // Every key of CaseParameters. Units SI; angles in degrees.
    const Key keys[] = {
      {"Test", "Type", Kind::selection, "UCS", "UCS|BTS|CTCS|indentation|linear-cutting",
       "UCS (cylinder), BTS (disc), CTCS (confined cylinder), indentation, linear-cutting (rock block, Cutter section)"},
      {"Test", "Name", Kind::text, "", "", "case name; empty = the case file's stem"},
      {"Test", "Diameter", Kind::real, "0.05", "", "specimen diameter [m]"},
      {"Test", "Length", Kind::real, "0.1", "", "UCS/CTCS specimen length, BTS disc thickness [m]"},
      {"Test", "Confining pressure", Kind::real, "0", "", "CTCS lateral pressure [Pa], compression positive"},

      {"Rock", "Group", Kind::text, "M1", "", "material group looked up in the data folder (M1..M10)"},
      {"Rock", "Model", Kind::selection, "mohr-coulomb", "elastic|mohr-coulomb|mohr-coulomb-cutoff|hoek-brown",
       "constitutive model of the rock"},
      {"Rock", "Strength parameters", Kind::selection, "calibrated", "calibrated|measured|brazilian",
       "c, phi from Table 4 (calibrated to UCS and BTS), Table 3 (measured by CTCS, groups M8-M10) or brazilian (calibrated to UCS and to BTS at the disc centre's stress state, cosim calibrate --brazilian)"},
      {"Rock", "Data directory", Kind::text, "", "",
       "folder with table3_fitted_parameters.csv, table4_calibrated.csv; empty = cases/data"},
      {"Rock", "Density", Kind::real, "2900", "", "[kg/m^3] (not in the paper: a typical basalt value)"},
      {"Rock", "Youngs modulus", Kind::optional_real, "", "", "[Pa]; empty = from Rock/Group"},
      {"Rock", "Poissons ratio", Kind::optional_real, "", "", "[-]; empty = from Rock/Group"},
      {"Rock", "Cohesion", Kind::optional_real, "", "", "[Pa]; empty = from Rock/Group"},
      {"Rock", "Friction angle", Kind::optional_real, "", "", "[deg]; empty = from Rock/Group"},
      {"Rock", "Dilation angle", Kind::real, "0", "", "[deg], at most the friction angle"},
      {"Rock", "Tensile strength", Kind::optional_real, "", "",
       "tension cut-off [Pa]; empty = the group's BTS for mohr-coulomb-cutoff, else none"},
      {"Rock", "Hoek-Brown mi", Kind::real, "25", "", "Hoek-Brown m_i [-] (basalt about 25)"},
      {"Rock", "UCS", Kind::optional_real, "", "", "uniaxial strength sigma_ci [Pa]; empty = from Rock/Group"},
      {"Rock", "Softening strain", Kind::real, "0.002", "", "plastic strain to residual strength [-]"},
      {"Rock", "Residual fraction", Kind::real, "0.1", "", "residual / peak strength [-]"},
      {"Rock", "Residual friction angle", Kind::optional_real, "", "",
       "[deg] friction angle of fully damaged (crushed) rock, reached with the residual strength; empty = the friction angle throughout (mohr-coulomb models)"},
      {"Rock", "Strength scatter", Kind::real, "0", "",
       "Weibull modulus m of a per-particle strength factor (mean 1) on c, tensile strength and Hoek-Brown s; 0 = homogeneous rock, else >= 1 (rock: about 5-20)"},
      {"Rock", "Scatter seed", Kind::integer, "1", "", "seed of the strength scatter: the same seed, the same rock"},

      {"SPH", "Particle spacing", Kind::real, "0.0025", "", "lattice spacing dx [m]"},
      {"SPH", "FORM", Kind::selection, "8", "0|1|7|8",
       "LS-DYNA formulation: 0/1 updated Lagrangian without/with gradient correction, 7/8 total Lagrangian"},
      {"SPH", "CSLH", Kind::real, "1.2", "", "smoothing length h = CSLH dx [-]"},
      {"SPH", "TSSFAC", Kind::real, "0.9", "", "time-step scale factor [-]"},
      {"SPH", "Kernel", Kind::selection, "cubic", "cubic|wendland", "smoothing kernel"},
      {"SPH", "Evolve smoothing length", Kind::boolean, "false", "", "dh/dt = (h/d) div v"},
      {"SPH", "Viscosity alpha", Kind::real, "1.0", "", "Monaghan artificial viscosity, linear [-]"},
      {"SPH", "Viscosity beta", Kind::real, "1.0", "", "Monaghan artificial viscosity, quadratic [-]"},
      {"SPH", "Hourglass coefficient", Kind::real, "0.1", "", "total-Lagrangian hourglass control [-]"},
      {"SPH", "Loaded face correction", Kind::boolean, "true", "",
       "UCS/CTCS: move the symmetric force's boundary term onto the layer the platen loads"},
      {"SPH", "Threads", Kind::integer, "0", "", "threads of the run (SPH and coupling loops); 0 = all cores"},
      {"SPH", "Pair force precision", Kind::selection, "mixed", "mixed|double",
       "3-D pair force on AVX2: float terms with double differences and sums (mixed) or all double"},

      {"Platens", "Model", Kind::selection, "rigid", "rigid|elastic", "rigid (prescribed) or elastic steel (FEM)"},
      {"Platens", "Friction coefficient", Kind::real, "0", "", "Coulomb friction rock-platen [-]"},
      {"Platens", "Youngs modulus", Kind::real, "200e9", "", "[Pa]"},
      {"Platens", "Poissons ratio", Kind::real, "0.3", "", "[-]"},
      {"Platens", "Density", Kind::real, "7850", "", "[kg/m^3]"},
      {"Platens", "Thickness", Kind::real, "0.02", "", "along the loading axis [m]"},
      {"Platens", "Diameter", Kind::real, "0", "", "diameter (UCS/CTCS) or width (BTS) [m]; 0 = from the specimen"},
      {"Platens", "Element size", Kind::real, "0", "", "FEM element size [m]; 0 = from the particle spacing"},
      {"Platens", "Contact stiffness scale", Kind::real, "0.1", "", "penalty stiffness / its stability bound at the rock step [-]; the step shrinks by sqrt(1 + s); 0.5 for stress waves"},
      {"Platens", "Shape", Kind::selection, "flat", "flat|jaw",
       "BTS: flat platens or ISRM curved loading jaws (UCS/CTCS: flat only)"},
      {"Platens", "Jaw radius", Kind::real, "0", "", "BTS jaw: radius of the contact arc [m]; 0 = 1.5 x disc radius (ISRM)"},

      {"Loading", "Strain rate", Kind::real, "0", "", "nominal axial strain rate [1/s]; 0 = from the wave transit time"},
      {"Loading", "Transit times", Kind::real, "40", "", "derived rate: ramp to peak over this many wave transits [-]"},
      {"Loading", "End strain", Kind::real, "0.01", "", "stop at this nominal strain [-] (BTS: displacement / D)"},
      {"Loading", "Post-peak drop", Kind::real, "0.2", "", "stop when the load fell this fraction below its peak [-]"},
      {"Loading", "Max kinetic ratio", Kind::real, "0.01", "", "quasi-static limit, kinetic / internal energy [-]"},
      {"Loading", "Max force imbalance", Kind::real, "0.05", "", "quasi-static limit, |F_top - F_bottom| / F [-]"},

      {"Cutter", "Shape", Kind::selection, "disc", "wedge|cone|flat|disc",
       "indentation: wedge, cone or flat (cylindrical punch); linear-cutting: disc (CCS disc cutter)"},
      {"Cutter", "Tip angle", Kind::real, "90", "", "wedge / cone included angle [deg]"},
      {"Cutter", "Tip radius", Kind::real, "0", "", "wedge / cone tip rounding radius [m]; 0 = sharp"},
      {"Cutter", "Indenter width", Kind::real, "0.02", "", "wedge width across its tip, cone / punch diameter [m]"},
      {"Cutter", "Wedge length", Kind::real, "0.02", "", "wedge tip length along y [m]"},
      {"Cutter", "Disc diameter", Kind::real, "0.4318", "", "disc cutter diameter [m] (17 inch: 0.4318)"},
      {"Cutter", "Tip width", Kind::real, "0.0127", "", "CCS disc tip width [m]"},
      {"Cutter", "Penetration", Kind::real, "0.005", "", "depth of cut (linear-cutting) or final depth (indentation) [m]"},
      {"Cutter", "Line spacing", Kind::real, "0.075", "", "spacing between cuts [m], for the CSM estimate (one pass is cut)"},
      {"Cutter", "Speed", Kind::real, "4", "", "cutting speed along x, indentation speed along -z [m/s]"},
      {"Cutter", "Cut length", Kind::real, "0.08", "", "distance cut along x [m]"},
      {"Cutter", "Block length", Kind::real, "0.15", "", "rock block along the cut (x) [m]"},
      {"Cutter", "Block width", Kind::real, "0.1", "", "rock block across the cut (y) [m]"},
      {"Cutter", "Block height", Kind::real, "0.05", "", "rock block depth (z) [m]"},

      {"Output", "History rows", Kind::integer, "400", "", "about this many rows in history.csv"},
      {"Output", "Snapshots", Kind::integer, "20", "", "particle / mesh snapshots in results.h5"},
      {"Output", "Progress", Kind::boolean, "true", "", "progress display on stderr (also --quiet)"},
      {"Output", "Checkpoint interval", Kind::integer, "0", "", "write checkpoint.h5 every this many steps; 0 = not by steps"},
      {"Output", "Checkpoint minutes", Kind::real, "0", "", "write checkpoint.h5 every this many minutes of wall time; 0 = not by time"},
      {"Output", "Stop after steps", Kind::integer, "0", "", "stop with a checkpoint after this step, as on SIGTERM (restart tests); 0 = never"},
    };

    const Key *find_key(const std::string &section, const std::string &name)
    {
      for (const auto &k : keys)
        if (section == k.section && name == k.name)
          return &k;
      return nullptr;
    }

    std::vector<std::string> section_names()
    {
      std::vector<std::string> out;
      for (const auto &k : keys)
        if (out.empty() || out.back() != k.section)
          out.push_back(k.section);
      return out;
    }

    std::vector<std::string> key_names(const std::string &section)
    {
      std::vector<std::string> out;
      for (const auto &k : keys)
        if (section == k.section)
          out.push_back(k.name);
      return out;
    }

    std::vector<std::string> full_names()
    {
      std::vector<std::string> out;
      for (const auto &k : keys)
        out.push_back(k.full());
      return out;
    }

    std::string join(const std::vector<std::string> &items, const std::string &separator)
    {
      std::string out;
      for (const auto &i : items)
        out += (out.empty() ? "" : separator) + i;
      return out;
    }

    std::string accepted(const Key &k)
    {
      switch (k.kind)
      {
        case Kind::real:
          return "a finite number";
        case Kind::optional_real:
          return "a finite number, or empty for the value of Rock/Group";
        case Kind::integer:
          return "an integer";
        case Kind::boolean:
          return "true or false";
        case Kind::selection:
        {
          std::string c = k.choices;
          for (auto &ch : c)
            if (ch == '|')
              ch = ',';
          std::string out;
          std::stringstream ss(c);
          std::string item;
          while (std::getline(ss, item, ','))
            out += (out.empty() ? "" : ", ") + item;
          return "one of " + out;
        }
        case Kind::text:
          return "any text";
      }
      return {};
    }

    bool value_matches(const Key &k, const std::string &value)
    {
      switch (k.kind)
      {
        case Kind::real:
          return parse_finite_double(value).has_value();
        case Kind::optional_real:
          return value.empty() || parse_finite_double(value).has_value();
        case Kind::integer:
        {
          if (value.empty())
            return false;
          char *end = nullptr;
          const long v = std::strtol(value.c_str(), &end, 10);
          return end == value.c_str() + value.size() && v > -1000000000L && v < 1000000000L;
        }
        case Kind::boolean:
          return value == "true" || value == "false";
        case Kind::selection:
        {
          std::stringstream ss(k.choices);
          std::string item;
          while (std::getline(ss, item, '|'))
            if (item == value)
              return true;
          return false;
        }
        case Kind::text:
          return true;
      }
      return false;
    }

    /// Where each key got its value, for messages: "case.prm:12", "--set \"A/B=c\"" or "".
    using Origins = std::map<std::string, std::string>;

    struct Assignment
    {
      const Key *key;
      std::string value;
      std::string origin;
    };

    /// Removes a deal.II-style comment (a '#' not preceded by a backslash).
    std::string strip_comment(const std::string &line)
    {
      for (std::size_t i = 0; i < line.size(); ++i)
        if (line[i] == '#' && (i == 0 || line[i - 1] != '\\'))
          return line.substr(0, i);
      return line;
    }

    void check_value(const Key &k, const std::string &value, const std::string &origin)
    {
      if (!value_matches(k, value))
        throw InputError(origin + ": " + k.full() + " = '" + value + "' is not " + accepted(k) +
                         (k.kind == Kind::selection ? "" : " (" + std::string(k.doc) + ")"));
    }

    /// Reads the case file line by line and checks every section, key and value before deal.II
    /// parses it, so each message can name the line and suggest a valid name.
    std::vector<Assignment> scan_case_file(const std::string &path)
    {
      std::ifstream in(path);
      if (!in)
        throw InputError(path + ": cannot open the case file (" +
                         (std::filesystem::exists(path) ? "not readable" : "no such file") +
                         "); give the path of a .prm file such as cases/ucs/ucs.prm");
      std::vector<Assignment> out;
      std::vector<std::pair<std::string, std::size_t>> sections; // name, line opened
      std::string raw, line;
      std::size_t n = 0;
      while (std::getline(in, raw))
      {
        ++n;
        const std::size_t line_number = n;
        line = strip_comment(raw);
        // continuation lines
        while (!trim(line).empty() && trim(line).back() == '\\' && std::getline(in, raw))
        {
          ++n;
          line = trim(line);
          line.pop_back();
          line += " " + strip_comment(raw);
        }
        line = trim(line);
        const std::string where = path + ":" + std::to_string(line_number);
        if (line.empty())
          continue;
        const auto space = line.find_first_of(" \t");
        const std::string word = line.substr(0, space);
        const std::string rest = space == std::string::npos ? "" : trim(line.substr(space));
        if (word == "subsection")
        {
          if (!sections.empty())
            throw InputError(where + ": unknown section '" + sections.back().first + "/" + rest +
                             "'; sections do not nest; accepted sections: " + join(section_names(), ", "));
          bool known = false;
          for (const auto &s : section_names())
            known = known || s == rest;
          if (!known)
            throw InputError(where + ": unknown section '" + rest + "'" + did_you_mean(rest, section_names()) +
                             "; accepted sections: " + join(section_names(), ", "));
          sections.emplace_back(rest, line_number);
        }
        else if (word == "end")
        {
          if (!rest.empty())
            throw InputError(where + ": 'end' takes nothing after it (found '" + rest + "')");
          if (sections.empty())
            throw InputError(where + ": 'end' without an open subsection");
          sections.pop_back();
        }
        else if (word == "set")
        {
          const auto eq = rest.find('=');
          if (eq == std::string::npos)
            throw InputError(where + ": '" + line + "' has no '='; write 'set Key = value'");
          const std::string name = trim(rest.substr(0, eq));
          const std::string value = trim(rest.substr(eq + 1));
          if (sections.empty())
          {
            std::vector<std::string> homes;
            for (const auto &k : keys)
              if (name == k.name)
                homes.push_back(k.section);
            throw InputError(where + ": 'set " + name + "' outside a subsection; " +
                             (homes.empty() ? "every key belongs to one of the sections " + join(section_names(), ", ")
                                            : "it belongs in subsection " + join(homes, " or ")));
          }
          const std::string &section = sections.back().first;
          const Key *k = find_key(section, name);
          if (k == nullptr)
            throw InputError(where + ": unknown key '" + name + "' in section " + section +
                             did_you_mean(name, key_names(section)) + "; accepted keys in " + section + ": " +
                             join(key_names(section), ", "));
          check_value(*k, value, where);
          out.push_back({k, value, where});
        }
        else if (word == "include")
          throw InputError(where + ": 'include' is not supported in case files; use one file, or --set");
        else
          throw InputError(where + ": cannot read '" + line +
                           "'; expected 'subsection Name', 'set Key = value', 'end' or a # comment");
      }
      if (!sections.empty())
        throw InputError(path + ":" + std::to_string(sections.back().second) + ": subsection '" +
                         sections.back().first + "' is not closed with 'end'");
      return out;
    }

    Assignment parse_override(const std::string &text)
    {
      const std::string origin = "--set \"" + text + "\"";
      const auto eq = text.find('=');
      const auto slash = text.find('/');
      if (eq == std::string::npos || slash == std::string::npos || slash > eq)
        throw InputError(origin + ": expected \"Section/Key=value\", e.g. --set \"SPH/Particle spacing=0.002\"");
      const std::string section = trim(text.substr(0, slash));
      const std::string name = trim(text.substr(slash + 1, eq - slash - 1));
      const std::string value = trim(text.substr(eq + 1));
      bool known_section = false;
      for (const auto &s : section_names())
        known_section = known_section || s == section;
      if (!known_section)
        throw InputError(origin + ": unknown section '" + section + "'" +
                         did_you_mean(section + "/" + name, full_names()) + "; accepted sections: " +
                         join(section_names(), ", "));
      const Key *k = find_key(section, name);
      if (k == nullptr)
        throw InputError(origin + ": unknown key '" + name + "' in section " + section +
                         did_you_mean(name, key_names(section)) + "; accepted keys in " + section + ": " +
                         join(key_names(section), ", "));
      check_value(*k, value, origin);
      return {k, value, origin};
    }

    void declare(dealii::ParameterHandler &prm)
    {
      for (const auto &section : section_names())
      {
        prm.enter_subsection(section);
        for (const auto &k : keys)
        {
          if (section != k.section)
            continue;
          std::unique_ptr<dealii::Patterns::PatternBase> pattern;
          switch (k.kind)
          {
            case Kind::real:
              pattern = std::make_unique<dealii::Patterns::Double>();
              break;
            case Kind::integer:
              pattern = std::make_unique<dealii::Patterns::Integer>();
              break;
            case Kind::boolean:
              pattern = std::make_unique<dealii::Patterns::Bool>();
              break;
            case Kind::selection:
              pattern = std::make_unique<dealii::Patterns::Selection>(k.choices);
              break;
            case Kind::optional_real:
            case Kind::text:
              pattern = std::make_unique<dealii::Patterns::Anything>();
              break;
          }
          prm.declare_entry(k.name, k.default_value, *pattern, k.doc);
        }
        prm.leave_subsection();
      }
    }

    /// One line out of a deal.II exception text.
    std::string one_line(const std::string &text)
    {
      std::string out;
      bool blank = false;
      for (const char ch : text)
      {
        const bool space = ch == '\n' || ch == '\r' || ch == '\t' || ch == ' ';
        if (space && !blank && !out.empty())
          out += ' ';
        else if (!space)
          out += ch;
        blank = space;
      }
      return trim(out);
    }

    /// Reads the values back out of the ParameterHandler and checks them.
    class Reader
    {
    public:
      Reader(dealii::ParameterHandler &prm, const Origins &origins, const std::string &case_path)
        : prm_(prm)
        , origins_(origins)
        , case_path_(case_path)
      {}

      std::string get(const std::string &full) const
      {
        const auto slash = full.find('/');
        prm_.enter_subsection(full.substr(0, slash));
        const std::string v = prm_.get(full.substr(slash + 1));
        prm_.leave_subsection();
        return v;
      }

      void set(const std::string &full, const std::string &value)
      {
        const auto slash = full.find('/');
        prm_.enter_subsection(full.substr(0, slash));
        prm_.set(full.substr(slash + 1), value);
        prm_.leave_subsection();
      }

      double real(const std::string &full) const { return *parse_finite_double(get(full)); }
      std::optional<double> optional(const std::string &full) const { return parse_finite_double(get(full)); }
      int integer(const std::string &full) const { return std::atoi(get(full).c_str()); }
      bool boolean(const std::string &full) const { return get(full) == "true"; }

      /// "file:line" or "--set ..." of a key; the case file when it kept its default.
      std::string origin(const std::string &full) const
      {
        const auto it = origins_.find(full);
        return it == origins_.end() ? case_path_ + ": (default)" : it->second;
      }
      bool was_set(const std::string &full) const { return origins_.count(full) > 0; }

      [[noreturn]] void fail(const std::string &full, const std::string &what) const
      {
        throw InputError(origin(full) + ": " + full + " = " + shown(full) + ": " + what);
      }

      void require(bool ok, const std::string &full, const std::string &what) const
      {
        if (!ok)
          fail(full, what);
      }

      std::string shown(const std::string &full) const
      {
        const std::string v = get(full);
        return v.empty() ? "''" : v;
      }

    private:
      dealii::ParameterHandler &prm_;
      const Origins &origins_;
      std::string case_path_;
    };

    /// The shortest text that reads back as the same double: used_parameters.prm repeats a run
    /// (and a --restart continues it) bit for bit.
    std::string format(double v)
    {
      char buffer[64];
      const auto r = std::to_chars(buffer, buffer + sizeof buffer, v);
      return std::string(buffer, r.ptr);
    }

    std::string mm(double v) { return format(v * 1e3) + " mm"; }

    /// The Cutter section of an indentation / linear-cutting case, validated; warns about keys of
    /// the laboratory tests that these tests do not use.
    void read_cutter(const Reader &r, CaseParameters &p, std::vector<std::string> &warnings)
    {
      CutterParameters &c = p.cutter;
      c.shape = r.get("Cutter/Shape");
      c.tip_angle = r.real("Cutter/Tip angle");
      c.tip_radius = r.real("Cutter/Tip radius");
      r.require(c.tip_radius >= 0 && c.tip_radius <= 0.1, "Cutter/Tip radius", "must be in [0, 0.1] m");
      c.indenter_width = r.real("Cutter/Indenter width");
      c.wedge_length = r.real("Cutter/Wedge length");
      c.disc_diameter = r.real("Cutter/Disc diameter");
      c.tip_width = r.real("Cutter/Tip width");
      c.penetration = r.real("Cutter/Penetration");
      c.line_spacing = r.real("Cutter/Line spacing");
      c.speed = r.real("Cutter/Speed");
      c.cut_length = r.real("Cutter/Cut length");
      c.block_length = r.real("Cutter/Block length");
      c.block_width = r.real("Cutter/Block width");
      c.block_height = r.real("Cutter/Block height");
      const bool cutting = p.test == "linear-cutting";
      if (cutting)
        r.require(c.shape == "disc", "Cutter/Shape", "linear-cutting rolls a disc cutter: set it to disc");
      else
        r.require(c.shape != "disc", "Cutter/Shape", "indentation presses a wedge, cone or flat punch: set one of them");
      r.require(c.tip_angle >= 30 && c.tip_angle <= 170, "Cutter/Tip angle", "must be in [30, 170] degrees");
      r.require(c.indenter_width > 0 && c.indenter_width <= 1, "Cutter/Indenter width", "must be in (0, 1] m");
      r.require(c.wedge_length > 0 && c.wedge_length <= 1, "Cutter/Wedge length", "must be in (0, 1] m");
      r.require(c.disc_diameter > 0.02 && c.disc_diameter <= 1, "Cutter/Disc diameter", "must be in (0.02, 1] m");
      r.require(c.tip_width > 0 && c.tip_width <= 0.1, "Cutter/Tip width", "must be in (0, 0.1] m");
      r.require(c.line_spacing > 0 && c.line_spacing <= 1, "Cutter/Line spacing", "must be in (0, 1] m");
      r.require(c.speed > 0 && c.speed <= 100, "Cutter/Speed", "must be in (0, 100] m/s");
      r.require(c.block_length > 0 && c.block_length <= 2, "Cutter/Block length", "must be in (0, 2] m");
      r.require(c.block_width > 0 && c.block_width <= 2, "Cutter/Block width", "must be in (0, 2] m");
      r.require(c.block_height > 0 && c.block_height <= 2, "Cutter/Block height", "must be in (0, 2] m");
      r.require(c.penetration > 0 && c.penetration < 0.5 * c.block_height, "Cutter/Penetration",
                "must be in (0, Block height / 2 = " + mm(0.5 * c.block_height) + ")");
      if (cutting)
        r.require(c.cut_length > 0 && c.cut_length <= 0.8 * c.block_length, "Cutter/Cut length",
                  "must be in (0, 0.8 x Block length = " + mm(0.8 * c.block_length) + "]");
      const double smallest = std::min({c.block_length, c.block_width, c.block_height});
      if (!(p.sph.spacing <= smallest / 10))
        r.fail("SPH/Particle spacing", "too coarse for the " + mm(c.block_length) + " x " + mm(c.block_width) + " x " +
                                         mm(c.block_height) + " block: at most 1/10 of its smallest side (" +
                                         mm(smallest / 10) + ")");
      r.require(p.sph.spacing <= 0.5 * c.penetration, "SPH/Particle spacing",
                "must be at most half the Cutter/Penetration (" + mm(0.5 * c.penetration) +
                  ") so that at least two particle layers are cut");
      for (const char *key : {"Test/Diameter", "Test/Length", "Platens/Diameter", "Loading/Strain rate",
                              "Loading/Transit times", "Loading/End strain", "Loading/Post-peak drop",
                              "Loading/Max force imbalance"})
        if (r.was_set(key))
          warnings.push_back(std::string(key) + " is not used by Test/Type = " + p.test +
                             " (the Cutter section sets the block and the path)");
    }
  } // namespace

  std::string case_file_keys_help()
  {
    std::string out;
    for (const auto &k : keys)
      out += "  " + k.full() + " [" + (std::string(k.default_value).empty() ? "empty" : k.default_value) +
             "]: " + k.doc + "\n";
    return out;
  }

  CaseFile read_case_file(const std::string &path, const std::vector<std::string> &overrides)
  {
    namespace fs = std::filesystem;
    if (fs::is_directory(path))
      throw InputError(path + ": is a folder; give the path of a .prm case file such as cases/ucs/ucs.prm");
    const std::vector<Assignment> from_file = scan_case_file(path);
    std::vector<Assignment> from_command_line;
    for (const auto &o : overrides)
      from_command_line.push_back(parse_override(o));

    Origins origins;
    for (const auto &a : from_file)
      origins[a.key->full()] = a.origin;
    for (const auto &a : from_command_line)
      origins[a.key->full()] = a.origin;

    dealii::ParameterHandler prm;
    declare(prm);
    try
    {
      prm.parse_input(path, "", /*skip_undefined=*/false, /*assert_mandatory_entries_are_found=*/false);
      for (const auto &a : from_command_line)
      {
        prm.enter_subsection(a.key->section);
        prm.set(a.key->name, a.value);
        prm.leave_subsection();
      }
    }
    catch (const InputError &)
    {
      throw;
    }
    catch (const std::exception &e)
    {
      // the scan above should have caught everything deal.II refuses; keep the message one line
      throw InputError(path + ": " + one_line(e.what()));
    }

    Reader r(prm, origins, path);
    CaseFile result;
    CaseParameters &p = result.parameters;

    // --- Test
    p.test = r.get("Test/Type");
    p.name = r.get("Test/Name");
    if (p.name.empty())
      p.name = fs::path(path).stem().string();
    p.diameter = r.real("Test/Diameter");
    p.length = r.real("Test/Length");
    p.confining_pressure = r.real("Test/Confining pressure");
    r.require(p.diameter > 0 && p.diameter <= 10, "Test/Diameter", "must be in (0, 10] m");
    r.require(p.length > 0 && p.length <= 10, "Test/Length", "must be in (0, 10] m");
    r.require(p.confining_pressure >= 0 && p.confining_pressure < 1e10, "Test/Confining pressure",
              "must be >= 0 Pa (compression positive) and below 1e10 Pa");
    if (p.test != "CTCS")
      r.require(p.confining_pressure == 0, "Test/Confining pressure",
                "applies only to Test/Type = CTCS (this case is " + p.test + "); set it to 0 or use CTCS");
    else if (p.confining_pressure == 0)
      result.warnings.push_back("Test/Confining pressure is 0 in a CTCS case: this is a UCS test");

    // --- SPH
    p.sph.spacing = r.real("SPH/Particle spacing");
    p.sph.form = std::atoi(r.get("SPH/FORM").c_str());
    p.sph.cslh = r.real("SPH/CSLH");
    p.sph.tssfac = r.real("SPH/TSSFAC");
    p.sph.kernel = r.get("SPH/Kernel");
    p.sph.evolve_smoothing_length = r.boolean("SPH/Evolve smoothing length");
    p.sph.loaded_face_correction  = r.boolean("SPH/Loaded face correction");
    p.sph.av_alpha = r.real("SPH/Viscosity alpha");
    p.sph.av_beta = r.real("SPH/Viscosity beta");
    p.sph.hourglass = r.real("SPH/Hourglass coefficient");
    p.sph.n_threads = r.integer("SPH/Threads");
    p.sph.single_precision = r.get("SPH/Pair force precision") == "mixed";
    const bool cutting = p.test == "indentation" || p.test == "linear-cutting";
    const double smallest = p.test == "BTS" ? std::min(p.diameter, p.length) : std::min(p.diameter, p.length);
    r.require(p.sph.spacing > 0, "SPH/Particle spacing", "must be > 0 m (e.g. 0.001 to 0.005)");
    if (cutting)
      read_cutter(r, p, result.warnings); // checks the spacing against the block
    else if (!(p.sph.spacing <= smallest / 10))
      throw InputError(r.origin(r.was_set("SPH/Particle spacing") ? "SPH/Particle spacing" : "Test/Diameter") +
                       ": SPH/Particle spacing = " + r.get("SPH/Particle spacing") + " m is too coarse for a " +
                       mm(p.diameter) + " x " + mm(p.length) + " specimen: must be at most 1/10 of its smallest "
                       "dimension (" + mm(smallest / 10) + ") so that at least 10 particles span it");
    {
      const double volume = cutting ? p.cutter.block_length * p.cutter.block_width * p.cutter.block_height
                                    : 3.14159265358979 / 4 * p.diameter * p.diameter * p.length;
      const double n_estimate = volume / std::pow(p.sph.spacing, 3);
      r.require(n_estimate <= 2e8, "SPH/Particle spacing",
                "gives about " + format(std::round(n_estimate / 1e6)) +
                  " million particles; at most 200 million are accepted (use a coarser spacing)");
    }
    r.require(p.sph.cslh >= 1.0 && p.sph.cslh <= 2.0, "SPH/CSLH",
              "must be in [1.0, 2.0] (the paper tests 1.05, 1.2, 1.3; LS-DYNA default 1.2)");
    r.require(p.sph.tssfac > 0 && p.sph.tssfac <= 10, "SPH/TSSFAC", "must be in (0, 10] (stable: at most 1, usually 0.9)");
    if (p.sph.tssfac > 1)
      result.warnings.push_back("SPH/TSSFAC = " + r.get("SPH/TSSFAC") + " is above 1: expect an unstable run");
    r.require(p.sph.av_alpha >= 0 && p.sph.av_alpha <= 10, "SPH/Viscosity alpha", "must be in [0, 10]");
    r.require(p.sph.av_beta >= 0 && p.sph.av_beta <= 10, "SPH/Viscosity beta", "must be in [0, 10]");
    r.require(p.sph.hourglass >= 0 && p.sph.hourglass <= 1, "SPH/Hourglass coefficient", "must be in [0, 1]");
    r.require(p.sph.n_threads >= 0 && p.sph.n_threads <= 4096, "SPH/Threads", "must be in [0, 4096] (0 = all cores)");

    // --- Rock: the group first, explicit keys override
    RockParameters &rock = p.rock;
    rock.group = r.get("Rock/Group");
    rock.model = r.get("Rock/Model");
    std::string data_directory = r.get("Rock/Data directory");
    if (data_directory.empty())
      data_directory = app::data_directory().string();
    else if (fs::path(data_directory).is_relative() && r.origin("Rock/Data directory").rfind("--set", 0) != 0)
      data_directory = (fs::path(path).parent_path() / data_directory).string();
    const MaterialTable table = MaterialTable::read(data_directory);
    const MaterialGroup *group = table.lookup(rock.group);
    if (group == nullptr)
      r.fail("Rock/Group", "unknown rock group" + did_you_mean(rock.group, [&] {
                             std::vector<std::string> names;
                             for (const auto &g : table.groups())
                               names.push_back(g.group);
                             return names;
                           }()) + "; known groups: " + table.group_names() + " (" + data_directory + ")");
    const std::string strength_source = r.get("Rock/Strength parameters");
    const bool measured = strength_source == "measured";
    std::optional<double> group_c, group_phi;
    if (strength_source == "brazilian")
    {
      // the disc centre's stress state (3 BTS, -BTS) on the envelope instead of uniaxial tension
      if (!(group->ucs > 4 * group->bts))
        r.fail("Rock/Strength parameters", "brazilian needs UCS > 4 BTS (group " + rock.group + ")");
      const MohrCoulombStrength b = calibrate_mohr_coulomb_brazilian(group->ucs, group->bts);
      group_c = b.cohesion;
      group_phi = b.friction_angle;
    }
    else if (measured)
    {
      if (!group->measured_cohesion)
        r.fail("Rock/Strength parameters", "group " + rock.group + " has no measured c, phi (Table 3); groups that have them: " +
                                             table.groups_with_measured_strength() + "; or use calibrated");
      group_c = group->measured_cohesion;
      group_phi = group->measured_friction_angle;
    }
    else
    {
      group_c = group->calibrated_cohesion;
      group_phi = group->calibrated_friction_angle;
    }
    rock.density = r.real("Rock/Density");
    rock.youngs_modulus = r.optional("Rock/Youngs modulus").value_or(group->youngs_modulus);
    rock.poissons_ratio = r.optional("Rock/Poissons ratio").value_or(group->poissons_ratio);
    rock.ucs = r.optional("Rock/UCS").value_or(group->ucs);
    rock.bts = group->bts;
    const bool cutoff = rock.model == "mohr-coulomb-cutoff";
    rock.tensile_strength = r.optional("Rock/Tensile strength").value_or(cutoff ? group->bts : 0.0);
    const bool needs_mc = rock.model == "mohr-coulomb" || cutoff;
    if (r.optional("Rock/Cohesion"))
      rock.cohesion = *r.optional("Rock/Cohesion");
    else if (group_c)
      rock.cohesion = *group_c;
    else if (needs_mc)
      r.fail("Rock/Group", "has no calibrated c, phi (no table4_calibrated.csv row); set Rock/Cohesion and Rock/Friction angle");
    if (r.optional("Rock/Friction angle"))
      rock.friction_angle = *r.optional("Rock/Friction angle");
    else if (group_phi)
      rock.friction_angle = *group_phi;
    rock.dilation_angle = r.real("Rock/Dilation angle");
    rock.hoek_brown_mi = r.real("Rock/Hoek-Brown mi");
    rock.softening_strain = r.real("Rock/Softening strain");
    rock.residual_fraction = r.real("Rock/Residual fraction");
    rock.residual_friction_angle = r.optional("Rock/Residual friction angle").value_or(-1.0);
    rock.strength_scatter = r.real("Rock/Strength scatter");
    rock.scatter_seed = r.integer("Rock/Scatter seed");

    r.require(rock.density > 0 && rock.density < 30000, "Rock/Density", "must be in (0, 30000) kg/m^3");
    r.require(rock.youngs_modulus > 0 && rock.youngs_modulus < 1e13, "Rock/Youngs modulus",
              "must be in (0, 1e13) Pa (basalt: about 1e11)");
    r.require(rock.poissons_ratio >= 0 && rock.poissons_ratio < 0.5, "Rock/Poissons ratio", "must be in [0, 0.5)");
    r.require(rock.cohesion > 0, "Rock/Cohesion", "must be > 0 Pa");
    r.require(rock.friction_angle > 0 && rock.friction_angle < 90, "Rock/Friction angle", "must be in (0, 90) degrees");
    r.require(rock.dilation_angle >= 0 && rock.dilation_angle <= rock.friction_angle, "Rock/Dilation angle",
              "must be in [0, friction angle = " + format(rock.friction_angle) + "] degrees");
    r.require(rock.tensile_strength >= 0, "Rock/Tensile strength", "must be >= 0 Pa");
    if (cutoff)
    {
      const double apex = rock.cohesion / std::tan(rock.friction_angle * 3.14159265358979 / 180);
      r.require(rock.tensile_strength > 0 && rock.tensile_strength <= apex, "Rock/Tensile strength",
                "must be in (0, c/tan(phi) = " + format(apex) + "] Pa for mohr-coulomb-cutoff");
    }
    if (rock.model == "hoek-brown")
    {
      r.require(rock.hoek_brown_mi > 0 && rock.hoek_brown_mi < 100, "Rock/Hoek-Brown mi", "must be in (0, 100) for hoek-brown");
      r.require(rock.ucs > 0, "Rock/UCS", "must be > 0 Pa for hoek-brown");
    }
    r.require(rock.softening_strain > 0 && rock.softening_strain < 1, "Rock/Softening strain", "must be in (0, 1)");
    r.require(rock.residual_fraction >= 0 && rock.residual_fraction <= 1, "Rock/Residual fraction", "must be in [0, 1]");
    if (r.optional("Rock/Residual friction angle"))
    {
      r.require(needs_mc, "Rock/Residual friction angle",
                "softens the Mohr-Coulomb friction angle; Rock/Model = " + rock.model + " has none (leave it empty)");
      r.require(rock.residual_friction_angle > 0 && rock.residual_friction_angle <= rock.friction_angle,
                "Rock/Residual friction angle", "must be in (0, friction angle = " + format(rock.friction_angle) + "] degrees");
      r.require(rock.residual_friction_angle >= rock.dilation_angle, "Rock/Residual friction angle",
                "must be at least Rock/Dilation angle = " + format(rock.dilation_angle) + " degrees");
    }
    r.require(rock.strength_scatter == 0 || (rock.strength_scatter >= 1 && rock.strength_scatter <= 1000),
              "Rock/Strength scatter", "must be 0 (homogeneous) or a Weibull modulus in [1, 1000]");
    r.require(rock.strength_scatter == 0 || rock.model != "elastic", "Rock/Strength scatter",
              "scatters strength, which Rock/Model = elastic does not have; set it to 0 or choose a plastic model");
    r.require(rock.scatter_seed >= 0, "Rock/Scatter seed", "must be >= 0");

    // --- Platens
    PlatenParameters &pl = p.platens;
    pl.model = r.get("Platens/Model");
    pl.friction = r.real("Platens/Friction coefficient");
    pl.youngs_modulus = r.real("Platens/Youngs modulus");
    pl.poissons_ratio = r.real("Platens/Poissons ratio");
    pl.density = r.real("Platens/Density");
    pl.thickness = r.real("Platens/Thickness");
    pl.diameter = r.real("Platens/Diameter");
    pl.element_size = r.real("Platens/Element size");
    pl.contact_stiffness_scale = r.real("Platens/Contact stiffness scale");
    r.require(pl.friction >= 0 && pl.friction <= 2, "Platens/Friction coefficient", "must be in [0, 2]");
    r.require(pl.youngs_modulus > 0 && pl.youngs_modulus < 1e13, "Platens/Youngs modulus", "must be in (0, 1e13) Pa");
    r.require(pl.poissons_ratio >= 0 && pl.poissons_ratio < 0.5, "Platens/Poissons ratio", "must be in [0, 0.5)");
    r.require(pl.density > 0 && pl.density < 30000, "Platens/Density", "must be in (0, 30000) kg/m^3");
    r.require(pl.thickness > 0 && pl.thickness <= 10, "Platens/Thickness", "must be in (0, 10] m");
    r.require(pl.diameter >= 0 && pl.diameter <= 10, "Platens/Diameter", "must be in [0, 10] m (0 = from the specimen)");
    r.require(pl.element_size >= 0 && pl.element_size <= pl.thickness, "Platens/Element size",
              "must be in [0, platen thickness] m (0 = from the particle spacing)");
    r.require(pl.contact_stiffness_scale > 0 && pl.contact_stiffness_scale <= 1, "Platens/Contact stiffness scale",
              "must be in (0, 1]");
    pl.shape = r.get("Platens/Shape");
    pl.jaw_radius = r.real("Platens/Jaw radius");
    r.require(pl.shape == "flat" || p.test == "BTS", "Platens/Shape", "jaw is for BTS only; use flat for " + p.test);
    r.require(pl.jaw_radius == 0 || pl.shape == "jaw", "Platens/Jaw radius", "is used with Platens/Shape = jaw only; leave it 0");
    if (pl.shape == "jaw")
    {
      const double width = pl.diameter > 0 ? pl.diameter : 0.6 * p.diameter; // as the driver builds it
      const double radius = pl.jaw_radius > 0 ? pl.jaw_radius : 0.75 * p.diameter;
      r.require(pl.jaw_radius >= 0 && radius > 0.5 * p.diameter && radius > 0.5 * width, "Platens/Jaw radius",
                "must exceed the disc radius (" + mm(0.5 * p.diameter) + ") and half the jaw width (" + mm(0.5 * width) +
                  "); ISRM: 1.5 x the disc radius (0 = that)");
    }

    // --- Loading
    LoadingParameters &ld = p.loading;
    ld.strain_rate = r.real("Loading/Strain rate");
    ld.transit_times = r.real("Loading/Transit times");
    ld.end_strain = r.real("Loading/End strain");
    ld.post_peak_drop = r.real("Loading/Post-peak drop");
    ld.max_kinetic_ratio = r.real("Loading/Max kinetic ratio");
    ld.max_force_imbalance = r.real("Loading/Max force imbalance");
    r.require(ld.strain_rate >= 0 && ld.strain_rate <= 100, "Loading/Strain rate",
              "must be in [0, 100] 1/s (0 = derived from the wave transit time; the paper uses 0.01)");
    r.require(ld.transit_times > 0 && ld.transit_times <= 1e6, "Loading/Transit times", "must be in (0, 1e6]");
    r.require(ld.end_strain > 0 && ld.end_strain <= 0.5, "Loading/End strain", "must be in (0, 0.5]");
    r.require(ld.post_peak_drop > 0 && ld.post_peak_drop < 1, "Loading/Post-peak drop", "must be in (0, 1)");
    r.require(ld.max_kinetic_ratio > 0, "Loading/Max kinetic ratio", "must be > 0");
    r.require(ld.max_force_imbalance > 0, "Loading/Max force imbalance", "must be > 0");

    // --- Output
    p.output.n_history_rows = r.integer("Output/History rows");
    p.output.n_snapshots = r.integer("Output/Snapshots");
    p.output.progress = r.boolean("Output/Progress");
    r.require(p.output.n_history_rows >= 2 && p.output.n_history_rows <= 10000000, "Output/History rows",
              "must be in [2, 10000000]");
    r.require(p.output.n_snapshots >= 0 && p.output.n_snapshots <= 100000, "Output/Snapshots", "must be in [0, 100000]");
    p.output.checkpoint_steps = r.integer("Output/Checkpoint interval");
    p.output.checkpoint_minutes = r.real("Output/Checkpoint minutes");
    p.output.stop_after_steps = r.integer("Output/Stop after steps");
    r.require(p.output.checkpoint_steps >= 0, "Output/Checkpoint interval", "must be >= 0 steps (0 = no periodic checkpoints)");
    r.require(p.output.checkpoint_minutes >= 0 && p.output.checkpoint_minutes <= 1e6, "Output/Checkpoint minutes",
              "must be in [0, 1e6] minutes (0 = no timed checkpoints)");
    r.require(p.output.stop_after_steps >= 0, "Output/Stop after steps", "must be >= 0 (0 = never)");

    // used_parameters.prm: the final values, the group's included
    r.set("Test/Name", p.name);
    r.set("Rock/Youngs modulus", format(rock.youngs_modulus));
    r.set("Rock/Poissons ratio", format(rock.poissons_ratio));
    r.set("Rock/Cohesion", format(rock.cohesion));
    r.set("Rock/Friction angle", format(rock.friction_angle));
    r.set("Rock/Tensile strength", format(rock.tensile_strength));
    r.set("Rock/UCS", format(rock.ucs));
    r.set("Rock/Data directory", fs::absolute(data_directory).lexically_normal().string());
    std::ostringstream used;
    used << "# cosim: parameters used for case '" << p.name << "' (" << path << ")\n"
         << "# Rock values resolved from group " << rock.group << " ("
         << (measured ? "measured c, phi: Table 3"
                      : strength_source == "brazilian" ? "c, phi calibrated to UCS and BTS at the disc centre's stress state"
                                                       : "calibrated c, phi: Table 4")
         << ") and explicit keys\n";
    prm.print_parameters(used, dealii::ParameterHandler::PRM);
    result.used_parameters = used.str();
    return result;
  }
} // namespace app
