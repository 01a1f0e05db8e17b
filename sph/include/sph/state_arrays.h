#pragma once
/// @file
/// The state of a running simulation as named flat arrays of doubles: what a checkpoint holds.
/// The SPH body, the coupler and the drivers all save into and load from this one type.

#include <map>
#include <string>
#include <vector>

namespace sph
{
  /// Named flat arrays of doubles (checkpoints); each part adds its arrays under its own prefix,
  /// e.g. "body.x", "driver.scalars".
  using StateArrays = std::map<std::string, std::vector<double>>;
} // namespace sph
