#include <app/cli.h>
#include <diagnose/csv.h>
#include <diagnose/text_input.h>
#include <coupling/run_case.h>

#include <algorithm>
#include <cctype>

namespace app
{
  using diagnose::parse_finite_double;
  using coupling::InputError;

  std::size_t edit_distance(const std::string &a, const std::string &b)
  {
    std::vector<std::size_t> row(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j)
      row[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i)
    {
      std::size_t diagonal = row[0];
      row[0] = i;
      for (std::size_t j = 1; j <= b.size(); ++j)
      {
        const std::size_t above = row[j];
        const bool same = std::tolower(static_cast<unsigned char>(a[i - 1])) ==
                          std::tolower(static_cast<unsigned char>(b[j - 1]));
        row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (same ? 0 : 1)});
        diagonal = above;
      }
    }
    return row[b.size()];
  }

  std::string nearest_name(const std::string &name, const std::vector<std::string> &candidates)
  {
    std::string best;
    std::size_t best_distance = std::string::npos;
    for (const auto &c : candidates)
    {
      const std::size_t d = edit_distance(name, c);
      if (d < best_distance)
        best = c, best_distance = d;
    }
    // close enough: at most a third of the longer name differs (always allow 2 edits)
    const std::size_t limit = std::max<std::size_t>(2, std::max(name.size(), best.size()) / 3);
    return best_distance <= limit ? best : std::string();
  }

  std::string did_you_mean(const std::string &name, const std::vector<std::string> &candidates)
  {
    const std::string best = nearest_name(name, candidates);
    return best.empty() ? std::string() : " (did you mean '" + best + "'?)";
  }

  ArgumentCursor::ArgumentCursor(const std::string &command, const std::vector<std::string> &args)
    : command_(command)
    , args_(args)
  {}

  std::string ArgumentCursor::option_name(const std::string &argument)
  {
    if (argument.rfind("--", 0) == 0)
    {
      const auto eq = argument.find('=');
      if (eq != std::string::npos)
        return argument.substr(0, eq);
    }
    return argument;
  }

  std::string ArgumentCursor::next()
  {
    std::string a = args_.at(i_++);
    has_pending_value_ = false;
    if (a.rfind("--", 0) == 0)
    {
      const auto eq = a.find('=');
      if (eq != std::string::npos)
      {
        pending_value_ = a.substr(eq + 1);
        has_pending_value_ = true;
        a = a.substr(0, eq);
      }
    }
    return a;
  }

  std::string ArgumentCursor::value(const std::string &option)
  {
    std::string v;
    if (has_pending_value_)
    {
      has_pending_value_ = false;
      v                  = pending_value_;
    }
    else if (done())
      throw InputError("cosim " + command_ + ": option " + option + " needs a value (see cosim " +
                       command_ + " --help)");
    else
      v = args_[i_++];
    // an empty value is never meant: refuse it rather than fall back to a default silently
    if (diagnose::trim(v).empty())
      throw InputError("cosim " + command_ + ": option " + option + " has an empty value (see cosim " + command_ +
                       " --help)");
    return v;
  }

  double ArgumentCursor::number(const std::string &option)
  {
    const std::string text = value(option);
    const auto v = parse_finite_double(text);
    if (!v)
      throw InputError("cosim " + command_ + ": " + option + " '" + diagnose::clip(text) +
                       "' is not a finite number (see cosim " + command_ + " --help)");
    return *v;
  }
} // namespace app
