#pragma once
/// @file
/// Declaring the case-file keys, ParameterAcceptor style: each key is bound to the member of
/// CaseParameters it sets (deal.II's ParameterHandler::add_parameter), its default is that member's
/// value, and the check of its range sits beside it. One `declare_*_keys` function per section,
/// each in its own app/src/*_keys.cc; case_file.cc assembles them. Internal to app/src: only the
/// key files and case_file.cc include deal.II.

#include <coupling/case_parameters.h>

#include <deal.II/base/parameter_handler.h>

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace app::keys
{
  /// What a key accepts, for the messages.
  enum class Kind
  {
    real,          ///< a finite number
    optional_real, ///< a finite number, or empty for the value of Rock/Group
    integer,
    boolean,
    selection, ///< one of `choices`
    text
  };

  /// One declared key, as the messages and `--set` need it.
  struct Key
  {
    std::string section;
    std::string name;
    std::string doc;
    Kind kind = Kind::text;
    std::string choices; ///< selection: "a|b|c"
    std::shared_ptr<const dealii::Patterns::PatternBase> pattern;
    /// Range check, run after the case is read: empty when the value is fine, else what it must
    /// be ("must be > 0 m"). Absent: any value of the type.
    std::function<std::string()> check;

    std::string full() const { return section + "/" + name; }
    /// "a finite number", "one of UCS, BTS", ...
    std::string accepted() const;
  };

  /// The rock keys that default to the group's value (empty in the case file). Angles in
  /// degrees, as written.
  struct RockOverrides
  {
    std::optional<double> youngs_modulus, poissons_ratio, cohesion, friction_angle_deg,
      tensile_strength, ucs, residual_friction_angle_deg, hb_mi, hb_a;
  };

  /// Declares the keys of one section into a ParameterHandler and records them in `keys`.
  /// Enters the subsection on construction, leaves it on destruction.
  class Section
  {
  public:
    Section(dealii::ParameterHandler &prm, std::vector<Key> &keys, const std::string &name);
    ~Section();
    Section(const Section &) = delete;
    Section &operator=(const Section &) = delete;

    /// A number, integer, flag or text bound to `member`; `ok` is its range and `must` what the
    /// message says when the value is outside it.
    template <class T>
    void add(const std::string &name, T &member, const std::string &doc,
             std::function<bool(const T &)> ok = {}, const std::string &must = "");
    /// Text out of `choices` ("a|b|c") bound to `member`.
    void add_choice(const std::string &name, std::string &member, const std::string &choices,
                    const std::string &doc, std::function<std::string()> check = {});
    /// An enum shown as text: `names` ("a|b|c") in the order of `values`.
    template <class E>
    void add_enum(const std::string &name, E &member, const std::string &names,
                  const std::vector<E> &values, const std::string &doc);
    /// An angle stored in radians in `member`, written in degrees.
    void add_degrees(const std::string &name, double &member, const std::string &doc,
                     std::function<bool(double)> ok_deg, const std::string &must);
    /// A number that may be left empty (then the group's value applies).
    void add_optional(const std::string &name, std::optional<double> &member, const std::string &doc);
    /// A real number whose text `set` turns into the members it stands for.
    void add_real(const std::string &name, const std::string &default_text,
                  std::function<void(double)> set, const std::string &doc);
    /// A check across keys, reported against this key.
    void check(const std::string &name, std::function<std::string()> check);

  private:
    void record(const std::string &name, const std::string &doc, Kind kind, const std::string &choices,
                std::function<std::string()> check);
    dealii::ParameterHandler &prm_;
    std::vector<Key> &keys_;
    std::string name_;
  };

  template <class T>
  void Section::add(const std::string &name, T &member, const std::string &doc,
                    std::function<bool(const T &)> ok, const std::string &must)
  {
    Kind kind = Kind::text;
    std::unique_ptr<dealii::Patterns::PatternBase> pattern;
    if constexpr (std::is_same_v<T, bool>)
    {
      kind    = Kind::boolean;
      pattern = std::make_unique<dealii::Patterns::Bool>();
    }
    else if constexpr (std::is_integral_v<T>)
    {
      kind    = Kind::integer;
      pattern = std::make_unique<dealii::Patterns::Integer>();
    }
    else if constexpr (std::is_floating_point_v<T>)
    {
      kind    = Kind::real;
      pattern = std::make_unique<dealii::Patterns::Double>();
    }
    else
      pattern = std::make_unique<dealii::Patterns::Anything>();
    prm_.add_parameter(name, member, doc, *pattern);
    std::function<std::string()> check;
    if (ok)
      check = [ok, &member, must]() { return ok(member) ? std::string() : must; };
    record(name, doc, kind, "", check);
  }

  template <class E>
  void Section::add_enum(const std::string &name, E &member, const std::string &names,
                         const std::vector<E> &values, const std::string &doc)
  {
    std::vector<std::string> text;
    for (std::size_t b = 0, e; b <= names.size(); b = e + 1)
    {
      e = names.find('|', b);
      if (e == std::string::npos)
        e = names.size();
      text.push_back(names.substr(b, e - b));
    }
    std::string current;
    for (std::size_t i = 0; i < values.size(); ++i)
      if (values[i] == member)
        current = text[i];
    prm_.declare_entry(name, current, dealii::Patterns::Selection(names), doc);
    prm_.add_action(name, [&member, text, values](const std::string &v) {
      for (std::size_t i = 0; i < values.size(); ++i)
        if (text[i] == v)
          member = values[i];
    });
    record(name, doc, Kind::selection, names, {});
  }

  /// The shortest text that reads back as the same double.
  std::string format(double v);

  // One function per section of the case file, each in its <section>_keys.cc.
  void declare_test_keys(Section &s, coupling::CaseParameters &p);
  void declare_rock_keys(Section &s, coupling::CaseParameters &p, RockOverrides &o);
  void declare_sph_keys(Section &s, coupling::CaseParameters &p);
  void declare_platen_keys(Section &s, coupling::CaseParameters &p);
  void declare_loading_keys(Section &s, coupling::CaseParameters &p);
  void declare_cutter_keys(Section &s, coupling::CaseParameters &p);
  void declare_output_keys(Section &s, coupling::CaseParameters &p);
} // namespace app::keys

namespace diagnose
{
  class MaterialTable;
  struct MaterialGroup;
} // namespace diagnose

namespace app::keys
{
  /// Fills the rock keys left empty from the group (c, phi by Rock/Strength parameters); the
  /// friction angle taken from the group goes into `o` too, in degrees as the table writes it.
  /// `fail(key, what)` throws the message for a key.
  void resolve_rock(coupling::CaseParameters &p, RockOverrides &o, const diagnose::MaterialTable &table,
                    const diagnose::MaterialGroup &group,
                    const std::function<void(const std::string &, const std::string &)> &fail);
  /// The friction angle in degrees, as the case file writes it.
  double friction_angle_degrees(const sph::MaterialParameters &m);
} // namespace app::keys
