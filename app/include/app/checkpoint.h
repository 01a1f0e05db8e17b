#pragma once
/// @file
/// checkpoint.h5: the full state of a running case (StateArrays) in HDF5, one 1-D double dataset
/// per array at the root, named as the array (e.g. "body.x", "driver.history"), plus the root
/// attribute `cosim_checkpoint_version`. Doubles are stored bit for bit, so a restart from the
/// file continues exactly as from the state in memory.

#include <coupling/run_output.h>

#include <string>

namespace app
{
  /// Version written into every checkpoint; read_checkpoint refuses others.
  /// 2: fem::SteelBody scalars gained the rigid x velocity and the frame force vector (disc cutter).
  constexpr int checkpoint_version = 2;

  /// Writes `state` to `path` atomically (a temporary file renamed over `path`, so that a crash
  /// while writing leaves the previous checkpoint intact). std::runtime_error on I/O errors.
  void write_checkpoint(const std::string &path, const coupling::StateArrays &state);

  /// Reads a checkpoint. InputError (one line naming the file) when it is missing, unreadable,
  /// not a cosim checkpoint or of another version.
  coupling::StateArrays read_checkpoint(const std::string &path);
} // namespace app
