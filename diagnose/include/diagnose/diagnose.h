#pragma once
/// @file
/// `cosim diagnose`: the discrepancy study on measured data (docs/design.md, "Measured data").
/// Readers of the data folder, the material-point surrogate with its candidate extensions, the
/// TAO fit, the evidence (BIC, held-out error) and the outputs. Units inside: MPa, mm, kN, s;
/// stresses compression-positive as the data files write them (the rock models in sph/ are
/// tension-positive; the surrogate converts where it calls them).

#include <array>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace coupling
{
  struct CaseParameters;
}

namespace diagnose
{
  /// One row of material.csv: what was measured for a group (empty cells: not measured).
  struct MaterialRow
  {
    std::string group;
    std::optional<double> E_GPa, nu, density, UCS_MPa, BTS_MPa, c_MPa, phi_deg;
  };

  /// One row of strength.csv: a specimen at failure, compression-positive principal stresses.
  struct StrengthRow
  {
    std::string test; ///< UCS, BTS, CTCS or TXE
    std::string group;
    double sigma1 = 0; ///< [MPa]
    double sigma3 = 0; ///< [MPa]; BTS: -BTS
    std::string where; ///< "file:line"
  };

  /// One curves/*.csv file: a load-frame record. `force` is the axial force the frame adds to the
  /// confinement (deviatoric load; UCS: the whole load).
  struct Curve
  {
    std::string file;
    std::string test; ///< UCS, CTCS or BTS
    std::string group;
    double diameter          = 0;    ///< [mm]
    double length            = 0;    ///< UCS/CTCS length or BTS thickness [mm]
    double confining         = 0;    ///< [MPa]
    bool platen_displacement = true; ///< displacement read at the platen (else on the specimen)
    /// Loaded to failure (header `failure: yes`, the default): its largest force is the
    /// specimen's strength. `failure: no`: a curve only (a stiffness test stopped before failure).
    bool failed = true;
    std::vector<double> time, displacement, force; ///< [s], [mm], [kN]
    /// Fewer than 5 rows: the specimen's peak only (too few points for the curve itself).
    bool peak_only() const { return time.size() < 5; }
  };

  /// A measured-data folder (any subset of the three kinds).
  struct Data
  {
    std::vector<MaterialRow> materials;
    std::vector<StrengthRow> strengths;
    std::vector<Curve> curves;
  };

  /// Reads DATA_DIR (material.csv, strength.csv, curves/*.csv). Throws InputError naming the file
  /// and line of the first bad row; throws when the folder holds none of the three.
  Data read_data(const std::string &folder);

  /// The fixed effect names (docs/design.md), `none` excluded.
  const std::vector<std::string> &effect_names();

  /// Reads a case of the coupled simulator: the default case with `overrides` ("Section/Key=value",
  /// in order) applied and checked, into `parameters`, and the complete case file of its values
  /// into `text` (the app's case-file reader; throws coupling::InputError).
  using CaseReader = std::function<void(const std::vector<std::string> &overrides,
                                        coupling::CaseParameters &parameters, std::string &text)>;

  /// Options of one study.
  struct Options
  {
    double bic_threshold = 10; ///< Delta BIC an effect must earn ("very strong", Kass-Raftery)
    /// > 0: run the coupled simulator on held-out specimens at this particle spacing [m] (a
    /// cylinder wider than 20 spacings is run at diameter / 20, and a specimen whose smallest
    /// dimension is under 10 spacings at a tenth of it), baseline and extended case
    double coupled_spacing = 0;
    int max_simulations    = 6;  ///< specimens the coupled simulator runs, at most
    CaseReader read_case;        ///< needed when coupled_spacing > 0
  };

  /// A fitted parameter with its standard error (from the Jacobian at the optimum).
  struct FittedValue
  {
    std::string name, unit;
    double value = 0, standard_error = 0;
  };

  /// One candidate's evidence.
  struct Candidate
  {
    std::string name;
    bool applicable = true; ///< false when the data cannot inform it (reason says why)
    std::string reason;
    std::vector<FittedValue> parameters;
    double delta_bic          = 0; ///< BIC(baseline refit) - BIC(candidate); > 0 favours it
    double delta_bic_baseline = 0; ///< BIC(baseline) - BIC(candidate)
    double error_before       = 0; ///< baseline RMS normalised error on all data [-]
    double error_after        = 0; ///< this candidate's [-]
    double heldout_before = 0, heldout_after = 0; ///< leave-one-out RMS normalised error [-]
  };

  /// Error summary of a model: RMS of residuals in their own units and normalised.
  struct ModelError
  {
    std::string model;
    double fit = 0, heldout = 0; ///< RMS normalised residual [-]
    double strength_rms_MPa = 0, heldout_strength_rms_MPa = 0;
    double curve_rms_mm = 0, heldout_curve_rms_mm = 0;
    /// Held-out RMS error on the discrepancy: the test conditions the baseline misses by more than
    /// 3 SDs of their replicate mean, in those SDs (leave-one-specimen-out predictions) [-]
    double discrepancy = 0;
    std::map<std::string, double> coupled; ///< coupled-simulator errors, when run
  };

  /// The name of the i-th (from 0) simulated specimen's files and rows: s1, s2, ...
  inline std::string simulation_stem(const std::size_t i)
  {
    return "s" + std::to_string(i + 1);
  }

  /// One coupled run of a simulated specimen: its case file and what it gave.
  struct SimulatedRun
  {
    std::string case_text;                     ///< the complete case file it ran
    std::vector<double> displacement_mm, force_kN; ///< its curve (deviatoric force; BTS: the load)
    double peak_MPa = 0; ///< sigma1 at the peak (BTS: 2P / (pi D t)) [MPa]
    /// the specimen's error: RMS of its two parts, (peak - measured) / noise and the RMS over its
    /// curve points of (displacement - measured) / noise [-]
    double error = 0;
    double curve_rms_mm = 0; ///< RMS displacement error on the pre-peak curve points [mm]
    std::string stop_reason;
    /// The run went unstable (or, for a heterogeneous rock, a run of its fit did): stop_reason
    /// says where; the peak and curve are those before it, and the specimen is left out of the
    /// coupled gain.
    bool unstable = false;
  };

  /// A measured specimen the coupled simulator ran, held out of the fit of the extended model's
  /// parameters: measured against the baseline case and the extended case.
  struct Simulation
  {
    std::string name; ///< the curve file or "file:line" of the strength row
    std::string test, group;
    double diameter_mm = 0, length_mm = 0, confining_MPa = 0;
    double particle_spacing = 0; ///< [m]
    double measured_peak_MPa = 0;
    int n_points = 0; ///< pre-peak curve points compared (0: a strength row, its peak only)
    std::vector<double> measured_displacement_mm, measured_force_kN; ///< the measured curve
    SimulatedRun baseline, extended;
  };

  /// The study's result.
  struct Diagnosis
  {
    std::vector<std::string> identified;
    /// Effects whose own Delta BIC comes within Options::bic_threshold of a named one's: the data
    /// cannot tell them apart from it (a competing explanation, not named).
    std::vector<std::string> indistinguishable;
    std::vector<Candidate> candidates;
    ModelError baseline, extended;
    double gain = 1, heldout_gain = 1;
    /// Baseline / extended held-out error on the discrepancy (ModelError::discrepancy): the gain
    /// where the baseline is wrong, undiluted by the data both models fit to the noise [-]
    double discrepancy_gain = 1;
    int n_discrepancy       = 0; ///< test conditions (or curve points) in the discrepancy
    /// The coupled simulator's held-out gain: RMS normalised error of the baseline case over
    /// the extended case's on the simulated specimens (Diagnosis::simulations) whose runs did
    /// not go unstable, when run; NaN when every specimen's did [-]
    double coupled_gain = 1;
    std::vector<Simulation> simulations;
    std::vector<FittedValue> extended_parameters;
    std::map<std::string, double> noise; ///< per data kind, what it came from in notes
    std::vector<std::string> notes;
    int n_strength = 0, n_curve_points = 0;
    std::string envelope_table; ///< CSV: group,sigma3_MPa,baseline_sigma1_MPa,extended_sigma1_MPa
    std::string
      points_table; ///< CSV: kind,source,group,test,sigma3_MPa,force_kN,measured,baseline,extended
  };

  /// Whether a simulated specimen is left out of Diagnosis::coupled_gain: a run of it unstable.
  inline bool left_out(const Simulation &m) { return m.baseline.unstable || m.extended.unstable; }

  /// The simulated specimens left out of Diagnosis::coupled_gain.
  inline int coupled_unstable(const Diagnosis &d)
  {
    int n = 0;
    for (const Simulation &m : d.simulations)
      n += left_out(m);
    return n;
  }

  /// Runs the study.
  Diagnosis diagnose(const Data &data, const Options &options);

  /// diagnosis.json text.
  std::string diagnosis_json(const Diagnosis &d);

  /// Writes diagnosis.json, report.md, envelope.csv and points.csv into `out` (created). `data_dir`
  /// is named in the report. std::runtime_error when a file cannot be written.
  void write_report(const std::filesystem::path &out, const Diagnosis &d, const std::string &data_dir);
} // namespace diagnose
