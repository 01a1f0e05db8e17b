#pragma once
/// @file
/// Everything a case file (.prm) says, validated and in SI units. Only coupling/app knows the .prm
/// format; the drivers take this plain struct. Angles are stored in degrees as users write them.

#include <string>

namespace coupling
{
  /// Rock material of one run, after the group lookup in cases/data and any explicit overrides.
  struct RockParameters
  {
    std::string group = "M1";          ///< material group M1..M10 (Table 3 / Table 4 of the paper)
    std::string model = "mohr-coulomb"; ///< elastic, mohr-coulomb, mohr-coulomb-cutoff, hoek-brown
    double density = 2900.0;           ///< [kg/m^3]
    double youngs_modulus = 97.07e9;   ///< [Pa]
    double poissons_ratio = 0.28;      ///< [-]
    double cohesion = 32.99e6;         ///< [Pa]
    double friction_angle = 63.68;     ///< [deg]
    double dilation_angle = 0.0;       ///< [deg] (non-associated flow when below friction_angle)
    double tensile_strength = 0.0;     ///< [Pa] tension cut-off; 0 = none (mohr-coulomb-cutoff)
    double hoek_brown_mi = 0.0;        ///< [-] Hoek-Brown m_i (hoek-brown)
    double ucs = 0.0;                  ///< [Pa] uniaxial strength sigma_ci (hoek-brown, reporting)
    double bts = 0.0;                  ///< [Pa] the group's Brazilian tensile strength (reporting, CSM)
    double softening_strain = 2e-3;    ///< [-] plastic strain over which strength falls to residual
    double residual_fraction = 0.1;    ///< [-] residual strength / peak strength
    double residual_friction_angle = -1; ///< [deg] friction angle of crushed rock (damage 1); < 0: none
    double strength_scatter = 0.0;     ///< [-] Weibull modulus of per-particle strength; 0 = homogeneous
    int scatter_seed = 1;              ///< seed of the strength scatter (same seed, same rock)
  };

  /// SPH numerics (names after LS-DYNA's *CONTROL_SPH / *SECTION_SPH).
  struct SphParameters
  {
    double spacing = 2.5e-3;      ///< particle spacing dx [m]
    int form = 8;                 ///< LS-DYNA FORM: 0, 1, 7 or 8
    double cslh = 1.2;            ///< h = CSLH * dx [-]
    double tssfac = 0.9;          ///< time-step scale factor [-]
    std::string kernel = "cubic"; ///< cubic or wendland
    bool evolve_smoothing_length = false; ///< dh/dt = (h/dim) div v
    double av_alpha = 1.0;        ///< Monaghan artificial viscosity, linear term [-]
    double av_beta = 1.0;         ///< Monaghan artificial viscosity, quadratic term [-]
    double hourglass = 0.1;       ///< total-Lagrangian hourglass coefficient [-]
    int n_threads = 0;            ///< 0 = all cores
    bool single_precision = true; ///< 3-D pair force in mixed precision (SPH/Pair force precision)
    bool loaded_face_correction = true; ///< UCS/CTCS: boundary term lumped on the loaded layer
  };

  /// Platens: rigid (prescribed motion) or elastic steel (deal.II FEM).
  struct PlatenParameters
  {
    std::string model = "rigid";  ///< rigid or elastic
    double friction = 0.0;        ///< Coulomb friction coefficient rock-platen [-]
    double youngs_modulus = 200e9; ///< steel [Pa]
    double poissons_ratio = 0.3;  ///< steel [-]
    double density = 7850.0;      ///< steel [kg/m^3]
    double thickness = 0.02;      ///< platen thickness along the loading axis [m]
    double diameter = 0.0;        ///< platen diameter (UCS/CTCS) or width (BTS) [m]; 0 = from specimen
    double element_size = 0.0;    ///< FEM element size [m]; 0 = from the particle spacing
    /// penalty stiffness / its stability bound at the rock's own step [-]; the coupled step is
    /// that step / sqrt(1 + scale) (coupling::coupled_time_step)
    double contact_stiffness_scale = 0.1;
    std::string shape = "flat";   ///< BTS: flat platens or ISRM curved jaws (jaw)
    double jaw_radius = 0.0;      ///< BTS jaw: radius of the contact arc [m]; 0 = 1.5 x disc radius
  };

  /// Loading path. A strain rate of 0 derives the rate from the specimen's wave transit time.
  struct LoadingParameters
  {
    double strain_rate = 0.0;      ///< nominal axial strain rate [1/s]; 0 = derived
    double transit_times = 40.0;   ///< when derived: load ramp to peak over this many wave transits
    double end_strain = 0.01;      ///< run stops at this nominal strain [-] (UCS/CTCS; BTS: d/D)
    double post_peak_drop = 0.2;   ///< run stops when the load fell this fraction below its peak
    double max_kinetic_ratio = 0.01; ///< quasi-static limit on kinetic/internal energy [-]
    double max_force_imbalance = 0.05; ///< quasi-static limit on |F_top-F_bottom|/F [-]
  };

  /// What the run writes besides summary and history.
  struct OutputParameters
  {
    int n_history_rows = 400;  ///< about this many history rows over the load path
    int n_snapshots = 20;      ///< particle / mesh snapshots over the load path
    bool progress = true;      ///< progress display on stderr
    int checkpoint_steps = 0;  ///< write checkpoint.h5 every this many steps; 0 = not by steps
    double checkpoint_minutes = 0; ///< ... and/or every this many minutes of wall time; 0 = not
    long stop_after_steps = 0; ///< stop with a checkpoint after this step (restart tests); 0 = no
  };

  /// Indentation and linear cutting: the cutter (an FEM body; model and steel from PlatenParameters),
  /// its path, and the rock block. Angles in degrees as users write them.
  struct CutterParameters
  {
    std::string shape = "disc";     ///< wedge, cone, flat (cylindrical punch) or disc (CCS disc)
    double tip_angle = 90.0;        ///< wedge / cone included angle [deg]
    double tip_radius = 0.0;        ///< wedge / cone tip rounding radius [m]; 0 = sharp
    double indenter_width = 0.02;   ///< wedge width across the tip, cone / punch diameter [m]
    double wedge_length = 0.02;     ///< wedge tip length along y [m]
    double disc_diameter = 0.4318;  ///< disc cutter diameter [m] (17 inch)
    double tip_width = 0.0127;      ///< CCS tip width [m]
    double penetration = 0.005;     ///< cutting: depth of cut; indentation: final depth [m]
    double line_spacing = 0.075;    ///< spacing between cuts [m] (CSM estimate only: one pass is cut)
    double speed = 4.0;             ///< cutting speed along x and indentation speed along -z [m/s]
    double cut_length = 0.08;       ///< distance cut along x [m]
    double block_length = 0.15;     ///< rock block along x (cutting direction) [m]
    double block_width = 0.1;       ///< rock block along y [m]
    double block_height = 0.05;     ///< rock block along z (depth) [m]
  };

  /// One case: the test, the specimen, and the parts.
  struct CaseParameters
  {
    std::string name = "ucs";        ///< case name (default output folder results/<name>)
    std::string test = "UCS";        ///< UCS, BTS, CTCS, indentation or linear-cutting
    double diameter = 0.05;          ///< specimen diameter [m]
    double length = 0.1;             ///< UCS/CTCS: length; BTS: disc thickness [m]
    double confining_pressure = 0.0; ///< CTCS lateral pressure [Pa], compression positive
    RockParameters rock;
    SphParameters sph;
    PlatenParameters platens;
    LoadingParameters loading;
    OutputParameters output;
    CutterParameters cutter;         ///< indentation and linear-cutting only
  };
} // namespace coupling
