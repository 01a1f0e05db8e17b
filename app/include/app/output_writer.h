#pragma once
/// @file
/// The files of a result folder: summary.json, history.csv, results.h5 (+ results.xdmf for
/// ParaView) and curve.png. Units in the file are SI-prefixed as the column / key names say.

#include <coupling/run_output.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace app
{
  /// How a run ended: summary.json's "status".
  enum class RunStatus
  {
    completed,   ///< ran to its stop criterion; every result key has its value
    unstable,    ///< stopped by the stability checks; the folder is OUTDIR.failed
    interrupted, ///< stopped by SIGINT / SIGTERM after writing a checkpoint
    failed       ///< stopped by another error
  };

  /// "completed", "unstable", "interrupted" or "failed".
  std::string to_string(RunStatus status);

  /// What summary.json says beside a completed run's Summary: the outcome and, for a run that did
  /// not complete (no Summary), what is known of it.
  struct RunEnd
  {
    RunStatus status = RunStatus::completed;
    std::string message;            ///< why the run stopped early; "" (null) when completed
    std::string test;               ///< test type, used when there is no Summary
    double wall_seconds = -1;       ///< [s], used when there is no Summary; < 0: null
    long n_steps = -1;              ///< steps done, used when there is no Summary; < 0: null
    long last_good_step = -1;       ///< unstable: step of last_good_state.h5; < 0: none (null)
    double last_good_time = 0;      ///< unstable: its time [s]
    std::string checkpoint;         ///< interrupted: the checkpoint file; "" (null) otherwise
    std::string restart_command;    ///< interrupted: the command that continues it; "" (null) otherwise
  };

  /// summary.json text (nlohmann-json), one schema for every outcome: `schema_version` (1),
  /// `status`, `cosim_version`, `commit`, `message`, then every Summary key as docs/design.md
  /// names it (units in the name; compression positive), then `last_good_state`, `checkpoint`,
  /// `restart`. Every one of these keys is always present; a key without a value for this
  /// outcome is null (summary == nullptr: every result key but test, n_steps and wall_seconds).
  /// A completed run adds its test type's further results (Summary::extra) after the fixed keys.
  /// Top-level keys one per line, nested values on the key's line.
  std::string summary_json(const coupling::Summary *summary, const RunEnd &end);

  /// In a child process after fork(): stdout to /dev/null, stderr into the file `log`
  /// (created or truncated). Only open() and dup2(): safe between fork() and exec().
  void redirect_child_output(const char *log);

  /// summary.json text of a completed run.
  std::string summary_json(const coupling::Summary &summary);

  /// What a summary.json file says: its status ("completed", "unstable", ...) and, for a
  /// completed run, the Summary it was written from (SI units again; the further results in the
  /// file's order). InputError (one line naming the file) when it cannot be read or is not a
  /// summary.json of this schema.
  struct SummaryFile
  {
    std::string status;
    std::optional<coupling::Summary> summary;
  };
  SummaryFile read_summary_json(const std::string &path);

  /// Column names of history.csv, in order.
  const std::vector<std::string> &history_columns();

  /// Writes history.csv (header, one row per HistoryRow). Throws std::runtime_error on I/O errors.
  void write_history_csv(const std::string &path, const std::vector<coupling::HistoryRow> &rows);

  /// Writes `text` to `path`; std::runtime_error on failure.
  void write_text_file(const std::string &path, const std::string &text);

  /// results.h5 written as the run goes (HDF5 C API) and its results.xdmf companion (XDMF 3, for
  /// ParaView). Every dataset has a string attribute `units` ("1": dimensionless; "index":
  /// connectivity); the root has `cosim_version` and `commit`.
  /// Layout: /history/<column> (1-D, units as in history.csv); /snapshots/NNNNNN with attribute
  /// time_s, particles/{position, velocity, displacement (n x 3) [m, m/s, m];
  /// stress (n x 6) [Pa], tension positive, components in XDMF's Tensor6 order xx,xy,xz,yy,yz,zz
  /// (attribute `components`); von_mises (n) [Pa]; mean_stress_compression_positive (n)
  /// -(xx+yy+zz)/3 [Pa]; plastic_strain, damage (n) [1]} and meshes/<name>/{position,
  /// displacement (n x 3) [m], hexahedra (cells x 8, VTK order), von_mises (cells) [Pa]};
  /// /particle_vertices/<n>: 0..n-1, the Polyvertex connectivity of an n-particle snapshot.
  class ResultsFile
  {
  public:
    /// Creates (truncates) the HDF5 file. std::runtime_error when it cannot.
    explicit ResultsFile(const std::string &h5_path);
    ~ResultsFile();
    ResultsFile(const ResultsFile &) = delete;
    ResultsFile &operator=(const ResultsFile &) = delete;

    /// Appends one snapshot. A distributed body's (ParticleSnapshot::global_index) is written
    /// by all MPI ranks together: every other rank calls write_particle_rows meanwhile.
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

  /// The rows of a distributed body's snapshot (ParticleSnapshot::global_index) written into
  /// the particle datasets of `group` (e.g. "/snapshots/000003") of the HDF5 file `h5_path`, by
  /// all ranks of MPI_COMM_WORLD together (parallel HDF5, collective): rank 0's ResultsFile calls
  /// it from add_snapshot, having made the datasets, and every other rank calls it with the same
  /// snapshot count (its path and group are taken from rank 0). std::runtime_error on failure.
  void write_particle_rows(std::string h5_path, std::string group, const coupling::ParticleSnapshot &particles);

  /// Runs tools/`script_name` with `args` under python3 ($COSIM_PYTHON if set), expected to write
  /// `png`. Returns "" on success, else a one-line reason (python3 or matplotlib missing: the
  /// script's last stderr line) ending in "(<png file name> skipped)".
  std::string run_plot_script(const std::string &script_name, const std::vector<std::string> &args,
                              const std::string &png);

  /// What curve.png says beside the curve: the case and the rock group's measured values.
  struct CurveLabels
  {
    std::string group;              ///< rock group, e.g. "M1"; "" = not shown
    double particle_spacing = 0;    ///< [m]; 0 = not shown
    double measured_ucs = 0;        ///< the group's measured UCS [Pa]; 0 = none
    double measured_youngs_modulus = 0; ///< the group's measured E [Pa]; 0 = none
    double measured_bts = 0;        ///< the group's measured BTS [Pa]; 0 = none
    std::string source;             ///< where the measured values come from, e.g. "Table 3"
  };

  /// The script arguments of plot_curve.py for `labels` (--group, --spacing-mm, --ucs-MPa, ...).
  std::vector<std::string> curve_label_arguments(const CurveLabels &labels);

  /// Runs tools/plot_curve.py on history.csv to make curve.png. Returns "" on success, else a
  /// one-line reason (python3 or matplotlib missing, script failed).
  std::string plot_curve(const std::string &history_csv, const std::string &test, const std::string &png,
                         const CurveLabels &labels = {});
} // namespace app
