#pragma once
/// @file
/// checkpoint.h5: the full state of a running case (StateArrays) in HDF5, one 1-D double dataset
/// per array at the root, named as the array (e.g. "body.x", "driver.history"), plus the root
/// attribute `cosim_checkpoint_version`. Doubles are stored bit for bit, so a restart from the
/// file continues exactly as from the state in memory.
///
/// Integrity: every dataset carries the attribute `fnv1a64`, the 64-bit FNV-1a checksums of
/// consecutive blocks of its bytes (one block, or one per rank that wrote it), with the blocks'
/// bounds in `fnv1a64_bounds` (value offsets); the root carries `cosim_version` (version and commit
/// of the program that wrote it) and `used_parameters` (the case as used_parameters.prm holds it).
/// read_checkpoint refuses a file whose data fail their checksum, written by another program
/// version, or (when given the case) written for another case, saying what differs.

#include <coupling/run_output.h>

#include <cstdint>
#include <string>

namespace app
{
  /// Version written into every checkpoint; read_checkpoint refuses others.
  /// 2: fem::SteelBody scalars gained the rigid x velocity and the frame force vector (disc cutter).
  /// 3: per-dataset checksums and the case and program identity.
  /// 4: a checksum per block of each dataset (written by several ranks together).
  /// 5: the rock's `cracked` flags (hourglass control dropped across tensile cracks).
  constexpr int checkpoint_version = 5;

  /// Writes `state` to `path` atomically (a temporary file renamed over `path`, so that a crash
  /// while writing leaves the previous checkpoint intact). std::runtime_error on I/O errors.
  /// `used_parameters`: the case's used_parameters.prm text, stored for the restart check.
  /// A distributed run (`rows` given): called by every rank with its rows (coupling::StateRows);
  /// the file then holds the whole arrays in global order, written by all ranks together with
  /// parallel HDF5 (rank 0's `path` and `used_parameters` count), and restarts on any number of
  /// ranks. Collective.
  void write_checkpoint(const std::string &path, const coupling::StateArrays &state,
                        const std::string &used_parameters = "",
                        const coupling::StateRows *rows = nullptr);

  /// Reads a checkpoint. InputError (one line naming the file) when it is missing, unreadable,
  /// not a cosim checkpoint or of another version, when a dataset fails its checksum, when it was
  /// written by another program version, and, when `used_parameters` is given (the text of the
  /// restart folder's used_parameters.prm), when it was written for another case: the message
  /// names the first key that differs and both values.
  coupling::StateArrays read_checkpoint(const std::string &path, const std::string *used_parameters = nullptr);

  /// 64-bit FNV-1a checksum of `n` bytes.
  std::uint64_t fnv1a64(const void *data, std::size_t n);
} // namespace app
