#pragma once
/// @file
/// The surrogate of `cosim diagnose`: a material-point model of each measured datum (strength
/// row, curve peak, pre-peak curve point) with the baseline and the candidate extensions, and the
/// TAO least-squares fit of a chosen set of extensions. Internal to coupling/src.

#include <coupling/case_parameters.h>
#include <diagnose/diagnose.h>

#include <functional>
#include <set>
#include <string>
#include <vector>

namespace diagnose
{

  /// A set of switched-on extensions (effect names).
  using EffectSet = std::set<std::string>;

  /// One datum the surrogate predicts.
  struct Datum
  {
    enum Kind
    {
      strength,    ///< sigma1 at sigma3 (compressive) or -BTS (BTS) [MPa]
      curve_point, ///< displacement at a force on a pre-peak curve [mm]
    } kind = strength;
    std::string test, group;
    double sigma3       = 0;    ///< confinement [MPa] (BTS: the measured -BTS, unused)
    double measured     = 0;    ///< sigma1 [MPa] / BTS [MPa] (positive) / displacement [mm]
    double force        = 0;    ///< curve point: deviatoric force [kN]
    double area         = 0;    ///< cross-section [mm^2] (BTS: D t)
    double length       = 0;    ///< specimen length [mm] (curve points)
    double slenderness  = 2;    ///< L/D [-] (strength rows: standard 2)
    double volume_ratio = 1;    ///< specimen volume / a 50x100 mm cylinder's [-]
    double strain_rate  = 0;    ///< [1/s]; 0: unknown (strength rows)
    bool platen         = true; ///< curve displacement read at the platen
    int source          = 0;    ///< index of the row / curve it came from
    int condition       = 0; ///< index of its test condition (replicates share one; held-out folds)
    std::string where;
  };

  /// A model parameter: name, unit, box, and whether the box is searched on a log scale.
  struct Parameter
  {
    std::string name, unit;
    double lo = 0, hi = 1, init = 0;
    bool log   = true;
    double off = 0; ///< the value at which the effect vanishes (for "at its bound" checks)
  };

  /// Per-group values the baseline takes from measurements.
  struct GroupBase
  {
    std::string group;
    double ucs = 0, phi = 0; ///< MC envelope: UCS [MPa], friction angle [deg]
    double E = 0;            ///< Young's modulus [MPa]
    std::string source;      ///< where they came from (report)
    double nu = 0.25;        ///< Poisson's ratio [-] (measured, else 0.25)
  };

  /// The surrogate for one effect set: parameter layout and predictions.
  class Surrogate
  {
  public:
    /// `refit`: the base strength (UCS per group, phi) is fitted; otherwise baseline values.
    Surrogate(const std::vector<GroupBase> &groups, const EffectSet &effects, bool refit);

    const std::vector<Parameter> &parameters() const { return parameters_; }
    const EffectSet &effects() const { return effects_; }
    /// Initial values (baseline, effects at their inits).
    std::vector<double> initial() const;
    /// The model's prediction of `d` with parameter values `p` [MPa or mm].
    double predict(const Datum &d, const std::vector<double> &p) const;
    /// Predicted sigma1 [MPa] at confinement s3 (compressive) for a standard specimen.
    double envelope(const std::string &group, double s3, const std::vector<double> &p) const;
    /// Predicted tensile strength [MPa] of a group.
    double tensile_strength(const std::string &group, const std::vector<double> &p) const;

  private:
    int group_index(const std::string &g) const;
    double value(const std::string &name, const std::vector<double> &p, double fallback) const;

    std::vector<GroupBase> groups_;
    EffectSet effects_;
    bool refit_;
    std::vector<Parameter> parameters_;
  };

  /// A fit result: values, standard errors and the weighted sum of squares.
  struct FitResult
  {
    std::vector<double> values, standard_errors;
    double chi2       = 0; ///< sum of (residual / noise)^2 [-]
    int n_evaluations = 0;
  };

  /// Least squares of (predict - measured)/noise over `data` with PETSc TAO (POUNDERS, bounded),
  /// from each start in `starts`; the best optimum is kept and, with `polish`, refined by a second
  /// run with a fresh trust region. `noise(d)` is the standard deviation of a datum.
  FitResult fit(const Surrogate &model, const std::vector<Datum> &data,
                const std::function<double(const Datum &)> &noise,
                const std::vector<std::vector<double>> &starts, bool polish = true);

  /// The rock and the effects of one simulated case, as the case file states them (MPa, deg,
  /// kN/mm; compression +).
  struct SimulatedRock
  {
    double E = 0, nu = 0.25, density = 2700;
    bool hoek_brown = false;
    double ucs = 0, phi = 30;   ///< Mohr-Coulomb through the UCS (Hoek-Brown: sigma_ci = ucs)
    double m_i      = 0;        ///< Hoek-Brown m_i
    double tensile  = 0;        ///< tension cut-off [MPa]; 0: none
    /// Strength factor of the specimen's size and strain rate (weakest link, rate law), applied
    /// to the UCS and the cut-off (the simulator loads at its own quasi-static rate) [-]
    double strength_factor = 1;
    double closure_ratio = 1, closure_stress = 1; ///< E0 / E [-], sigma_cc [MPa]
    double k_frame  = 0; ///< load frame [kN/mm]; 0: rigid
    double friction = 0; ///< platen friction coefficient [-]
    /// A heterogeneous crack-band rock (the rock that carries end friction's confinement; a
    /// homogeneous cylinder fails at its held rims first and is weakened by friction): Weibull
    /// modulus of the strength scatter; 0: homogeneous, the case's own softening.
    double weibull_m = 0;
    /// The strength [MPa] that the heterogeneous rock's standard specimen (50 x 100 mm, the
    /// platens' friction) carries on the mean of its realisations: simulate() scales the
    /// strengths to it (its fracture energy follows: the case's rock's brittleness).
    double calibration_peak = 0;
    /// What the extended model says the data's shortest compressive specimen (D x L [mm])
    /// carries [MPa]: simulate() fits the rock's brittleness to it
    double short_peak = 0, short_diameter = 0, short_length = 0;
    /// The strength scale found by simulate() [-]
    double calibration_factor = 1;
    /// The heterogeneous rock's characteristic length E G_I / f_t^2 [m] (its fracture energy
    /// follows at any strength), found by simulate()
    double characteristic_length = 0;
    std::vector<std::string> notes; ///< comment lines for the case file
  };

  /// A measured specimen for the coupled simulator, with the baseline and the extended rock (the
  /// extended one fitted without this specimen).
  struct SimulatorTarget
  {
    std::string name, test, group;
    double diameter = 50, length = 100, sigma3 = 0; ///< [mm, mm, MPa]
    double measured_peak = 0, peak_noise = 1;       ///< sigma1 or BTS and its noise [MPa]
    bool has_peak        = true;                    ///< false: a curve without failure
    bool platen          = true; ///< curve displacement read at the platen (else gauge)
    std::vector<Datum> points;   ///< pre-peak curve points (Datum::measured: displacement)
    std::vector<double> point_noise; ///< [mm]
    const Curve *curve = nullptr;    ///< the whole measured curve, or none (a strength row)
    double end_strain  = 0.01;       ///< where the run stops at the latest (BTS: d / D)
    SimulatedRock baseline, extended;
  };

  /// Runs the coupled simulator on each target with its baseline and its extended rock at
  /// options.coupled_spacing (cases read by options.read_case); fills out.simulations, the
  /// baseline's and extended model's ModelError::coupled and out.coupled_gain.
  void simulate(const std::vector<SimulatorTarget> &targets, const Options &options,
                Diagnosis &out);

  /// The length [in units of D] by which ends held by platen friction shorten a cylinder's
  /// platen-read compliance: its platen displacement is (q / E) (L - c D) where elastic free
  /// slip gives (q / E) L. Rigid platens holding the end faces (no slip: platen friction of 0.3
  /// and more holds them) confine an end zone about a diameter long whose stiffening does not
  /// depend on L; c = nu^2 (0.526 + 0.022 nu + 0.476 nu^2), fitted to the finite element
  /// solution of `cosim reference --interface bonded` (elastic, mesh 16, L/D 1, nu 0.1-0.4:
  /// within 0.12 % of c; at L/D 1/2 and 2, nu 0.25, the same c within 2 %).
  double held_end_shortening(double nu);

  /// Strain of the specimen axis at deviatoric stress q on top of confinement s3 under the
  /// crack-closure law (compression +) [-]; plain q / E when the ratio r = E0/E is 1.
  double closure_axial_strain(double q, double s3, double E, double r, double sigma_cc);
} // namespace diagnose
