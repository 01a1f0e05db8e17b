// Declaring case-file keys: the Section helper and what the messages say a key accepts.
#include "case_keys.h"

#include <diagnose/csv.h>

#include <charconv>

namespace app::keys
{
  namespace
  {
    constexpr double pi = 3.14159265358979323846;

    /// A finite number or nothing (the group's value then applies).
    class OptionalDouble : public dealii::Patterns::PatternBase
    {
    public:
      bool match(const std::string &text) const override
      {
        return text.empty() || diagnose::parse_finite_double(text).has_value();
      }
      std::string description(const OutputStyle = Machine) const override { return "[Double or empty]"; }
      std::unique_ptr<dealii::Patterns::PatternBase> clone() const override
      {
        return std::make_unique<OptionalDouble>();
      }
    };
  } // namespace

  std::string format(double v)
  {
    char buffer[64];
    const auto r = std::to_chars(buffer, buffer + sizeof buffer, v);
    return std::string(buffer, r.ptr);
  }

  std::string Key::accepted() const
  {
    switch (kind)
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
        std::string out = "one of ";
        for (const char c : choices)
          out += c == '|' ? std::string(", ") : std::string(1, c);
        return out;
      }
      case Kind::text:
        return "any text";
    }
    return {};
  }

  Section::Section(dealii::ParameterHandler &prm, std::vector<Key> &keys, const std::string &name)
    : prm_(prm)
    , keys_(keys)
    , name_(name)
  {
    prm_.enter_subsection(name_);
  }

  Section::~Section() { prm_.leave_subsection(); }

  void Section::record(const std::string &name, const std::string &doc, const Kind kind,
                       const std::string &choices, std::function<std::string()> check)
  {
    Key k;
    k.section = name_;
    k.name    = name;
    k.doc     = doc;
    k.kind    = kind;
    k.choices = choices;
    switch (kind)
    {
      case Kind::real:
        k.pattern = std::make_shared<dealii::Patterns::Double>();
        break;
      case Kind::optional_real:
        k.pattern = std::make_shared<OptionalDouble>();
        break;
      case Kind::integer:
        k.pattern = std::make_shared<dealii::Patterns::Integer>();
        break;
      case Kind::boolean:
        k.pattern = std::make_shared<dealii::Patterns::Bool>();
        break;
      case Kind::selection:
        k.pattern = std::make_shared<dealii::Patterns::Selection>(choices);
        break;
      case Kind::text:
        k.pattern = std::make_shared<dealii::Patterns::Anything>();
        break;
    }
    k.check = std::move(check);
    keys_.push_back(std::move(k));
  }

  void Section::add_choice(const std::string &name, std::string &member, const std::string &choices,
                           const std::string &doc, std::function<std::string()> check)
  {
    prm_.add_parameter(name, member, doc, dealii::Patterns::Selection(choices));
    record(name, doc, Kind::selection, choices, std::move(check));
  }

  void Section::add_degrees(const std::string &name, double &member, const std::string &doc,
                            std::function<bool(double)> ok_deg, const std::string &must)
  {
    // the default in degrees; a value read converts to radians here, once
    prm_.declare_entry(name, format(member * 180.0 / pi), dealii::Patterns::Double(), doc);
    prm_.add_action(name, [&member](const std::string &v) {
      if (const auto d = diagnose::parse_finite_double(v))
        member = *d * pi / 180.0;
    });
    record(name, doc, Kind::real, "",
           [&member, ok_deg, must]() { return ok_deg(member * 180.0 / pi) ? std::string() : must; });
  }

  void Section::add_optional(const std::string &name, std::optional<double> &member, const std::string &doc)
  {
    prm_.declare_entry(name, member ? format(*member) : "", OptionalDouble(), doc);
    prm_.add_action(name, [&member](const std::string &v) { member = diagnose::parse_finite_double(v); });
    record(name, doc, Kind::optional_real, "", {});
  }

  void Section::add_real(const std::string &name, const std::string &default_text,
                         std::function<void(double)> set, const std::string &doc)
  {
    prm_.declare_entry(name, default_text, dealii::Patterns::Double(), doc);
    prm_.add_action(name, [set](const std::string &v) {
      if (const auto d = diagnose::parse_finite_double(v))
        set(*d);
    });
    record(name, doc, Kind::real, "", {});
  }

  void Section::check(const std::string &name, std::function<std::string()> check)
  {
    for (auto &k : keys_)
      if (k.section == name_ && k.name == name)
      {
        const auto own = k.check;
        k.check = own ? std::function<std::string()>([own, check]() {
          const std::string a = own();
          return a.empty() ? check() : a;
        })
                      : check;
      }
  }
} // namespace app::keys
