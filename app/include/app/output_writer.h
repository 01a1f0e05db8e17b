#pragma once
/// @file
/// The files of a result folder: summary.json, history.csv, results.h5 (+ results.xdmf for
/// ParaView) and curve.png. Units in the file are SI-prefixed as the column / key names say.

#include <coupling/run_output.h>

#include <memory>
#include <string>
#include <vector>

namespace app
{
  /// summary.json text: every Summary field, names as docs/design.md lists them (units in the name).
  std::string summary_json(const coupling::Summary &summary);

  /// Column names of history.csv, in order.
  const std::vector<std::string> &history_columns();

  /// Writes history.csv (header, one row per HistoryRow). Throws std::runtime_error on I/O errors.
  void write_history_csv(const std::string &path, const std::vector<coupling::HistoryRow> &rows);

  /// Writes `text` to `path`; std::runtime_error on failure.
  void write_text_file(const std::string &path, const std::string &text);

  /// results.h5 written as the run goes (HDF5 C API) and its results.xdmf companion.
  /// Layout: /history/<column> (1-D, units as in history.csv); /snapshots/NNNNNN with attribute
  /// time_s, particles/{position,velocity,displacement (n x 3) [m, m/s], stress (n x 6,
  /// xx,yy,zz,yz,xz,xy, tension + [Pa]), plastic_strain, damage (n)} and meshes/<name>/{position,
  /// displacement (n x 3), hexahedra (cells x 8, VTK order), von_mises (cells) [Pa]}.
  class ResultsFile
  {
  public:
    /// Creates (truncates) the HDF5 file. std::runtime_error when it cannot.
    explicit ResultsFile(const std::string &h5_path);
    ~ResultsFile();
    ResultsFile(const ResultsFile &) = delete;
    ResultsFile &operator=(const ResultsFile &) = delete;

    /// Appends one snapshot.
    void add_snapshot(double time, const coupling::ParticleSnapshot &particles, const std::vector<coupling::MeshSnapshot> &meshes);
    /// Writes the history table (once, at the end).
    void write_history(const std::vector<coupling::HistoryRow> &rows);
    /// Closes the HDF5 file and writes the XDMF file that points into it (relative path).
    void close(const std::string &xdmf_path);

    /// Copies the snapshots of another results.h5 taken at times <= `until` [s] (a restart: the
    /// interrupted run's snapshots up to its checkpoint) as the first ones of this file. Returns
    /// how many; 0 when the file is missing or unreadable (a hard-killed run's may be).
    std::size_t copy_snapshots(const std::string &h5_path, double until);
    /// Number of snapshots so far.
    std::size_t n_snapshots() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
  };

  /// Runs tools/`script_name` with `args` under python3 ($COSIM_PYTHON if set), expected to write
  /// `png`. Returns "" on success, else a one-line reason (python3 or matplotlib missing: the
  /// script's last stderr line) ending in "(<png file name> skipped)".
  std::string run_plot_script(const std::string &script_name, const std::vector<std::string> &args,
                              const std::string &png);

  /// Runs tools/plot_curve.py on history.csv to make curve.png. Returns "" on success, else a
  /// one-line reason (python3 or matplotlib missing, script failed).
  std::string plot_curve(const std::string &history_csv, const std::string &test, const std::string &png);
} // namespace app
