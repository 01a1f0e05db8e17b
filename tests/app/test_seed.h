#pragma once
/// @file
/// The seed of a test that draws a random case (a random stop step, ...): a fixed one, so that
/// CI runs the same case every time and a failure repeats; COSIM_TEST_SEED=N in the environment
/// draws another case by hand (the tests print the seed they used).

#include <cstdlib>
#include <string>

namespace coupling::test
{
  inline unsigned test_seed(const unsigned fixed)
  {
    if (const char *s = std::getenv("COSIM_TEST_SEED"))
      return static_cast<unsigned>(std::stoul(s));
    return fixed;
  }
} // namespace coupling::test
