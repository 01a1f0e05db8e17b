#pragma once
// The message contract every fuzz target checks: an InputError is one non-empty line of valid
// UTF-8, short whatever the input held (clipped echoes); anything else aborts (a finding).
#include <coupling/errors.h>
#include <diagnose/text_input.h>

#include <cstdlib>
#include <string>

namespace cosim_fuzz
{
  inline void check_message(const coupling::InputError &e)
  {
    const std::string what = e.what();
    if (what.empty() || what.find('\n') != std::string::npos || what.size() > 2000 ||
        diagnose::invalid_utf8_at(what).has_value() || what.find('\0') != std::string::npos)
      std::abort();
  }
} // namespace cosim_fuzz
