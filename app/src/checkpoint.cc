#include <app/checkpoint.h>
#include <app/paths.h>
#include <coupling/run_case.h>
#include <diagnose/csv.h>
#include <diagnose/text_input.h>

#include <hdf5.h>

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

  void write_checkpoint(const std::string &path, const StateArrays &state, const std::string &used_parameters)
  {
    silence_hdf5();
    const std::string tmp = path + ".tmp";
    const hid_t file      = H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    if (file < 0)
      throw std::runtime_error("checkpoint: cannot create " + clip(tmp) + " (disk full or not writable?)");
    bool ok = write_attribute(file, "cosim_checkpoint_version", H5T_NATIVE_INT, &checkpoint_version) &&
              write_string_attribute(file, "cosim_version", program_identity()) &&
              write_string_attribute(file, "used_parameters", used_parameters);
    for (const auto &[name, values] : state)
    {
      if (!ok)
        break;
      const hsize_t n   = values.size();
      const hid_t space = H5Screate_simple(1, &n, nullptr);
      const hid_t set   = H5Dcreate2(file, name.c_str(), H5T_IEEE_F64LE, space, H5P_DEFAULT,
                                     H5P_DEFAULT, H5P_DEFAULT);
      const std::uint64_t sum = fnv1a64(values.data(), values.size() * sizeof(double));
      ok = set >= 0 &&
           (n == 0 || H5Dwrite(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) >= 0) &&
           write_attribute(set, "fnv1a64", H5T_NATIVE_UINT64, &sum);
      if (set >= 0)
        H5Dclose(set);
      H5Sclose(space);
    }
    ok = H5Fclose(file) >= 0 && ok;
    std::error_code ec;
    if (ok)
      std::filesystem::rename(tmp, path, ec);
    if (!ok || ec)
    {
      std::filesystem::remove(tmp, ec);
      throw std::runtime_error("checkpoint: cannot write " + clip(path) + " (disk full or not writable?)");
    }
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
      std::uint64_t stored_sum = 0;
      if (error.empty())
      {
        const hid_t sum_attr = H5Aexists(set, "fnv1a64") > 0 ? H5Aopen(set, "fnv1a64", H5P_DEFAULT) : -1;
        if (sum_attr < 0 || H5Aread(sum_attr, H5T_NATIVE_UINT64, &stored_sum) < 0)
          error = "dataset " + clip(name, 60) + " has no checksum (damaged?)";
        else if (stored_sum != fnv1a64(values.data(), values.size() * sizeof(double)))
          error = "dataset " + clip(name, 60) +
                  " fails its checksum: the file is damaged; restart from an intact copy or run again";
        if (sum_attr >= 0)
          H5Aclose(sum_attr);
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
