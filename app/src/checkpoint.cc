#include <app/checkpoint.h>
#include <coupling/run_case.h>

#include <hdf5.h>

#include <cstdio>
#include <filesystem>
#include <stdexcept>

namespace app
{
  using coupling::InputError;
  using coupling::StateArrays;

  namespace
  {
    /// HDF5 prints its own error stack by default; our messages say what failed.
    void silence_hdf5()
    {
      H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    }
  } // namespace

  void write_checkpoint(const std::string &path, const StateArrays &state)
  {
    silence_hdf5();
    const std::string tmp = path + ".tmp";
    const hid_t file      = H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    if (file < 0)
      throw std::runtime_error("checkpoint: cannot create " + tmp);
    bool ok = true;
    {
      const hid_t space = H5Screate(H5S_SCALAR);
      const hid_t attr  = H5Acreate2(file, "cosim_checkpoint_version", H5T_NATIVE_INT, space,
                                     H5P_DEFAULT, H5P_DEFAULT);
      ok                = attr >= 0 && H5Awrite(attr, H5T_NATIVE_INT, &checkpoint_version) >= 0;
      if (attr >= 0)
        H5Aclose(attr);
      H5Sclose(space);
    }
    for (const auto &[name, values] : state)
    {
      if (!ok)
        break;
      const hsize_t n   = values.size();
      const hid_t space = H5Screate_simple(1, &n, nullptr);
      const hid_t set   = H5Dcreate2(file, name.c_str(), H5T_IEEE_F64LE, space, H5P_DEFAULT,
                                     H5P_DEFAULT, H5P_DEFAULT);
      ok = set >= 0 && (n == 0 || H5Dwrite(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT,
                                           values.data()) >= 0);
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
      throw std::runtime_error("checkpoint: cannot write " + path);
    }
  }

  StateArrays read_checkpoint(const std::string &path)
  {
    silence_hdf5();
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
      throw InputError("checkpoint " + path +
                       ": no such file; --restart DIR needs a DIR with checkpoint.h5 and "
                       "used_parameters.prm (a run stopped by a signal or with "
                       "Output/Checkpoint interval set)");
    const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    if (file < 0)
      throw InputError("checkpoint " + path + ": not a readable HDF5 file");
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
        error = "cannot open dataset " + name;
        break;
      }
      const hid_t space = H5Dget_space(set);
      hsize_t n         = 0;
      if (space < 0 || H5Sget_simple_extent_ndims(space) != 1 ||
          H5Sget_simple_extent_dims(space, &n, nullptr) < 0)
        error = "dataset " + name + " is not a 1-D array";
      std::vector<double> values(n);
      if (error.empty() && n > 0 &&
          H5Dread(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) < 0)
        error = "cannot read dataset " + name;
      if (space >= 0)
        H5Sclose(space);
      H5Dclose(set);
      state[name] = std::move(values);
    }
    H5Fclose(file);
    if (!error.empty())
      throw InputError("checkpoint " + path + ": " + error);
    return state;
  }
} // namespace app
