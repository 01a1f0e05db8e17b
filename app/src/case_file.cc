// Reading a case file: the keys of every section (app/src/*_keys.cc) declared into one deal.II
// ParameterHandler bound to CaseParameters, the file parsed by deal.II (.prm or .json), `--set`
// applied, the rock group resolved and every check run. deal.II's exceptions become one-line
// InputErrors naming the file and line (or the --set argument), the key, what is wrong and what
// is accepted.
#include "case_keys.h"

#include <app/case_file.h>
#include <app/cli.h>
#include <app/paths.h>
#include <coupling/run_case.h>
#include <diagnose/csv.h>
#include <diagnose/material_table.h>
#include <diagnose/text_input.h>
#include <sph/rock_models.h>

#include <boost/property_tree/json_parser.hpp>
#include <boost/property_tree/ptree.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace app
{
  using coupling::CaseParameters;
  using coupling::CutterParameters;
  using coupling::InputError;
  using diagnose::trim;
  using keys::format;
  using keys::Key;
  namespace fs = std::filesystem;

  namespace
  {
    /// Every key of a case, declared into `prm` and bound to `p` (and to `o`, the rock keys that
    /// may stay empty).
    struct Declaration
    {
      dealii::ParameterHandler prm;
      std::vector<Key> keys;
      keys::RockOverrides overrides;

      explicit Declaration(CaseParameters &p)
      {
        { keys::Section s(prm, keys, "Test"); keys::declare_test_keys(s, p); }
        { keys::Section s(prm, keys, "Rock"); keys::declare_rock_keys(s, p, overrides); }
        { keys::Section s(prm, keys, "SPH"); keys::declare_sph_keys(s, p); }
        { keys::Section s(prm, keys, "Platens"); keys::declare_platen_keys(s, p); }
        { keys::Section s(prm, keys, "Loading"); keys::declare_loading_keys(s, p); }
        { keys::Section s(prm, keys, "Cutter"); keys::declare_cutter_keys(s, p); }
        { keys::Section s(prm, keys, "Output"); keys::declare_output_keys(s, p); }
      }

      const Key *find(const std::string &section, const std::string &name) const
      {
        for (const auto &k : keys)
          if (k.section == section && k.name == name)
            return &k;
        return nullptr;
      }

      std::vector<std::string> sections() const
      {
        std::vector<std::string> out;
        for (const auto &k : keys)
          if (out.empty() || out.back() != k.section)
            out.push_back(k.section);
        return out;
      }

      std::vector<std::string> names(const std::string &section) const
      {
        std::vector<std::string> out;
        for (const auto &k : keys)
          if (k.section == section)
            out.push_back(k.name);
        return out;
      }

      std::vector<std::string> full_names() const
      {
        std::vector<std::string> out;
        for (const auto &k : keys)
          out.push_back(k.full());
        return out;
      }

      std::string get(const std::string &section, const std::string &name)
      {
        prm.enter_subsection(section);
        const std::string v = prm.get(name);
        prm.leave_subsection();
        return v;
      }

      void set(const std::string &section, const std::string &name, const std::string &value)
      {
        prm.enter_subsection(section);
        prm.set(name, value);
        prm.leave_subsection();
      }
    };

    std::string join(const std::vector<std::string> &items, const std::string &separator)
    {
      std::string out;
      for (const auto &i : items)
        out += (out.empty() ? "" : separator) + i;
      return out;
    }

    /// One line out of a library's text.
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

    std::string info_of(const dealii::ExceptionBase &e)
    {
      std::ostringstream s;
      e.print_info(s);
      return s.str();
    }

    bool ends_with(const std::string &s, const std::string &tail)
    {
      return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
    }

    /// The lines of a .prm file as deal.II reads them (comments cut), to tell a message which
    /// section a line deal.II refused belongs to and where a key was set. deal.II parses.
    class Outline
    {
    public:
      explicit Outline(const std::string &path)
      {
        std::ifstream in(path);
        std::string line;
        while (std::getline(in, line))
        {
          const auto hash = line.find('#');
          lines_.push_back(trim(hash == std::string::npos ? line : line.substr(0, hash)));
        }
      }

      const std::string &line(int n) const
      {
        static const std::string none;
        return n >= 1 && n <= static_cast<int>(lines_.size()) ? lines_[n - 1] : none;
      }

      /// Sections open before line `n` (1-based), with the line that opened each.
      std::vector<std::pair<std::string, int>> open_before(int n) const
      {
        std::vector<std::pair<std::string, int>> open;
        for (int i = 1; i < n && i <= static_cast<int>(lines_.size()); ++i)
        {
          const std::string &l = lines_[i - 1];
          if (l.rfind("subsection ", 0) == 0 || l.rfind("SUBSECTION ", 0) == 0)
            open.emplace_back(trim(l.substr(11)), i);
          else if ((l == "end" || l == "END") && !open.empty())
            open.pop_back();
        }
        return open;
      }

      /// The line of the last `set name = ...` in `section`; 0 where there is none.
      int line_of(const std::string &section, const std::string &name) const
      {
        int found = 0;
        std::vector<std::string> open;
        for (int i = 1; i <= static_cast<int>(lines_.size()); ++i)
        {
          const std::string &l = lines_[i - 1];
          if (l.rfind("subsection ", 0) == 0 || l.rfind("SUBSECTION ", 0) == 0)
            open.push_back(trim(l.substr(11)));
          else if ((l == "end" || l == "END") && !open.empty())
            open.pop_back();
          else if ((l.rfind("set ", 0) == 0 || l.rfind("SET ", 0) == 0) && open.size() == 1 &&
                   open[0] == section)
          {
            const auto eq = l.find('=');
            if (eq != std::string::npos && trim(l.substr(4, eq - 4)) == name)
              found = i;
          }
        }
        return found;
      }

    private:
      std::vector<std::string> lines_;
    };

    /// `text` between "Line <" and ">".
    int line_number_in(const std::string &text)
    {
      const auto at = text.find("Line <");
      return at == std::string::npos ? 0 : std::atoi(text.c_str() + at + 6);
    }

    /// The line after `label` in a deal.II message, trimmed.
    std::string line_after(const std::string &text, const std::string &label)
    {
      auto at = text.find(label);
      if (at == std::string::npos)
        return {};
      at = text.find('\n', at);
      if (at == std::string::npos)
        return {};
      const auto end = text.find('\n', at + 1);
      return trim(text.substr(at + 1, end == std::string::npos ? std::string::npos : end - at - 1));
    }

    std::string bad_value(const Key &k, const std::string &value, const std::string &where)
    {
      return where + ": " + k.full() + " = '" + value + "' is not " + k.accepted() +
             (k.kind == keys::Kind::selection ? "" : " (" + k.doc + ")");
    }

    std::string unknown_section(const Declaration &d, const std::string &where, const std::string &name,
                                const std::vector<std::string> &candidates)
    {
      return where + ": unknown section '" + name + "'" + did_you_mean(name, candidates) +
             "; accepted sections: " + join(d.sections(), ", ");
    }

    std::string unknown_key(const Declaration &d, const std::string &where, const std::string &section,
                            const std::string &name)
    {
      return where + ": unknown key '" + name + "' in section " + section + did_you_mean(name, d.names(section)) +
             "; accepted keys in " + section + ": " + join(d.names(section), ", ");
    }

    /// deal.II's refusal of a .prm file, as one line naming the line, the key and what is accepted.
    std::string prm_message(const Declaration &d, const std::string &path, const dealii::ExceptionBase &e)
    {
      const std::string info = info_of(e);
      const Outline outline(path);
      const int n            = line_number_in(info);
      const std::string where = path + ":" + std::to_string(n);
      const std::string line  = outline.line(n);
      const auto open         = outline.open_before(n);
      using PH                = dealii::ParameterHandler;
      if (dynamic_cast<const PH::ExcNoSubsection *>(&e))
      {
        const std::string name = trim(line.substr(std::min<std::size_t>(line.size(), 11)));
        if (!open.empty())
          return where + ": unknown section '" + open.back().first + "/" + name +
                 "'; sections do not nest; accepted sections: " + join(d.sections(), ", ");
        return unknown_section(d, where, name, d.sections());
      }
      if (dynamic_cast<const PH::ExcInvalidEntryForPattern *>(&e))
      {
        const std::string value = line_after(info, "The entry value");
        const std::string name  = line_after(info, "for the entry named");
        if (const Key *k = open.empty() ? nullptr : d.find(open.back().first, name))
          return bad_value(*k, value, where);
        return where + ": " + one_line(info.substr(info.find(':') + 1));
      }
      if (dynamic_cast<const PH::ExcUnbalancedSubsections *>(&e))
      {
        const auto still_open = outline.open_before(1 << 30);
        if (!still_open.empty())
          return path + ":" + std::to_string(still_open.back().second) + ": subsection '" +
                 still_open.back().first + "' is not closed with 'end'";
        return path + ": " + one_line(info);
      }
      if (dynamic_cast<const PH::ExcCannotParseLine *>(&e))
      {
        if (info.find("No entry with name <") != std::string::npos)
        {
          const auto b = info.find("No entry with name <") + 20;
          const std::string name = info.substr(b, info.find('>', b) - b);
          if (open.empty())
          {
            std::vector<std::string> homes;
            for (const auto &k : d.keys)
              if (k.name == name)
                homes.push_back(k.section);
            return where + ": 'set " + name + "' outside a subsection; " +
                   (homes.empty() ? "every key belongs to one of the sections " + join(d.sections(), ", ")
                                  : "it belongs in subsection " + join(homes, " or "));
          }
          return unknown_key(d, where, open.back().first, name);
        }
        if (info.find("after 'end'") != std::string::npos)
          return where + ": 'end' takes nothing after it (found '" + trim(line.substr(3)) + "')";
        if (info.find("no subsection to leave") != std::string::npos)
          return where + ": 'end' without an open subsection";
        if (info.find("Invalid format of 'set'") != std::string::npos)
          return where + ": '" + line + "' has no '='; write 'set Key = value'";
        if (info.find("could not be parsed") != std::string::npos)
          return where + ": cannot read '" + line +
                 "'; expected 'subsection Name', 'set Key = value', 'end' or a # comment";
      }
      return (n > 0 ? where : path) + ": " + one_line(info);
    }

    /// deal.II's refusal of a .json file: the tree walked again to name the culprit.
    std::string json_message(const Declaration &d, const std::string &path, const dealii::ExceptionBase &e)
    {
      namespace pt = boost::property_tree;
      pt::ptree tree;
      try
      {
        pt::read_json(path, tree);
      }
      catch (const pt::json_parser_error &j)
      {
        return path + ":" + std::to_string(j.line()) + ": not valid JSON (" + one_line(j.message()) +
               "); write {\"Section\": {\"Key\": \"value\", ...}, ...}";
      }
      for (const auto &[section, keys] : tree)
      {
        if (d.names(section).empty())
          return unknown_section(d, path, section, d.sections());
        for (const auto &[name, node] : keys)
        {
          const Key *k = d.find(section, name);
          if (k == nullptr)
            return unknown_key(d, path, section, name);
          const std::string value = node.empty() ? node.data() : node.get<std::string>("value", "");
          if (!k->pattern->match(value))
            return bad_value(*k, value, path);
        }
      }
      return path + ": " + one_line(info_of(e));
    }

    /// Where each key got its value, for messages.
    class Origins
    {
    public:
      Origins(const std::string &path, bool json)
        : path_(path)
        , json_(json)
      {
        if (json_)
          try
          {
            boost::property_tree::read_json(path, tree_);
          }
          catch (const std::exception &)
          {}
        else
          outline_ = std::make_unique<Outline>(path);
      }

      void set_by_option(const std::string &full, const std::string &option) { options_[full] = option; }

      /// "case.prm:12", "--set \"A/B=c\"", "case.json", or "case.prm: (default)".
      std::string of(const std::string &full) const
      {
        if (const auto it = options_.find(full); it != options_.end())
          return it->second;
        const auto slash = full.find('/');
        if (json_)
          return tree_.get_child_optional(boost::property_tree::ptree::path_type(full, '/')) ? path_
                                                                                              : path_ + ": (default)";
        const int n = outline_->line_of(full.substr(0, slash), full.substr(slash + 1));
        return n > 0 ? path_ + ":" + std::to_string(n) : path_ + ": (default)";
      }

      bool was_set(const std::string &full) const { return !ends_with(of(full), ": (default)"); }
      bool by_option(const std::string &full) const { return options_.count(full) > 0; }

    private:
      std::string path_;
      bool json_;
      std::map<std::string, std::string> options_;
      std::unique_ptr<Outline> outline_;
      boost::property_tree::ptree tree_;
    };

    /// Checks after the case is read: `fail` names the key's origin and value.
    class Reader
    {
    public:
      Reader(Declaration &d, const Origins &origins)
        : d_(d)
        , origins_(origins)
      {}

      std::string get(const std::string &full) const
      {
        const auto slash = full.find('/');
        return d_.get(full.substr(0, slash), full.substr(slash + 1));
      }
      std::string origin(const std::string &full) const { return origins_.of(full); }
      bool was_set(const std::string &full) const { return origins_.was_set(full); }

      [[noreturn]] void fail(const std::string &full, const std::string &what) const
      {
        const std::string v = get(full);
        throw InputError(origin(full) + ": " + full + " = " + (v.empty() ? "''" : v) + ": " + what);
      }

      void require(bool ok, const std::string &full, const std::string &what) const
      {
        if (!ok)
          fail(full, what);
      }

    private:
      Declaration &d_;
      const Origins &origins_;
    };

    std::string mm(double v) { return format(v * 1e3) + " mm"; }

    /// An override "Section/Key=value", checked and applied.
    void apply_override(Declaration &d, Origins &origins, const std::string &text)
    {
      const std::string origin = "--set \"" + text + "\"";
      const auto eq            = text.find('=');
      const auto slash         = text.find('/');
      if (eq == std::string::npos || slash == std::string::npos || slash > eq)
        throw InputError(origin + ": expected \"Section/Key=value\", e.g. --set \"SPH/Particle spacing=0.002\"");
      const std::string section = trim(text.substr(0, slash));
      const std::string name    = trim(text.substr(slash + 1, eq - slash - 1));
      const std::string value   = trim(text.substr(eq + 1));
      if (d.names(section).empty())
        throw InputError(origin + ": unknown section '" + section + "'" + did_you_mean(section + "/" + name, d.full_names()) +
                         "; accepted sections: " + join(d.sections(), ", "));
      const Key *k = d.find(section, name);
      if (k == nullptr)
        throw InputError(unknown_key(d, origin, section, name));
      if (!k->pattern->match(value))
        throw InputError(bad_value(*k, value, origin));
      d.set(section, name, value);
      origins.set_by_option(k->full(), origin);
    }

    /// The cross checks of an indentation / linear-cutting case; warns about keys of the
    /// laboratory tests that these tests do not use.
    void check_cutter(const Reader &r, const CaseParameters &p, std::vector<std::string> &warnings)
    {
      const CutterParameters &c = p.cutter;
      const bool cutting        = p.test == "linear-cutting";
      if (cutting)
        r.require(c.shape == "disc", "Cutter/Shape", "linear-cutting rolls a disc cutter: set it to disc");
      else
        r.require(c.shape != "disc", "Cutter/Shape", "indentation presses a wedge, cone or flat punch: set one of them");
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
      r.require(p.particle_arrangement == sph::ParticleArrangement::lattice, "SPH/Particle arrangement",
                "body-fitted is for the UCS/CTCS cylinder and the BTS disc; the rock block of " + p.test +
                  " is a lattice (its flat faces are exact): set it to lattice");
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

    /// How an escaped `\#` (a `#` in a value: a bare one starts a comment) travels through
    /// deal.II's reader, which cuts a line at any `#`: as this control character, turned back
    /// into `#` in the text values (restore_hash).
    constexpr char hidden_hash = '\x1f';

    /// Parses the case file into `d` (bound to the case's parameters), with our messages. The
    /// text goes through the one input reader first (byte-order mark, line ends, encoding).
    void parse(Declaration &d, const std::string &path, bool json)
    {
      if (!fs::exists(path))
        throw InputError(diagnose::clip(path) +
                         ": cannot open the case file (no such file); give the path of a .prm file such as "
                         "cases/ucs/ucs.prm");
      std::string text = diagnose::read_text_file(path, "case file");
      if (!json)
        for (std::size_t at = text.find("\\#"); at != std::string::npos; at = text.find("\\#", at))
          text.replace(at, 2, 1, hidden_hash);
      std::istringstream in(text);
      try
      {
        if (json)
          d.prm.parse_input_from_json(in, /*skip_undefined=*/false);
        else
          d.prm.parse_input(in, path, "", /*skip_undefined=*/false);
      }
      catch (const dealii::ExceptionBase &e)
      {
        throw InputError(json ? json_message(d, path, e) : prm_message(d, path, e));
      }
    }

    /// A text value as parsed: each `\#` of the file (see hidden_hash) back to `#`.
    std::string restore_hash(std::string value)
    {
      std::replace(value.begin(), value.end(), hidden_hash, '#');
      return value;
    }
  } // namespace

  std::string case_file_keys_help()
  {
    CaseParameters p;
    Declaration d(p);
    std::string out;
    for (const auto &k : d.keys)
    {
      const std::string v = d.get(k.section, k.name);
      out += "  " + k.full() + " [" + (v.empty() ? "empty" : v) + "]: " + k.doc + "\n";
    }
    return out;
  }

  std::string default_case_file()
  {
    CaseParameters p;
    Declaration d(p);
    std::ostringstream out;
    out << "# cosim " << version() << " (commit " << commit() << "): every case-file key with its default\n"
        << "# Rock keys left empty take the value of Rock/Group from the data tables.\n";
    d.prm.print_parameters(out, dealii::ParameterHandler::PRM);
    return out.str();
  }

  CaseFile read_case_file(const std::string &path, const std::vector<std::string> &overrides)
  {
    if (fs::is_directory(path))
      throw InputError(path + ": is a folder; give the path of a .prm case file such as cases/ucs/ucs.prm");
    const bool json = ends_with(path, ".json");
    if (!json && !ends_with(path, ".prm"))
      throw InputError(diagnose::clip(path) + ": a case file is a .prm (or .json) file; rename it, e.g. " +
                       diagnose::clip(fs::path(path).stem().string()) + ".prm");
    CaseFile result;
    CaseParameters &p = result.parameters;
    try
    {
      Declaration d(p);
      parse(d, path, json);
      Origins origins(path, json);
      for (const auto &o : overrides)
        apply_override(d, origins, o);
      Reader r(d, origins);
      // a value deal.II stored without reading it ({...} lists) must still be of the key's type
      for (const auto &k : d.keys)
        if (const std::string v = d.get(k.section, k.name); !k.pattern->match(v))
          throw InputError(bad_value(k, v, origins.of(k.full())));

      // --- Test
      p.name = restore_hash(p.name);
      if (p.name.empty())
        p.name = fs::path(path).stem().string();

      // --- Rock: the group first, explicit keys override
      coupling::RockCase &rc = p.rock_case;
      std::string data_directory = restore_hash(rc.data_directory);
      if (data_directory.empty())
        data_directory = app::data_directory().string();
      else if (fs::path(data_directory).is_relative() && !origins.by_option("Rock/Data directory"))
        data_directory = (fs::path(path).parent_path() / data_directory).string();
      const diagnose::MaterialTable table = diagnose::MaterialTable::read(data_directory);
      const diagnose::MaterialGroup *group = table.lookup(rc.group);
      if (group == nullptr)
        r.fail("Rock/Group", "unknown rock group" + did_you_mean(rc.group, [&] {
                               std::vector<std::string> names;
                               for (const auto &g : table.groups())
                                 names.push_back(g.group);
                               return names;
                             }()) + "; known groups: " + table.group_names() + " (" + data_directory + ")");
      keys::resolve_rock(p, d.overrides, table, *group,
                         [&r](const std::string &key, const std::string &what) { r.fail(key, what); });

      // --- every key's own check, in the order of the sections
      for (const auto &k : d.keys)
        if (k.check)
          if (const std::string what = k.check(); !what.empty())
            r.fail(k.full(), what);

      // --- checks across sections
      if (p.test == "CTCS" && p.confining_pressure == 0)
        result.warnings.push_back("Test/Confining pressure is 0 in a CTCS case: this is a UCS test");
      if (p.rock.softening_law == sph::SofteningLaw::fracture_energy &&
          p.rock.model != sph::RockModel::elastic)
      {
        // the shear counterpart of the snap-back refusal of Rock/Fracture energy: a warning, for
        // with basalt's G_II and strength it holds at every practical spacing (M1: bands under
        // 1.5 mm); the tensile crack, which the law is for, is refused instead
        const double ucs   = sph::rock::make_model_constants(p.rock).crush_pressure;
        const double g2    = p.rock.fracture_energy * p.rock.shear_fracture_energy_ratio;
        const double band  = sph::rock::crack_band_width(p.sph.spacing, p.sph.cslh);
        const double h_max = 2 * p.rock.youngs_modulus * g2 / (ucs * ucs);
        if (band >= h_max)
          result.warnings.push_back("Rock/Shear fracture energy ratio: shear softening snaps back "
                                    "at this spacing (crack band " +
                                    keys::format(band) +
                                    " m, wider than 2 E G_II / UCS^2 = " + keys::format(h_max) +
                                    " m): a particle failing in compression loses its strength "
                                    "within a step and dissipates more than "
                                    "G_II; G_II above " +
                                    keys::format(ucs * ucs * band / (2 * p.rock.youngs_modulus)) +
                                    " J/m^2 or a finer spacing avoids it");
      }
      if (p.rock_case.scatter_length > 0 && p.rock_case.scatter_length < p.sph.spacing)
        result.warnings.push_back("Rock/Scatter length = " + keys::format(p.rock_case.scatter_length) +
                                  " m is below SPH/Particle spacing = " + keys::format(p.sph.spacing) +
                                  " m: each particle takes the cell at its centre, and the rock is not resolved");
      if ((p.test == "UCS" || p.test == "CTCS") && p.platens.steel.model == fem::SteelModel::elastic &&
          p.particle_arrangement == sph::ParticleArrangement::lattice && p.platens.diameter > 0 &&
          p.platens.diameter < p.diameter + p.sph.spacing)
        result.warnings.push_back(
          "Platens/Diameter = " + keys::format(p.platens.diameter) +
          " m: elastic platens about as wide as a lattice specimen take its staircase side on their rim, "
          "which loads the steel unevenly (M1 on rollers, 2.5 mm, default softening: 272.7 MPa against 283.0 "
          "on the body-fitted specimen, the closed form 282.19); set SPH/Particle arrangement = body-fitted");
      // the flattened body-fitted disc converges from D/20 (cases/bts/README.md; M1, 20 deg flats,
      // Table 4's c, phi, 25 mm thick: 12.60 / 12.54 / 12.72 / 12.77 / 12.67 MPa at D/20, D/25,
      // D/40, D/50, D/62.5; 50 mm thick: 11.90 / 11.66 / 11.70 / 11.45 at D/10, D/15, D/20, D/40)
      if (p.test == "BTS" && p.flat_angle > 0 &&
          p.particle_arrangement == sph::ParticleArrangement::body_fitted &&
          p.sph.spacing > p.diameter / 20 * (1 + 1e-9))
        result.warnings.push_back(
          "SPH/Particle spacing = " + keys::format(p.sph.spacing) + " m is coarser than D/20 = " +
          keys::format(p.diameter / 20) +
          " m: the flattened disc's peak has not converged there (M1, 20 deg flats, 50 mm thick: 11.90 "
          "MPa at D/10, 11.70 / 11.45 MPa at D/20 / D/40); quote a peak from D/20 or finer");
      const double platen_diameter = coupling::cylinder_platen_diameter(p);
      // friction-held ends with the crack band of a shear fault's energy converge on them (M1,
      // Hoek-Brown, 60 mm platens: mu 0.3 279.51-280.06 MPa over 5 / 2.5 / 1.25 mm particles on
      // 10 / 5 / 2.5 mm elements; mu 0.1 281.81 / 281.11 MPa at 2.5 / 1.25 mm); frictionless ones
      // do not, with a dilation angle of 30 deg either (280.00 / 271.60 / 253.67 MPa). Measured on
      // that rock and test only: Mohr-Coulomb rock and CTCS keep the warning
      const bool held_crack_band = p.test == "UCS" && p.rock.model == sph::RockModel::hoek_brown &&
                                   p.platens.friction > 0 &&
                                   p.rock.softening_law == sph::SofteningLaw::fracture_energy &&
                                   p.rock.shear_fracture_energy_ratio >= 100;
      if ((p.test == "UCS" || p.test == "CTCS") && p.platens.steel.model == fem::SteelModel::elastic &&
          !p.platens.bonded && !held_crack_band && platen_diameter > p.diameter * (1 + 1e-9))
        result.warnings.push_back(
          "Platens/Diameter = " + keys::format(platen_diameter) +
          " m: on elastic platens wider than the specimen the peak does not converge in spacing (M1, "
          "Table 4's Mohr-Coulomb, body-fitted, 60 mm platens, default softening, 5 / 2.5 / 1.25 mm: "
          "244.6 / 187.2 / 161.9 MPa frictionless, 252.3 / 258.3 / 231.0 at friction 0.3; the closed "
          "form 282.2): the rim loads the rock unevenly, and with a dilation angle below the friction "
          "angle (non-associated flow) the FE reference's peak falls with its mesh too (278.3 / 263.5 "
          "MPa; 282.2 on every mesh with associated flow); quote a peak from platens of the "
          "specimen's diameter on rollers "
          "(Platens/Diameter = Test/Diameter, Platens/Loaded face = roller), or, with end friction, "
          "from the crack band of a shear fault's energy (Rock/Softening law = fracture energy, "
          "Rock/Shear fracture energy ratio = 100: converged on these platens)");
      const bool cutting    = p.test == "indentation" || p.test == "linear-cutting";
      // platen elements finer than the particles: the kinematic contact on elastic platens stays
      // stable on them (the held distance taken at the step's end), but the end layer fails early
      // (measured on UCS, body-fitted, on rollers: 5 mm particles on 2.5 mm elements 274.8 against
      // 281.3 MPa on 5 mm elements; 2.5 mm particles on 1.25 mm elements 260.3 against 282.9, the
      // first failure at 124.6 MPa in the end layer), and 1.25 mm elements under 5 mm particles
      // are unstable (an elastic rock too). BTS is refused alike, unmeasured
      // (cases/studies/platens/README.md)
      if (!cutting && p.platens.steel.model == fem::SteelModel::elastic &&
          coupling::contact_method(p) == coupling::ContactMethod::kinematic &&
          !p.platens.element_size_from_spacing && p.platens.steel.element_size < p.sph.spacing * (1 - 1e-9))
        throw InputError(r.origin("Platens/Element size") + ": Platens/Element size = " +
                         r.get("Platens/Element size") + " m is below SPH/Particle spacing = " +
                         r.get("SPH/Particle spacing") +
                         " m: on elastic platens meshed finer than the particles the kinematic contact's end layer "
                         "fails early (2.5 mm particles on 1.25 mm elements: 260.3 against 282.9 MPa); use "
                         "elements of at least the spacing");
      const double smallest = std::min(p.diameter, p.length);
      if (cutting)
        check_cutter(r, p, result.warnings);
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
      if (p.sph.tssfac > 1)
        result.warnings.push_back("SPH/TSSFAC = " + r.get("SPH/TSSFAC") + " is above 1: expect an unstable run");

      // used_parameters.prm: the final values, the group's included
      const keys::RockOverrides &o = d.overrides;
      d.set("Test", "Name", diagnose::escape_prm_value(p.name));
      d.set("Rock", "Youngs modulus", format(p.rock.youngs_modulus));
      d.set("Rock", "Poissons ratio", format(p.rock.poissons_ratio));
      d.set("Rock", "Cohesion", format(p.rock.cohesion));
      d.set("Rock", "Friction angle", format(o.friction_angle_deg.value_or(keys::friction_angle_degrees(p.rock))));
      d.set("Rock", "Tensile strength", format(p.rock.tensile_strength));
      d.set("Rock", "UCS", format(rc.ucs));
      d.set("Rock", "Data directory",
            diagnose::escape_prm_value(fs::absolute(data_directory).lexically_normal().string()));
      rc.data_directory = fs::absolute(data_directory).lexically_normal().string();
      std::ostringstream used;
      used << "# cosim " << version() << " (commit " << commit() << ")\n"
           << "# cosim: parameters used for case '" << p.name << "' (" << path << ")\n"
           << "# Rock values resolved from group " << rc.group << " ("
           << (rc.strength_source == "measured" ? "measured c, phi: Table 3"
               : rc.strength_source == "brazilian"
                 ? "c, phi calibrated to UCS and BTS at the disc centre's stress state"
               : rc.strength_source == "simulated" && p.rock.model == sph::RockModel::hoek_brown &&
                     p.rock.tensile_strength > 0
                 ? "Hoek-Brown envelope fitted to all its strengths, the tension cut-off with which the "
                   "simulator reproduces its BTS: simulator_calibrated.csv"
               : rc.strength_source == "simulated" && p.rock.model == sph::RockModel::hoek_brown
                 ? "Hoek-Brown envelope through its UCS, a = 1/2, the m_b with which the simulator "
                   "reproduces its BTS, no cut-off but the envelope's apex: simulator_calibrated.csv"
               : rc.strength_source == "simulated"
                 ? "c, phi with which the simulator reproduces its UCS and BTS: simulator_calibrated.csv"
               : rc.strength_source == "envelope" ? "Hoek-Brown envelope fitted to all its strengths"
                                                  : "calibrated c, phi: Table 4")
           << ") and explicit keys\n";
      if (p.rock.model == sph::RockModel::hoek_brown &&
          (rc.strength_source == "envelope" || rc.strength_source == "simulated"))
        used << "# Rock/Strength parameters = " << rc.strength_source << ": Hoek-Brown sigma_ci = " << format(p.rock.hb_sigma_ci)
             << " Pa, m_b = " << format(p.rock.hb_mb) << ", a = " << format(p.rock.hb_a)
             << ", tension cut-off " << format(p.rock.tensile_strength) << " Pa"
             << (p.rock.tensile_strength > 0 ? "" : " (none: the apex sigma_ci / m_b)") << "\n";
      d.prm.print_parameters(used, dealii::ParameterHandler::PRM);
      result.used_parameters = used.str();
    }
    catch (const InputError &e)
    {
      throw InputError(one_line(e.what())); // the contract: one line, whatever a value held
    }
    catch (const dealii::ExceptionBase &e)
    {
      throw InputError(path + ": " + one_line(info_of(e)));
    }
    return result;
  }
} // namespace app
