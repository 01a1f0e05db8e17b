#include <app/checkpoint.h>
#include <app/paths.h>
#include <coupling/run_case.h>
#include <diagnose/csv.h>
#include <diagnose/text_input.h>

#include "block_rows.h"

#include <hdf5.h>
#include <mpi.h>

#include <algorithm>
#include <cstdio>
#include <optional>
#include <filesystem>
#include <sstream>
#include <stdexcept>

namespace app
{
  using coupling::InputError;
  using coupling::StateArrays;
  using coupling::StateRows;
  using diagnose::clip;

  namespace
  {
    /// HDF5 prints its own error stack by default; our messages say what failed.
    void silence_hdf5()
    {
      H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    }

    std::string program_identity()
    {
      return version() + " (commit " + commit() + ")";
    }

    bool write_attribute(const hid_t object, const char *name, const hid_t type, const void *value)
    {
      const hid_t space = H5Screate(H5S_SCALAR);
      const hid_t attr  = H5Acreate2(object, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
      const bool ok     = attr >= 0 && H5Awrite(attr, type, value) >= 0;
      if (attr >= 0)
        H5Aclose(attr);
      H5Sclose(space);
      return ok;
    }

    bool write_string_attribute(const hid_t object, const char *name, const std::string &text)
    {
      const hid_t type = H5Tcopy(H5T_C_S1);
      H5Tset_size(type, std::max<std::size_t>(text.size(), 1));
      H5Tset_strpad(type, H5T_STR_NULLPAD);
      const std::string padded = text.empty() ? std::string(1, '\0') : text;
      const bool ok             = write_attribute(object, name, type, padded.data());
      H5Tclose(type);
      return ok;
    }

    /// A string attribute, or nothing when absent or unreadable.
    std::optional<std::string> read_string_attribute(const hid_t object, const char *name)
    {
      if (H5Aexists(object, name) <= 0)
        return std::nullopt;
      const hid_t attr = H5Aopen(object, name, H5P_DEFAULT);
      if (attr < 0)
        return std::nullopt;
      const hid_t type = H5Aget_type(attr);
      std::optional<std::string> out;
      if (type >= 0 && H5Tget_class(type) == H5T_STRING && !H5Tis_variable_str(type))
      {
        const std::size_t n = H5Tget_size(type);
        std::string text(n, '\0');
        const hid_t memory = H5Tcopy(H5T_C_S1);
        H5Tset_size(memory, n);
        H5Tset_strpad(memory, H5T_STR_NULLPAD);
        if (H5Aread(attr, memory, text.data()) >= 0)
        {
          const auto end = text.find('\0');
          out            = end == std::string::npos ? text : text.substr(0, end);
        }
        H5Tclose(memory);
      }
      if (type >= 0)
        H5Tclose(type);
      H5Aclose(attr);
      return out;
    }

    /// A 1-D unsigned 64-bit attribute (of at most 2^20 values), or nothing when absent or
    /// unreadable.
    std::optional<std::vector<std::uint64_t>> read_uint64_attribute(const hid_t object, const char *name)
    {
      if (H5Aexists(object, name) <= 0)
        return std::nullopt;
      const hid_t attr = H5Aopen(object, name, H5P_DEFAULT);
      if (attr < 0)
        return std::nullopt;
      std::optional<std::vector<std::uint64_t>> out;
      const hid_t space = H5Aget_space(attr);
      const int   rank  = space >= 0 ? H5Sget_simple_extent_ndims(space) : -1;
      hsize_t     n     = 1;
      if (rank == 0 || (rank == 1 && H5Sget_simple_extent_dims(space, &n, nullptr) >= 0 && n <= (1u << 20)))
      {
        std::vector<std::uint64_t> values(n);
        if (H5Aread(attr, H5T_NATIVE_UINT64, values.data()) >= 0)
          out = std::move(values);
      }
      if (space >= 0)
        H5Sclose(space);
      H5Aclose(attr);
      return out;
    }

    /// "Section/Key" -> value of every `set` line of a used_parameters.prm text.
    std::vector<std::pair<std::string, std::string>> settings(const std::string &prm)
    {
      std::vector<std::pair<std::string, std::string>> out;
      std::vector<std::string> sections;
      std::istringstream in(prm);
      std::string line;
      while (std::getline(in, line))
      {
        const std::string t = diagnose::trim(diagnose::strip_prm_comment(line));
        if (t.rfind("subsection ", 0) == 0)
          sections.push_back(diagnose::trim(t.substr(11)));
        else if (t == "end" && !sections.empty())
          sections.pop_back();
        else if (t.rfind("set ", 0) == 0)
        {
          const auto eq = t.find('=');
          std::string key = diagnose::trim(t.substr(4, eq == std::string::npos ? std::string::npos : eq - 4));
          std::string prefix;
          for (const auto &s : sections)
            prefix += s + "/";
          out.emplace_back(prefix + key, eq == std::string::npos ? "" : diagnose::trim(t.substr(eq + 1)));
        }
      }
      return out;
    }

    /// What differs between the case a checkpoint was written for and the case now: the first
    /// differing key with both values, or "" when the settings agree.
    std::string case_difference(const std::string &stored, const std::string &now)
    {
      const auto a = settings(stored), b = settings(now);
      for (const auto &[key, value] : a)
      {
        std::string other;
        bool found = false;
        for (const auto &[k, v] : b)
          if (k == key)
            other = v, found = true;
        if (!found)
          return key + " is missing from used_parameters.prm";
        if (other != value)
          return key + " = '" + clip(other, 60) + "' in used_parameters.prm, '" + clip(value, 60) +
                 "' in the checkpoint";
      }
      for (const auto &[key, value] : b)
      {
        bool found = false;
        for (const auto &kv : a)
          found = found || kv.first == key;
        if (!found)
          return key + " is in used_parameters.prm but not in the checkpoint's case";
      }
      if (stored != now)
        return "the text of used_parameters.prm differs from the checkpoint's case";
      return "";
    }
  } // namespace

  std::uint64_t fnv1a64(const void *data, const std::size_t n)
  {
    std::uint64_t hash   = 1469598103934665603ull;
    const auto *bytes    = static_cast<const unsigned char *>(data);
    for (std::size_t i = 0; i < n; ++i)
      hash = (hash ^ bytes[i]) * 1099511628211ull;
    return hash;
  }

  namespace
  {
    /// The checksum attributes of a dataset: the FNV-1a checksums of consecutive blocks of its
    /// values and the blocks' bounds (value offsets, one more than the checksums).
    bool write_checksums(const hid_t set, const std::vector<std::uint64_t> &sums,
                         const std::vector<std::uint64_t> &bounds)
    {
      bool ok = true;
      for (const auto &[name, values] : {std::pair<const char *, const std::vector<std::uint64_t> *>{"fnv1a64", &sums},
                                         {"fnv1a64_bounds", &bounds}})
      {
        const hsize_t n     = values->size();
        const hid_t   space = H5Screate_simple(1, &n, nullptr);
        const hid_t   attr  = H5Acreate2(set, name, H5T_NATIVE_UINT64, space, H5P_DEFAULT, H5P_DEFAULT);
        ok = ok && attr >= 0 && H5Awrite(attr, H5T_NATIVE_UINT64, values->data()) >= 0;
        if (attr >= 0)
          H5Aclose(attr);
        H5Sclose(space);
      }
      return ok;
    }

    /// The file's attributes and every whole array of `state` (all of them without `rows`); with
    /// `rows`, the datasets of the row arrays made at their whole size, not written.
    bool write_header_and_whole_arrays(const hid_t file, const StateArrays &state,
                                       const std::string &used_parameters, const StateRows *rows)
    {
      bool ok = write_attribute(file, "cosim_checkpoint_version", H5T_NATIVE_INT, &checkpoint_version) &&
                write_string_attribute(file, "cosim_version", program_identity()) &&
                write_string_attribute(file, "used_parameters", used_parameters);
      for (const auto &[name, values] : state)
      {
        if (!ok)
          break;
        const bool whole = !rows || rows->width.count(name) == 0;
        const hsize_t n  = whole ? values.size() : rows->n_global * static_cast<hsize_t>(rows->width.at(name));
        const hid_t space = H5Screate_simple(1, &n, nullptr);
        const hid_t plist = H5Pcreate(H5P_DATASET_CREATE);
        if (!whole) // every rank writes its block into it (contiguous, allocated now)
        {
          H5Pset_alloc_time(plist, H5D_ALLOC_TIME_EARLY);
          H5Pset_fill_time(plist, H5D_FILL_TIME_NEVER);
        }
        const hid_t set = H5Dcreate2(file, name.c_str(), H5T_IEEE_F64LE, space, H5P_DEFAULT, plist, H5P_DEFAULT);
        H5Pclose(plist);
        ok = set >= 0;
        if (ok && whole)
          ok = (n == 0 || H5Dwrite(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) >= 0) &&
               write_checksums(set, {fnv1a64(values.data(), values.size() * sizeof(double))}, {0, n});
        if (set >= 0)
          H5Dclose(set);
        H5Sclose(space);
      }
      return ok;
    }

    /// Renames `tmp` over `path`, or removes it; false when anything failed.
    bool commit_file(const std::string &tmp, const std::string &path, const bool ok)
    {
      std::error_code ec;
      if (ok)
        std::filesystem::rename(tmp, path, ec);
      if (!ok || ec)
        std::filesystem::remove(tmp, ec);
      return ok && !ec;
    }

    /// The distributed writer (see write_checkpoint). Collective over MPI_COMM_WORLD.
    bool write_rows_collectively(std::string path, const StateArrays &state, std::string used_parameters,
                                 const StateRows &rows)
    {
      const MPI_Comm comm = MPI_COMM_WORLD;
      int rank = 0, size = 1;
      MPI_Comm_rank(comm, &rank);
      MPI_Comm_size(comm, &size);
      broadcast(path, comm);
      broadcast(used_parameters, comm);
      const std::string tmp = path + ".tmp";
      // rank 0: the header, the whole arrays and the row datasets, then the file closed
      int ok = 1;
      if (rank == 0)
      {
        const hid_t file = H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
        ok = file >= 0 && write_header_and_whole_arrays(file, state, used_parameters, &rows);
        ok = (file >= 0 && H5Fclose(file) >= 0) && ok;
      }
      MPI_Bcast(&ok, 1, MPI_INT, 0, comm);
      if (!ok)
      {
        if (rank == 0)
          commit_file(tmp, path, false);
        return false;
      }
      // every rank: its rows of all row arrays in one exchange, into contiguous blocks
      std::vector<const std::vector<double> *> arrays;
      std::vector<std::size_t> widths;
      std::size_t total = 0;
      for (const auto &[name, width] : rows.width) // (the same names on every rank)
      {
        const auto it = state.find(name);
        if (it == state.end() || it->second.size() != rows.global_index.size() * width)
          throw std::logic_error("write_checkpoint: " + name + " is not this rank's rows");
        arrays.push_back(&it->second);
        widths.push_back(static_cast<std::size_t>(width));
        total += static_cast<std::size_t>(width);
      }
      std::vector<double> packed;
      packed.reserve(total * rows.global_index.size());
      for (std::size_t i = 0; i < rows.global_index.size(); ++i)
        for (std::size_t a = 0; a < arrays.size(); ++a)
          packed.insert(packed.end(), arrays[a]->begin() + widths[a] * i, arrays[a]->begin() + widths[a] * (i + 1));
      const std::vector<double> block = rows_in_blocks(packed, total, rows.global_index, rows.n_global, comm);
      const std::size_t first = block_start(rows.n_global, rank, size);
      const std::size_t n_rows = block.size() / std::max<std::size_t>(total, 1);
      // all ranks open the file with MPI-IO and write their blocks, collectively
      const hid_t access = H5Pcreate(H5P_FILE_ACCESS);
      H5Pset_fapl_mpio(access, comm, MPI_INFO_NULL);
      const hid_t file = H5Fopen(tmp.c_str(), H5F_ACC_RDWR, access);
      H5Pclose(access);
      int written = file >= 0;
      MPI_Allreduce(MPI_IN_PLACE, &written, 1, MPI_INT, MPI_MIN, comm);
      std::vector<std::uint64_t> sums;
      if (written)
      {
        const hid_t transfer = H5Pcreate(H5P_DATASET_XFER);
        H5Pset_dxpl_mpio(transfer, H5FD_MPIO_COLLECTIVE);
        std::size_t column = 0, a = 0;
        for (const auto &[name, width] : rows.width)
        {
          const std::size_t w = widths[a++];
          std::vector<double> mine(n_rows * w);
          for (std::size_t k = 0; k < n_rows; ++k)
            std::copy_n(block.begin() + k * total + column, w, mine.begin() + k * w);
          column += w;
          sums.push_back(fnv1a64(mine.data(), mine.size() * sizeof(double)));
          const hid_t set = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
          const hid_t file_space = set >= 0 ? H5Dget_space(set) : -1;
          const hsize_t start = first * w, count = mine.size();
          const hid_t memory = H5Screate_simple(1, &count, nullptr);
          if (count > 0 && file_space >= 0)
            H5Sselect_hyperslab(file_space, H5S_SELECT_SET, &start, nullptr, &count, nullptr);
          else
          {
            if (file_space >= 0)
              H5Sselect_none(file_space);
            H5Sselect_none(memory);
          }
          if (set < 0 || file_space < 0 ||
              H5Dwrite(set, H5T_NATIVE_DOUBLE, memory, file_space, transfer, mine.data()) < 0)
            written = 0;
          H5Sclose(memory);
          if (file_space >= 0)
            H5Sclose(file_space);
          if (set >= 0)
            H5Dclose(set);
        }
        H5Pclose(transfer);
        written = H5Fclose(file) >= 0 && written;
      }
      MPI_Allreduce(MPI_IN_PLACE, &written, 1, MPI_INT, MPI_MIN, comm);
      // rank 0: every block's checksum beside its dataset, then the file renamed over `path`
      const int n_sums = static_cast<int>(rows.width.size());
      sums.resize(rows.width.size(), 0);
      std::vector<std::uint64_t> all(rank == 0 ? static_cast<std::size_t>(n_sums) * size : 0);
      MPI_Gather(sums.data(), n_sums, MPI_UINT64_T, all.data(), n_sums, MPI_UINT64_T, 0, comm);
      if (rank == 0)
      {
        const hid_t file = written ? H5Fopen(tmp.c_str(), H5F_ACC_RDWR, H5P_DEFAULT) : -1;
        ok = file >= 0;
        std::size_t a = 0;
        for (const auto &[name, width] : rows.width)
        {
          if (!ok)
            break;
          std::vector<std::uint64_t> block_sums, bounds;
          for (int r = 0; r < size; ++r)
          {
            block_sums.push_back(all[static_cast<std::size_t>(r) * n_sums + a]);
            bounds.push_back(block_start(rows.n_global, r, size) * widths[a]);
          }
          bounds.push_back(rows.n_global * widths[a]);
          ++a;
          const hid_t set = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
          ok = set >= 0 && write_checksums(set, block_sums, bounds);
          if (set >= 0)
            H5Dclose(set);
        }
        ok = (file >= 0 && H5Fclose(file) >= 0) && ok;
        ok = commit_file(tmp, path, ok);
      }
      MPI_Bcast(&ok, 1, MPI_INT, 0, comm);
      return ok;
    }
  } // namespace

  void write_checkpoint(const std::string &path, const StateArrays &state, const std::string &used_parameters,
                        const StateRows *rows)
  {
    silence_hdf5();
    if (rows)
    {
      if (!write_rows_collectively(path, state, used_parameters, *rows))
        throw std::runtime_error("checkpoint: cannot write " + clip(path) + " (disk full or not writable?)");
      return;
    }
    const std::string tmp = path + ".tmp";
    const hid_t file      = H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    if (file < 0)
      throw std::runtime_error("checkpoint: cannot create " + clip(tmp) + " (disk full or not writable?)");
    bool ok = write_header_and_whole_arrays(file, state, used_parameters, nullptr);
    ok      = H5Fclose(file) >= 0 && ok;
    if (!commit_file(tmp, path, ok))
      throw std::runtime_error("checkpoint: cannot write " + clip(path) + " (disk full or not writable?)");
  }

  StateArrays read_checkpoint(const std::string &path, const std::string *used_parameters)
  {
    silence_hdf5();
    const std::string shown = clip(path);
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
      throw InputError("checkpoint " + shown +
                       ": no such file; --restart DIR needs a DIR with checkpoint.h5 and "
                       "used_parameters.prm (a run stopped by a signal or with "
                       "Output/Checkpoint interval set)");
    const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    if (file < 0)
      throw InputError("checkpoint " + shown + ": not a readable HDF5 file (damaged or truncated)");
    StateArrays state;
    std::string error;
    int version      = -1;
    const hid_t attr = H5Aopen(file, "cosim_checkpoint_version", H5P_DEFAULT);
    if (attr < 0 || H5Aread(attr, H5T_NATIVE_INT, &version) < 0)
      error = "not a cosim checkpoint (no cosim_checkpoint_version attribute)";
    else if (version != checkpoint_version)
      error = "checkpoint version " + std::to_string(version) + ", this cosim reads version " +
              std::to_string(checkpoint_version);
    if (attr >= 0)
      H5Aclose(attr);
    if (error.empty())
    {
      const auto written_by = read_string_attribute(file, "cosim_version");
      if (!written_by)
        error = "no cosim_version attribute (damaged?)";
      else if (*written_by != program_identity())
        error = "written by cosim " + clip(*written_by, 60) + ", this is cosim " + program_identity() +
                "; a checkpoint continues only in the program that wrote it (start the run again)";
    }
    if (error.empty() && used_parameters)
    {
      const auto stored = read_string_attribute(file, "used_parameters");
      if (!stored)
        error = "no used_parameters attribute (damaged?)";
      else if (const std::string what = case_difference(*stored, *used_parameters); !what.empty())
        error = "written for another case: " + what +
                "; restore the folder's used_parameters.prm or start the run again";
    }
    H5G_info_t info{};
    if (error.empty() && H5Gget_info(file, &info) < 0)
      error = "cannot list its datasets";
    for (hsize_t k = 0; error.empty() && k < info.nlinks; ++k)
    {
      const ssize_t len =
        H5Lget_name_by_idx(file, ".", H5_INDEX_NAME, H5_ITER_INC, k, nullptr, 0, H5P_DEFAULT);
      if (len <= 0)
      {
        error = "cannot read a dataset name";
        break;
      }
      std::string name(static_cast<std::size_t>(len), '\0');
      H5Lget_name_by_idx(file, ".", H5_INDEX_NAME, H5_ITER_INC, k, name.data(), len + 1,
                         H5P_DEFAULT);
      const hid_t set = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
      if (set < 0)
      {
        error = "cannot open dataset " + clip(name, 60);
        break;
      }
      const hid_t space = H5Dget_space(set);
      hsize_t n         = 0;
      if (space < 0 || H5Sget_simple_extent_ndims(space) != 1 ||
          H5Sget_simple_extent_dims(space, &n, nullptr) < 0)
        error = "dataset " + clip(name, 60) + " is not a 1-D array";
      else if (n > (hsize_t(1) << 34))
        error = "dataset " + clip(name, 60) + " claims " + std::to_string(n) + " values (damaged)";
      std::vector<double> values;
      if (error.empty())
        values.resize(n);
      if (error.empty() && n > 0 &&
          H5Dread(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) < 0)
        error = "cannot read dataset " + clip(name, 60) + " (damaged)";
      if (error.empty())
      {
        const auto sums = read_uint64_attribute(set, "fnv1a64");
        const auto bounds = read_uint64_attribute(set, "fnv1a64_bounds");
        bool valid = sums && bounds && !sums->empty() && bounds->size() == sums->size() + 1 &&
                     bounds->front() == 0 && bounds->back() == n;
        for (std::size_t b = 0; valid && b < sums->size(); ++b)
          valid = (*bounds)[b] <= (*bounds)[b + 1];
        if (!valid)
          error = "dataset " + clip(name, 60) + " has no checksum (damaged?)";
        for (std::size_t b = 0; error.empty() && b < sums->size(); ++b)
          if ((*sums)[b] != fnv1a64(values.data() + (*bounds)[b],
                                    ((*bounds)[b + 1] - (*bounds)[b]) * sizeof(double)))
            error = "dataset " + clip(name, 60) +
                    " fails its checksum: the file is damaged; restart from an intact copy or run again";
      }
      if (space >= 0)
        H5Sclose(space);
      H5Dclose(set);
      state[name] = std::move(values);
    }
    H5Fclose(file);
    if (!error.empty())
      throw InputError("checkpoint " + shown + ": " + error);
    return state;
  }
} // namespace app
