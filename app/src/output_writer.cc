#include <app/output_writer.h>
#include <app/paths.h>

#include <coupling/errors.h>

#include "block_rows.h"

#include <hdf5.h>
#include <mpi.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>
#include <stdexcept>
#include <sys/wait.h>
#include <unistd.h>

namespace app
{
  using coupling::Summary;
  using coupling::HistoryRow;
  using coupling::ParticleSnapshot;
  using coupling::MeshSnapshot;

  namespace
  {
    std::string number(double v, const char *fmt = "%.10g")
    {
      if (!std::isfinite(v))
        return "null";
      char buffer[64];
      std::snprintf(buffer, sizeof buffer, fmt, v + 0.0); // + 0.0: no "-0"
      return buffer;
    }

    /// The history columns with their value in file units.
    struct Column
    {
      const char *name;
      double (*value)(const HistoryRow &);
      const char *units; ///< the `units` attribute of /history/<name> in results.h5
    };

    const Column columns[] = {
      {"time_s", [](const HistoryRow &r) { return r.time; }, "s"},
      {"displacement_mm", [](const HistoryRow &r) { return r.displacement * 1e3; }, "mm"},
      {"force_kN", [](const HistoryRow &r) { return r.force * 1e-3; }, "kN"},
      {"force_bottom_kN", [](const HistoryRow &r) { return r.force_bottom * 1e-3; }, "kN"},
      {"stress_MPa", [](const HistoryRow &r) { return r.stress * 1e-6; }, "MPa"},
      {"strain", [](const HistoryRow &r) { return r.strain; }, "1"},
      {"axial_gauge_strain", [](const HistoryRow &r) { return r.axial_gauge_strain; }, "1"},
      {"radial_strain", [](const HistoryRow &r) { return r.radial_strain; }, "1"},
      {"kinetic_energy_J", [](const HistoryRow &r) { return r.kinetic_energy; }, "J"},
      {"internal_energy_J", [](const HistoryRow &r) { return r.internal_energy; }, "J"},
      {"dissipated_energy_J", [](const HistoryRow &r) { return r.dissipated_energy; }, "J"},
      {"external_work_J", [](const HistoryRow &r) { return r.external_work; }, "J"},
      {"n_failed", [](const HistoryRow &r) { return r.n_failed; }, "1"},
      {"rolling_force_kN", [](const HistoryRow &r) { return r.rolling_force * 1e-3; }, "kN"},
      {"side_force_kN", [](const HistoryRow &r) { return r.side_force * 1e-3; }, "kN"},
    };
  } // namespace

  namespace
  {
    using Json = nlohmann::ordered_json; // keys in the order written

    /// A finite value rounded to 10 significant digits (what the file needs, without the binary
    /// noise of a unit conversion: 281.44, not 281.44000000000005); null when not finite.
    Json value(double v)
    {
      if (!std::isfinite(v))
        return nullptr;
      char buffer[64];
      std::snprintf(buffer, sizeof buffer, "%.10g", v + 0.0); // + 0.0: no "-0"
      const double rounded = std::strtod(buffer, nullptr);
      // a whole number is written as one (a count in Summary::extra: 35260, not 35260.0)
      if (rounded == std::floor(rounded) && std::abs(rounded) < 1e15)
        return static_cast<long long>(rounded);
      return rounded;
    }

    Json text_or_null(const std::string &s) { return s.empty() ? Json(nullptr) : Json(s); }

    /// A scalar as JSON; invalid UTF-8 (a file name in a message) becomes U+FFFD, not an exception.
    std::string dump(const Json &j) { return j.dump(-1, ' ', false, Json::error_handler_t::replace); }

    /// A value on one line, with ", " and ": " between items (nlohmann's compact form has none).
    std::string one_line(const Json &j)
    {
      std::string out;
      if (j.is_object())
      {
        for (auto it = j.begin(); it != j.end(); ++it)
          out += (out.empty() ? "{" : ", ") + dump(Json(it.key())) + ": " + one_line(it.value());
        return out.empty() ? "{}" : out + "}";
      }
      if (j.is_array())
      {
        for (const auto &item : j)
          out += (out.empty() ? "[" : ", ") + one_line(item);
        return out.empty() ? "[]" : out + "]";
      }
      return dump(j);
    }

    /// An object with one top-level key per line, each value on its key's line.
    std::string document(const Json &j)
    {
      std::string out = "{";
      bool first = true;
      for (auto it = j.begin(); it != j.end(); ++it, first = false)
        out += std::string(first ? "\n" : ",\n") + "  " + dump(Json(it.key())) + ": " + one_line(it.value());
      return out + "\n}\n";
    }
  } // namespace

  std::string to_string(const RunStatus status)
  {
    switch (status)
    {
      case RunStatus::completed:
        return "completed";
      case RunStatus::unstable:
        return "unstable";
      case RunStatus::interrupted:
        return "interrupted";
      case RunStatus::failed:
        return "failed";
    }
    return "failed";
  }

  std::string summary_json(const Summary &summary) { return summary_json(&summary, RunEnd{}); }

  std::string summary_json(const Summary *s, const RunEnd &end)
  {
    Json j;
    j["schema_version"] = 1;
    j["status"]         = to_string(end.status);
    j["cosim_version"]  = version();
    j["commit"]         = commit();
    j["message"]        = text_or_null(end.message);
    // a result of the run: its value with a Summary, else null
    auto result = [&](const char *key, auto get) { j[key] = s ? Json(get(*s)) : Json(nullptr); };
    j["test"] = s ? s->test : end.test;
    result("n_particles", [](const Summary &r) { return r.n_particles; });
    j["n_steps"]      = s ? Json(s->n_steps) : end.n_steps >= 0 ? Json(end.n_steps) : Json(nullptr);
    j["wall_seconds"] = s ? value(s->wall_seconds) : end.wall_seconds >= 0 ? value(end.wall_seconds) : Json(nullptr);
    result("peak_stress_MPa", [](const Summary &r) { return value(r.peak_stress * 1e-6); });
    result("peak_force_kN", [](const Summary &r) { return value(r.peak_force * 1e-3); });
    result("strain_at_peak", [](const Summary &r) { return value(r.strain_at_peak); });
    result("youngs_modulus_GPa", [](const Summary &r) { return value(r.youngs_modulus * 1e-9); });
    result("platen_modulus_GPa", [](const Summary &r) { return value(r.platen_modulus * 1e-9); });
    result("poissons_ratio",
           [](const Summary &r) { return r.poissons_ratio < 0 ? Json(nullptr) : value(r.poissons_ratio); });
    result("max_displacement_mm", [](const Summary &r) { return value(r.max_displacement * 1e3); });
    result("max_kinetic_to_internal_energy", [](const Summary &r) { return value(r.max_kinetic_to_internal_energy); });
    result("max_force_imbalance", [](const Summary &r) { return value(r.max_force_imbalance); });
    result("energy_balance_error", [](const Summary &r) { return value(r.energy_balance_error); });
    result("max_exchange_imbalance", [](const Summary &r) { return value(r.max_exchange_imbalance); });
    result("quasi_static", [](const Summary &r) { return r.quasi_static; });
    result("true_area_mm2", [](const Summary &r) { return value(r.true_area * 1e6); });
    result("lattice_area_mm2", [](const Summary &r) { return value(r.lattice_area * 1e6); });
    result("strain_rate_per_s", [](const Summary &r) { return value(r.strain_rate); });
    result("time_step_s", [](const Summary &r) { return value(r.time_step); });
    result("stop_reason", [](const Summary &r) { return text_or_null(r.stop_reason); });
    if (s && !s->particles_per_rank.empty())
    {
      j["n_ranks"]            = s->particles_per_rank.size();
      j["particles_per_rank"] = s->particles_per_rank;
    }
    j["last_good_state"] = nullptr;
    if (end.last_good_step >= 0)
      j["last_good_state"] = Json{{"file", "last_good_state.h5"},
                                  {"xdmf", "last_good_state.xdmf"},
                                  {"step", end.last_good_step},
                                  {"time_s", value(end.last_good_time)}};
    j["checkpoint"] = text_or_null(end.checkpoint);
    j["restart"]    = text_or_null(end.restart_command);
    if (s)
      for (const auto &[key, v] : s->extra)
      {
        if (j.contains(key))
          throw std::logic_error("Summary::extra '" + key + "' repeats a summary.json key");
        j[key] = value(v);
      }
    return document(j);
  }

  SummaryFile read_summary_json(const std::string &path)
  {
    std::ifstream in(path, std::ios::binary);
    if (!in)
      throw coupling::InputError(path + ": cannot be read");
    Json j;
    try
    {
      j = Json::parse(in);
    }
    catch (const std::exception &e)
    {
      throw coupling::InputError(path + ": not JSON (" + std::string(e.what()) + ")");
    }
    if (!j.is_object() || !j.contains("schema_version") || j["schema_version"] != 1 || !j.contains("status") ||
        !j["status"].is_string())
      throw coupling::InputError(path + ": not a cosim summary.json of schema_version 1");
    SummaryFile file;
    file.status = j["status"].get<std::string>();
    if (file.status != "completed")
      return file;
    // the inverse of summary_json: null numbers are NaN, units back to SI
    auto number = [&](const char *key, double scale) {
      const auto it = j.find(key);
      if (it == j.end() || it->is_null())
        return std::numeric_limits<double>::quiet_NaN();
      if (!it->is_number())
        throw coupling::InputError(path + ": '" + key + "' is not a number");
      return it->get<double>() * scale;
    };
    auto text = [&](const char *key) {
      const auto it = j.find(key);
      return it != j.end() && it->is_string() ? it->get<std::string>() : std::string();
    };
    Summary s;
    s.test                           = text("test");
    s.n_particles                    = static_cast<std::size_t>(number("n_particles", 1));
    s.n_steps                        = static_cast<std::size_t>(number("n_steps", 1));
    s.wall_seconds                   = number("wall_seconds", 1);
    s.peak_stress                    = number("peak_stress_MPa", 1e6);
    s.peak_force                     = number("peak_force_kN", 1e3);
    s.strain_at_peak                 = number("strain_at_peak", 1);
    s.youngs_modulus                 = number("youngs_modulus_GPa", 1e9);
    s.platen_modulus                 = number("platen_modulus_GPa", 1e9);
    s.poissons_ratio                 = j.contains("poissons_ratio") && j["poissons_ratio"].is_number()
                                         ? j["poissons_ratio"].get<double>()
                                         : -1.0;
    s.max_displacement               = number("max_displacement_mm", 1e-3);
    s.max_kinetic_to_internal_energy = number("max_kinetic_to_internal_energy", 1);
    s.max_force_imbalance            = number("max_force_imbalance", 1);
    s.energy_balance_error           = number("energy_balance_error", 1);
    s.max_exchange_imbalance         = number("max_exchange_imbalance", 1);
    s.quasi_static                   = j.contains("quasi_static") && j["quasi_static"].is_boolean() &&
                     j["quasi_static"].get<bool>();
    s.true_area    = number("true_area_mm2", 1e-6);
    s.lattice_area = number("lattice_area_mm2", 1e-6);
    s.strain_rate  = number("strain_rate_per_s", 1);
    s.time_step    = number("time_step_s", 1);
    s.stop_reason  = text("stop_reason");
    // the further results: every other key with a number (or null) value, in the file's order
    static const std::set<std::string> fixed = {
      "schema_version", "status", "cosim_version", "commit", "message", "test", "n_particles", "n_steps",
      "wall_seconds", "peak_stress_MPa", "peak_force_kN", "strain_at_peak", "youngs_modulus_GPa",
      "platen_modulus_GPa", "poissons_ratio", "max_displacement_mm", "max_kinetic_to_internal_energy",
      "max_force_imbalance", "energy_balance_error", "max_exchange_imbalance", "quasi_static",
      "true_area_mm2", "lattice_area_mm2", "strain_rate_per_s", "time_step_s", "stop_reason",
      "last_good_state", "checkpoint", "restart", "n_ranks", "particles_per_rank"};
    if (const auto it = j.find("particles_per_rank"); it != j.end() && it->is_array())
      for (const auto &n : *it)
        if (n.is_number())
          s.particles_per_rank.push_back(n.get<std::size_t>());
    for (auto it = j.begin(); it != j.end(); ++it)
      if (!fixed.count(it.key()) && (it->is_number() || it->is_null()))
        s.extra.emplace_back(it.key(), it->is_null() ? std::numeric_limits<double>::quiet_NaN()
                                                     : it->get<double>());
    file.summary = s;
    return file;
  }

  const std::vector<std::string> &history_columns()
  {
    static const std::vector<std::string> names = [] {
      std::vector<std::string> n;
      for (const auto &c : columns)
        n.push_back(c.name);
      return n;
    }();
    return names;
  }

  void write_text_file(const std::string &path, const std::string &text)
  {
    std::ofstream out(path);
    out << text;
    out.close();
    if (!out)
      throw std::runtime_error(path + ": cannot write");
  }

  void write_history_csv(const std::string &path, const std::vector<HistoryRow> &rows)
  {
    std::ostringstream o;
    bool first = true;
    for (const auto &c : columns)
      o << (first ? "" : ",") << c.name, first = false;
    o << "\n";
    for (const auto &r : rows)
    {
      first = true;
      for (const auto &c : columns)
        o << (first ? "" : ",") << number(c.value(r), "%.9g"), first = false;
      o << "\n";
    }
    write_text_file(path, o.str());
  }

  // ---------------------------------------------------------------- HDF5 + XDMF

  struct ResultsFile::Impl
  {
    struct MeshInfo
    {
      std::string name;
      std::size_t n_vertices, n_cells;
    };
    struct SnapshotInfo
    {
      double time;
      std::string group;
      std::size_t n_particles;
      std::vector<MeshInfo> meshes;
      bool stress_measures = true; ///< has von_mises and mean stress (a copied older file may not)
      bool failure_modes   = true; ///< has failure_mode (a copied older file may not)
    };

    std::string path;
    hid_t file = -1;
    std::vector<SnapshotInfo> snapshots;

    static void check(herr_t status, const std::string &what)
    {
      if (status < 0)
        throw std::runtime_error("HDF5: " + what + " failed");
    }

    hid_t group(hid_t parent, const std::string &name)
    {
      const hid_t g = H5Gcreate2(parent, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
      if (g < 0)
        throw std::runtime_error("HDF5: cannot create group " + name + " in " + path);
      return g;
    }

    template <typename T>
    void dataset(hid_t parent, const std::string &name, const std::vector<T> &data, std::size_t n_columns,
                 hid_t type, const std::string &units)
    {
      const hsize_t rows = n_columns ? data.size() / n_columns : 0;
      const hid_t set = empty_dataset(parent, name, rows, n_columns, type, units, false);
      if (!data.empty())
        check(H5Dwrite(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()), "writing " + name);
      H5Dclose(set);
    }

    /// A dataset of `rows` x `n_columns` (1-D for one column) with its units, not yet written;
    /// `allocate`: its space reserved in the file now (contiguous, no fill), so that the ranks
    /// of a distributed run can write their rows into it later (write_particle_rows).
    hid_t empty_dataset(hid_t parent, const std::string &name, hsize_t rows, std::size_t n_columns,
                        hid_t type, const std::string &units, bool allocate)
    {
      hsize_t dims[2] = {rows, static_cast<hsize_t>(n_columns)};
      const hid_t space = H5Screate_simple(n_columns > 1 ? 2 : 1, dims, nullptr);
      const hid_t plist = H5Pcreate(H5P_DATASET_CREATE);
      if (allocate)
      {
        H5Pset_alloc_time(plist, H5D_ALLOC_TIME_EARLY);
        H5Pset_fill_time(plist, H5D_FILL_TIME_NEVER);
      }
      const hid_t set = H5Dcreate2(parent, name.c_str(), type, space, H5P_DEFAULT, plist, H5P_DEFAULT);
      H5Pclose(plist);
      H5Sclose(space);
      if (set < 0)
        throw std::runtime_error("HDF5: cannot create dataset " + name + " in " + path);
      attribute(set, "units", units);
      return set;
    }

    void attribute(hid_t object, const std::string &name, double value)
    {
      const hid_t space = H5Screate(H5S_SCALAR);
      const hid_t a = H5Acreate2(object, name.c_str(), H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT);
      check(H5Awrite(a, H5T_NATIVE_DOUBLE, &value), "writing attribute " + name);
      H5Aclose(a);
      H5Sclose(space);
    }

    void attribute(hid_t object, const std::string &name, const std::string &value)
    {
      // variable-length UTF-8: h5py reads it as str, ParaView and h5dump show it as text
      const hid_t type = H5Tcopy(H5T_C_S1);
      H5Tset_size(type, H5T_VARIABLE);
      H5Tset_cset(type, H5T_CSET_UTF8);
      const hid_t space = H5Screate(H5S_SCALAR);
      const hid_t a     = H5Acreate2(object, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT);
      const char *text  = value.c_str();
      check(a < 0 ? -1 : H5Awrite(a, type, &text), "writing attribute " + name);
      H5Aclose(a);
      H5Sclose(space);
      H5Tclose(type);
    }

    /// /particle_vertices/<n> (0..n-1), the Polyvertex connectivity of each particle count used.
    void write_particle_vertices()
    {
      std::set<std::size_t> counts;
      for (const auto &s : snapshots)
        if (s.n_particles > 0)
          counts.insert(s.n_particles);
      if (counts.empty())
        return;
      const hid_t g = H5Lexists(file, "particle_vertices", H5P_DEFAULT) > 0
                        ? H5Gopen2(file, "particle_vertices", H5P_DEFAULT)
                        : group(file, "particle_vertices");
      for (const std::size_t n : counts)
      {
        const std::string name = std::to_string(n);
        if (H5Lexists(g, name.c_str(), H5P_DEFAULT) > 0)
          continue;
        std::vector<unsigned int> index(n);
        for (std::size_t i = 0; i < n; ++i)
          index[i] = static_cast<unsigned int>(i);
        dataset(g, name, index, 1, H5T_NATIVE_UINT, "index");
      }
      H5Gclose(g);
    }
  };

  namespace
  {
    /// The "meaning" attribute of the failure_mode dataset (sph::FailureMode).
    const std::string failure_mode_meaning =
      "0 none (never yielded), 1 tensile (tension cut-off, or failure plane in tension), "
      "2 shear (Mohr-Coulomb, failure plane in compression), 3 crushed (shear under a mean "
      "compression of at least the uniaxial compressive strength)";

    /// The XDMF Tensor6 order xx,xy,xz,yy,yz,zz of ParticleSnapshot::stress (xx,yy,zz,yz,xz,xy).
    std::vector<double> stress_in_xdmf_order(const std::vector<double> &stress)
    {
      constexpr std::size_t from[6] = {0, 5, 4, 1, 3, 2};
      std::vector<double> out(stress.size());
      for (std::size_t i = 0; i + 6 <= stress.size(); i += 6)
        for (std::size_t c = 0; c < 6; ++c)
          out[i + c] = stress[i + from[c]];
      return out;
    }

    /// Von Mises stress sqrt(3 J2) [Pa] per particle of ParticleSnapshot::stress.
    std::vector<double> von_mises(const std::vector<double> &stress)
    {
      std::vector<double> out(stress.size() / 6);
      for (std::size_t p = 0; p < out.size(); ++p)
      {
        const double *s = &stress[6 * p]; // xx,yy,zz,yz,xz,xy
        const double d1 = s[0] - s[1], d2 = s[1] - s[2], d3 = s[2] - s[0];
        out[p] = std::sqrt(0.5 * (d1 * d1 + d2 * d2 + d3 * d3) + 3.0 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]));
      }
      return out;
    }

    /// Mean stress -(xx+yy+zz)/3 [Pa], compression positive, per particle.
    std::vector<double> mean_stress_compression_positive(const std::vector<double> &stress)
    {
      std::vector<double> out(stress.size() / 6);
      for (std::size_t p = 0; p < out.size(); ++p)
        out[p] = -(stress[6 * p] + stress[6 * p + 1] + stress[6 * p + 2]) / 3.0;
      return out;
    }
  } // namespace

  ResultsFile::ResultsFile(const std::string &h5_path)
    : impl_(std::make_unique<Impl>())
  {
    impl_->path = h5_path;
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); // errors become exceptions below, not stderr noise
    impl_->file = H5Fcreate(h5_path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    if (impl_->file < 0)
      throw std::runtime_error(h5_path + ": cannot create the HDF5 file");
    impl_->attribute(impl_->file, "cosim_version", version());
    impl_->attribute(impl_->file, "commit", commit());
    H5Gclose(impl_->group(impl_->file, "snapshots"));
  }

  ResultsFile::~ResultsFile()
  {
    if (impl_ && impl_->file >= 0)
      H5Fclose(impl_->file);
  }

  std::size_t ResultsFile::n_snapshots() const { return impl_->snapshots.size(); }

  namespace
  {
    /// One particle dataset of a snapshot: its name, columns per particle, units and the rows
    /// held here (doubles, or integers for failure_mode).
    struct ParticleField
    {
      const char *name;
      std::size_t columns;
      const char *units;
      std::vector<double> values;
      std::vector<int> integers;
      bool integer = false; ///< held in `integers`, written as integers
    };

    /// The datasets of /snapshots/NNNNNN/particles for the rows `particles` holds, fields it
    /// lacks as zeros (so that the XDMF stays valid). std::logic_error on a field of the wrong
    /// size.
    std::vector<ParticleField> particle_fields(const ParticleSnapshot &particles)
    {
      const std::size_t n = particles.n_rows();
      auto filled = [&](const std::vector<double> &v, std::size_t per, const char *what) {
        if (v.size() != n * per && !v.empty())
          throw std::logic_error(std::string("ParticleSnapshot::") + what + " has the wrong size");
        return v.empty() ? std::vector<double>(n * per, 0.0) : v;
      };
      if (!particles.failure_mode.empty() && particles.failure_mode.size() != n)
        throw std::logic_error("ParticleSnapshot::failure_mode has the wrong size");
      const std::vector<double> stress = filled(particles.stress, 6, "stress");
      std::vector<ParticleField> f;
      f.push_back({"position", 3, "m", filled(particles.position, 3, "position"), {}});
      f.push_back({"velocity", 3, "m/s", filled(particles.velocity, 3, "velocity"), {}});
      f.push_back({"displacement", 3, "m", filled(particles.displacement, 3, "displacement"), {}});
      f.push_back({"stress", 6, "Pa", stress_in_xdmf_order(stress), {}});
      f.push_back({"von_mises", 1, "Pa", von_mises(stress), {}});
      f.push_back({"mean_stress_compression_positive", 1, "Pa", mean_stress_compression_positive(stress), {}});
      f.push_back({"plastic_strain", 1, "1", filled(particles.plastic_strain, 1, "plastic_strain"), {}});
      f.push_back({"damage", 1, "1", filled(particles.damage, 1, "damage"), {}});
      f.push_back({"failure_mode", 1, "1", {},
                   particles.failure_mode.empty() ? std::vector<int>(n, 0) : particles.failure_mode});
      f.back().integer = true;
      return f;
    }

    /// The rows of `fields` (this rank's, at `global_index`, ascending) moved to the rank whose
    /// block of the body's `n` rows holds them (app::rows_in_blocks), the first of them returned
    /// in `first`.
    std::vector<ParticleField> rows_in_blocks(const std::vector<ParticleField> &fields,
                                              const std::vector<std::int64_t> &global_index,
                                              const std::size_t n, const MPI_Comm comm, std::size_t &first)
    {
      int rank = 0, size = 1;
      MPI_Comm_rank(comm, &rank);
      MPI_Comm_size(comm, &size);
      std::size_t width = 0; // every field's columns
      for (const ParticleField &f : fields)
        width += f.columns;
      std::vector<double> rows;
      rows.reserve(width * global_index.size());
      for (std::size_t i = 0; i < global_index.size(); ++i)
        for (const ParticleField &f : fields)
          for (std::size_t c = 0; c < f.columns; ++c)
            rows.push_back(f.integer ? static_cast<double>(f.integers[i * f.columns + c])
                                     : f.values[i * f.columns + c]);
      const std::vector<double> block = app::rows_in_blocks(rows, width, global_index, n, comm);
      first                  = block_start(n, rank, size);
      const std::size_t n_rows = block.size() / std::max<std::size_t>(width, 1);
      std::vector<ParticleField> out;
      std::size_t column = 0;
      for (const ParticleField &f : fields)
      {
        out.push_back({f.name, f.columns, f.units, {}, {}, f.integer});
        ParticleField &o = out.back();
        if (f.integer)
          o.integers.resize(n_rows * f.columns);
        else
          o.values.resize(n_rows * f.columns);
        for (std::size_t k = 0; k < n_rows; ++k)
          for (std::size_t c = 0; c < f.columns; ++c)
          {
            const double value = block[k * width + column + c];
            if (f.integer)
              o.integers[k * f.columns + c] = static_cast<int>(value);
            else
              o.values[k * f.columns + c] = value;
          }
        column += f.columns;
      }
      return out;
    }
  } // namespace

  void write_particle_rows(std::string h5_path, std::string group, const ParticleSnapshot &particles)
  {
    const MPI_Comm comm = MPI_COMM_WORLD;
    broadcast(h5_path, comm);
    broadcast(group, comm);
    std::size_t first = 0;
    const std::vector<ParticleField> fields =
      rows_in_blocks(particle_fields(particles), particles.global_index, particles.n, comm, first);
    const hid_t access = H5Pcreate(H5P_FILE_ACCESS);
    H5Pset_fapl_mpio(access, comm, MPI_INFO_NULL);
    const hid_t file = H5Fopen(h5_path.c_str(), H5F_ACC_RDWR, access);
    H5Pclose(access);
    if (file < 0)
      throw std::runtime_error(h5_path + ": cannot open the HDF5 file on every MPI rank");
    const hid_t transfer = H5Pcreate(H5P_DATASET_XFER);
    H5Pset_dxpl_mpio(transfer, H5FD_MPIO_COLLECTIVE);
    herr_t status = 0;
    for (const ParticleField &f : fields)
    {
      const std::string name = group + "/particles/" + f.name;
      const bool integer = f.integer;
      const hsize_t rows = (integer ? f.integers.size() : f.values.size()) / f.columns;
      const hid_t set = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
      const hid_t file_space = H5Dget_space(set);
      const hsize_t start[2] = {first, 0}, count[2] = {rows, f.columns};
      const hid_t memory = H5Screate_simple(f.columns > 1 ? 2 : 1, count, nullptr);
      if (rows > 0)
        H5Sselect_hyperslab(file_space, H5S_SELECT_SET, start, nullptr, count, nullptr);
      else
      {
        H5Sselect_none(file_space);
        H5Sselect_none(memory);
      }
      const void *data = integer ? static_cast<const void *>(f.integers.data()) : f.values.data();
      if (set < 0 || H5Dwrite(set, integer ? H5T_NATIVE_INT : H5T_NATIVE_DOUBLE, memory, file_space,
                              transfer, data) < 0)
        status = -1;
      H5Sclose(memory);
      H5Sclose(file_space);
      H5Dclose(set);
    }
    H5Pclose(transfer);
    if (H5Fclose(file) < 0 || status < 0)
      throw std::runtime_error(h5_path + ": writing the particle rows of " + group + " failed");
  }

  void ResultsFile::add_snapshot(double time, const ParticleSnapshot &particles, const std::vector<MeshSnapshot> &meshes)
  {
    Impl &m = *impl_;
    char name[32];
    std::snprintf(name, sizeof name, "%06zu", m.snapshots.size());
    Impl::SnapshotInfo info{time, std::string("/snapshots/") + name, particles.n, {}};
    const hid_t g = m.group(m.file, info.group);
    m.attribute(g, "time_s", time);
    const hid_t pg = m.group(g, "particles");
    // a distributed body: the datasets are made here for the whole body, and all ranks write
    // their rows into them below
    const bool distributed = !particles.global_index.empty();
    for (const ParticleField &f : particle_fields(particles))
    {
      const hid_t type = f.integer ? H5T_NATIVE_INT : H5T_NATIVE_DOUBLE;
      const hid_t set = m.empty_dataset(pg, f.name, particles.n, f.columns, type, f.units, distributed);
      if (!distributed && particles.n > 0)
        Impl::check(H5Dwrite(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT,
                             f.integer ? static_cast<const void *>(f.integers.data()) : f.values.data()),
                    std::string("writing ") + f.name);
      if (std::string(f.name) == "stress")
      {
        m.attribute(set, "components", "xx,xy,xz,yy,yz,zz");
        m.attribute(set, "sign", "tension positive");
      }
      if (std::string(f.name) == "failure_mode")
        m.attribute(set, "meaning", failure_mode_meaning);
      H5Dclose(set);
    }
    H5Gclose(pg);
    const hid_t mg = m.group(g, "meshes");
    for (const auto &mesh : meshes)
    {
      const std::size_t nv = mesh.position.size() / 3, nc = mesh.hexahedra.size() / 8;
      if (mesh.name.empty() || mesh.name.find_first_of("/ <>&\"") != std::string::npos)
        throw std::logic_error("MeshSnapshot::name must be a plain word, got '" + mesh.name + "'");
      const hid_t h = m.group(mg, mesh.name);
      m.dataset(h, "position", mesh.position, 3, H5T_NATIVE_DOUBLE, "m");
      m.dataset(h, "displacement", mesh.displacement.empty() ? std::vector<double>(nv * 3, 0.0) : mesh.displacement,
                3, H5T_NATIVE_DOUBLE, "m");
      m.dataset(h, "hexahedra", mesh.hexahedra, 8, H5T_NATIVE_UINT, "index");
      m.dataset(h, "von_mises", mesh.von_mises.empty() ? std::vector<double>(nc, 0.0) : mesh.von_mises, 1,
                H5T_NATIVE_DOUBLE, "Pa");
      H5Gclose(h);
      info.meshes.push_back({mesh.name, nv, nc});
    }
    H5Gclose(mg);
    H5Gclose(g);
    H5Fflush(m.file, H5F_SCOPE_GLOBAL);
    if (distributed)
    {
      // this rank closes the file, all ranks open it together and write their rows, and this
      // rank takes it up again
      H5Fclose(m.file);
      m.file = -1;
      write_particle_rows(m.path, info.group, particles);
      m.file = H5Fopen(m.path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
      if (m.file < 0)
        throw std::runtime_error(m.path + ": cannot open the HDF5 file again");
    }
    m.snapshots.push_back(std::move(info));
  }

  std::size_t ResultsFile::copy_snapshots(const std::string &h5_path, double until)
  {
    Impl &m = *impl_;
    const hid_t old = H5Fopen(h5_path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    if (old < 0)
      return 0;
    auto rows = [&](const std::string &dataset) -> std::size_t {
      const hid_t d = H5Dopen2(old, dataset.c_str(), H5P_DEFAULT);
      if (d < 0)
        return 0;
      const hid_t space = H5Dget_space(d);
      hsize_t dims[2]   = {0, 0};
      if (space >= 0 && H5Sget_simple_extent_ndims(space) >= 1 && H5Sget_simple_extent_ndims(space) <= 2)
        H5Sget_simple_extent_dims(space, dims, nullptr);
      if (space >= 0)
        H5Sclose(space);
      H5Dclose(d);
      return dims[0];
    };
    std::size_t copied = 0;
    const bool any     = H5Lexists(old, "/snapshots", H5P_DEFAULT) > 0;
    for (std::size_t k = 0; any; ++k)
    {
      char from[32], to[32];
      std::snprintf(from, sizeof from, "/snapshots/%06zu", k);
      if (H5Lexists(old, from, H5P_DEFAULT) <= 0)
        break;
      double time   = 0;
      const hid_t a = H5Aopen_by_name(old, from, "time_s", H5P_DEFAULT, H5P_DEFAULT);
      const bool ok = a >= 0 && H5Aread(a, H5T_NATIVE_DOUBLE, &time) >= 0;
      if (a >= 0)
        H5Aclose(a);
      if (!ok || time > until)
        break;
      std::snprintf(to, sizeof to, "/snapshots/%06zu", m.snapshots.size());
      Impl::SnapshotInfo info{time, to, rows(std::string(from) + "/particles/position"), {}};
      const std::string meshes = std::string(from) + "/meshes";
      const hid_t g            = H5Gopen2(old, meshes.c_str(), H5P_DEFAULT);
      H5G_info_t gi{};
      if (g >= 0 && H5Gget_info(g, &gi) >= 0)
        for (hsize_t j = 0; j < gi.nlinks; ++j)
        {
          char name[256];
          if (H5Lget_name_by_idx(g, ".", H5_INDEX_NAME, H5_ITER_INC, j, name, sizeof name, H5P_DEFAULT) <= 0)
            continue;
          const std::string base = meshes + "/" + name;
          info.meshes.push_back({name, rows(base + "/position"), rows(base + "/hexahedra")});
        }
      if (g >= 0)
        H5Gclose(g);
      info.stress_measures = H5Lexists(old, (std::string(from) + "/particles/von_mises").c_str(), H5P_DEFAULT) > 0;
      info.failure_modes =
        H5Lexists(old, (std::string(from) + "/particles/failure_mode").c_str(), H5P_DEFAULT) > 0;
      if (H5Ocopy(old, from, m.file, to, H5P_DEFAULT, H5P_DEFAULT) < 0)
        break;
      m.snapshots.push_back(std::move(info));
      ++copied;
    }
    H5Fclose(old);
    return copied;
  }

  void ResultsFile::write_history(const std::vector<HistoryRow> &rows)
  {
    Impl &m = *impl_;
    const hid_t g = m.group(m.file, "history");
    for (const auto &c : columns)
    {
      std::vector<double> v;
      v.reserve(rows.size());
      for (const auto &r : rows)
        v.push_back(c.value(r));
      m.dataset(g, c.name, v, 1, H5T_NATIVE_DOUBLE, c.units);
    }
    H5Gclose(g);
  }

  void ResultsFile::close(const std::string &xdmf_path)
  {
    Impl &m = *impl_;
    if (m.file >= 0)
    {
      m.write_particle_vertices();
      Impl::check(H5Fclose(m.file), "closing " + m.path);
      m.file = -1;
    }
    const std::string h5 = std::filesystem::path(m.path).filename().string();
    std::ostringstream x;
    auto item = [&](const std::string &dataset, std::size_t rows, std::size_t cols, const char *type = "Float",
                    int precision = 8) {
      std::ostringstream d;
      d << "<DataItem Dimensions=\"" << rows;
      if (cols > 1)
        d << " " << cols;
      d << "\" NumberType=\"" << type << "\" Precision=\"" << precision << "\" Format=\"HDF\">" << h5 << ":"
        << dataset << "</DataItem>";
      return d.str();
    };
    x << "<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n<Xdmf Version=\"3.0\">\n<Domain>\n"
      << "<Grid Name=\"results\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
    for (const auto &s : m.snapshots)
    {
      x << " <Grid Name=\"step\" GridType=\"Collection\" CollectionType=\"Spatial\">\n"
        << "  <Time Value=\"" << number(s.time, "%.12g") << "\"/>\n";
      if (s.n_particles > 0)
      {
        const std::string p = s.group + "/particles/";
        const std::size_t n = s.n_particles;
        x << "  <Grid Name=\"rock\" GridType=\"Uniform\">\n"
          << "   <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << n << "\" NodesPerElement=\"1\">"
          << item("/particle_vertices/" + std::to_string(n), n, 1, "UInt", 4) << "</Topology>\n"
          << "   <Geometry GeometryType=\"XYZ\">" << item(p + "position", n, 3) << "</Geometry>\n"
          << "   <Attribute Name=\"velocity\" AttributeType=\"Vector\" Center=\"Node\">" << item(p + "velocity", n, 3)
          << "</Attribute>\n"
          << "   <Attribute Name=\"displacement\" AttributeType=\"Vector\" Center=\"Node\">"
          << item(p + "displacement", n, 3) << "</Attribute>\n"
          << "   <Attribute Name=\"stress_tension_positive\" AttributeType=\"Tensor6\" Center=\"Node\">"
          << item(p + "stress", n, 6) << "</Attribute>\n";
        if (s.stress_measures)
          x << "   <Attribute Name=\"von_mises\" AttributeType=\"Scalar\" Center=\"Node\">" << item(p + "von_mises", n, 1)
            << "</Attribute>\n"
            << "   <Attribute Name=\"mean_stress_compression_positive\" AttributeType=\"Scalar\" Center=\"Node\">"
            << item(p + "mean_stress_compression_positive", n, 1) << "</Attribute>\n";
        x << "   <Attribute Name=\"plastic_strain\" AttributeType=\"Scalar\" Center=\"Node\">"
          << item(p + "plastic_strain", n, 1) << "</Attribute>\n"
          << "   <Attribute Name=\"damage\" AttributeType=\"Scalar\" Center=\"Node\">"
          << item(p + "damage", n, 1) << "</Attribute>\n";
        if (s.failure_modes)
          x << "   <Attribute Name=\"failure_mode\" AttributeType=\"Scalar\" Center=\"Node\">"
            << item(p + "failure_mode", n, 1, "Int", 4) << "</Attribute>\n";
        x << "  </Grid>\n";
      }
      for (const auto &mesh : s.meshes)
      {
        if (mesh.n_cells == 0)
          continue;
        const std::string p = s.group + "/meshes/" + mesh.name + "/";
        x << "  <Grid Name=\"" << mesh.name << "\" GridType=\"Uniform\">\n"
          << "   <Topology TopologyType=\"Hexahedron\" NumberOfElements=\"" << mesh.n_cells << "\">"
          << item(p + "hexahedra", mesh.n_cells, 8, "UInt", 4) << "</Topology>\n"
          << "   <Geometry GeometryType=\"XYZ\">" << item(p + "position", mesh.n_vertices, 3) << "</Geometry>\n"
          << "   <Attribute Name=\"displacement\" AttributeType=\"Vector\" Center=\"Node\">"
          << item(p + "displacement", mesh.n_vertices, 3) << "</Attribute>\n"
          << "   <Attribute Name=\"von_mises\" AttributeType=\"Scalar\" Center=\"Cell\">"
          << item(p + "von_mises", mesh.n_cells, 1) << "</Attribute>\n"
          << "  </Grid>\n";
      }
      x << " </Grid>\n";
    }
    x << "</Grid>\n</Domain>\n</Xdmf>\n";
    write_text_file(xdmf_path, x.str());
  }

  // ---------------------------------------------------------------- plot

  void redirect_child_output(const char *log)
  {
    const int null = open("/dev/null", O_WRONLY);
    const int err  = open(log, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (null >= 0)
      dup2(null, STDOUT_FILENO);
    if (err >= 0)
      dup2(err, STDERR_FILENO);
  }

  namespace
  {
    /// Runs argv, stdout to /dev/null, stderr into `log`. Returns the exit status (-1 if not run).
    int run_program(const std::vector<std::string> &argv, const std::string &log)
    {
      const pid_t pid = fork();
      if (pid < 0)
        return -1;
      if (pid == 0)
      {
        redirect_child_output(log.c_str());
        std::vector<char *> args;
        for (const auto &a : argv)
          args.push_back(const_cast<char *>(a.c_str()));
        args.push_back(nullptr);
        execvp(args[0], args.data());
        _exit(127);
      }
      int status = 0;
      if (waitpid(pid, &status, 0) < 0)
        return -1;
      return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    }

    std::string first_line(const std::string &path)
    {
      std::ifstream in(path);
      std::string line, last;
      while (std::getline(in, line))
        if (!line.empty())
          last = line; // a Python traceback ends with the actual error
      return last;
    }
  } // namespace

  std::string run_plot_script(const std::string &script_name, const std::vector<std::string> &args,
                              const std::string &png)
  {
    namespace fs = std::filesystem;
    const std::string what   = fs::path(png).filename().string();
    const std::string script = (script_directory() / script_name).string();
    if (!fs::exists(script))
      return "no " + script + " (" + what + " skipped)";
    std::string python = "python3";
    if (const char *env = std::getenv("COSIM_PYTHON"))
      python = env;
    else if (fs::exists("/usr/bin/python3"))
      python = "/usr/bin/python3"; // Debian's, where python3-matplotlib lives
    const std::string log = png + ".log";
    std::vector<std::string> argv = {python, script};
    argv.insert(argv.end(), args.begin(), args.end());
    const int status = run_program(argv, log);
    std::string reason;
    if (status == 127 || status == -1)
      reason = python + " not found (install python3 and python3-matplotlib; " + what + " skipped)";
    else if (status != 0)
      reason = first_line(log) + " (" + what + " skipped)";
    std::error_code ignored;
    fs::remove(log, ignored);
    return reason;
  }

  std::vector<std::string> curve_label_arguments(const CurveLabels &labels)
  {
    std::vector<std::string> args;
    auto add = [&](const char *option, double v) {
      if (v > 0 && std::isfinite(v))
        args.insert(args.end(), {option, number(v)});
    };
    if (!labels.group.empty())
      args.insert(args.end(), {"--group", labels.group});
    add("--spacing-mm", labels.particle_spacing * 1e3);
    add("--ucs-MPa", labels.measured_ucs * 1e-6);
    add("--E-GPa", labels.measured_youngs_modulus * 1e-9);
    add("--bts-MPa", labels.measured_bts * 1e-6);
    if (!labels.source.empty())
      args.insert(args.end(), {"--source", labels.source});
    return args;
  }

  std::string plot_curve(const std::string &history_csv, const std::string &test, const std::string &png,
                         const CurveLabels &labels)
  {
    std::vector<std::string> args = {history_csv, test, png};
    const std::vector<std::string> more = curve_label_arguments(labels);
    args.insert(args.end(), more.begin(), more.end());
    return run_plot_script("plot_curve.py", args, png);
  }
} // namespace app
