#pragma once
/// @file
/// Everything a case file says, validated and in SI units: the parts' own parameter structs
/// (sph::Parameters, sph::MaterialParameters, fem::Parameters) and what only a case has (its rock
/// group, the platens' interface and geometry, the loading path, the output). Each default lives
/// once, beside its member; the case-file keys (app/src/*_keys.cc) take them from here. Rock angles
/// are in radians, as sph stores them; the case file speaks degrees and converts where the key is
/// declared.

#include <coupling/contact.h>
#include <fem/parameters.h>
#include <sph/parameters.h>

#include <string>

namespace coupling
{
  /// What only the case knows about its rock: where its values come from and how they scatter.
  /// The material itself is CaseParameters::rock.
  struct RockCase
  {
    std::string group = "M1"; ///< material group M1..M10 (Table 3 / Table 4 of the paper)
    /// Source of c, phi: calibrated (Table 4), measured (Table 3) or brazilian (calibrated to UCS
    /// and to BTS at the disc centre's stress state)
    std::string strength_source = "calibrated";
    std::string data_directory; ///< folder of the group tables; empty = the shipped cases/data
    double ucs = 0.0;           ///< [Pa] the group's uniaxial strength (reporting, CSM estimates)
    double bts = 0.0;           ///< [Pa] the group's Brazilian tensile strength (reporting, CSM)
    double strength_scatter = 0.0; ///< [-] Weibull modulus of per-particle strength; 0 = homogeneous
    int scatter_seed = 1;          ///< seed of the strength scatter (same seed, same rock)
    /// [m] edge of the cubic cells that share one strength factor (the heterogeneity's
    /// correlation length, fixed in space so that refining the spacing resolves the same rock);
    /// 0 = one factor per particle
    double scatter_length = 0.0;
    /// Rate-dependent strength (sph/rate_strength.h): strength gain per decade of the nominal
    /// strain rate [-]; 0 = rate independent
    double rate_sensitivity = 0.0;
    double reference_strain_rate = 1e-5; ///< [1/s] rate at which the strengths are as given
  };

  /// The case's rock: the library's defaults, except that a case's rock softens (over a plastic
  /// strain of 2e-3) where sph's bare material does not.
  inline sph::MaterialParameters case_rock()
  {
    sph::MaterialParameters m;
    m.softening_strain = 2e-3;
    return m;
  }

  /// The case's platen steel: fem's defaults, except that a case's platens are rigid unless it
  /// says otherwise.
  inline fem::Parameters case_platen_steel()
  {
    fem::Parameters f;
    f.model = fem::SteelModel::rigid;
    return f;
  }

  /// Platens (and cutters): the steel body of fem plus the interface and geometry settings that
  /// fem does not have.
  struct PlatenParameters
  {
    fem::Parameters steel = case_platen_steel(); ///< model, E, nu, rho, element size of the body
    /// true: the element size follows the particle spacing (the driver's rule); false:
    /// steel.element_size as given
    bool element_size_from_spacing = true;
    double friction = 0.0;        ///< Coulomb (static) friction coefficient rock-platen [-]
    /// dynamic (sliding) friction coefficient [-]; < 0: the same as `friction`
    double dynamic_friction = -1.0;
    /// how the interface enforces contact: a penalty spring, the kinematic constraint, or
    /// automatic (the test's default: see contact_method())
    ContactMethod contact_method = ContactMethod::automatic;
    /// kinematic only: the rock tied to the platen once touched (no slip, no separation)
    bool bonded = false;
    /// kinematic on elastic platens: the contacts' joint solution stops when every end gap is
    /// below this fraction of the contact radius [-]
    double contact_tolerance = 1e-6;
    /// kinematic on elastic platens: a particle's force spread over its contact patch, sampled
    /// at this many points along each side (ContactParameters::patch_points) [-]; 0 = from the
    /// platen's element size h against the particle spacing dx: ceil((2 dx / h)^2), 1 to 4
    int contact_patch_points = 0;
    double thickness = 0.02;      ///< platen thickness along the loading axis [m]
    double diameter = 0.0;        ///< platen diameter (UCS/CTCS) or width (BTS) [m]; 0 = from specimen
    /// penalty stiffness / its stability bound at the rock's own step [-]; the coupled step is
    /// that step / sqrt(1 + scale) (coupling::coupled_time_step)
    double contact_stiffness_scale = 0.1;
    std::string shape = "flat";   ///< BTS: flat platens or ISRM curved jaws (jaw)
    double jaw_radius = 0.0;      ///< BTS jaw: radius of the contact arc [m]; 0 = 1.5 x disc radius
    /// Load-frame stiffness k_frame [N/m] in series with the top platen (fem/load_frame.h): the
    /// actuator moves at the loading rate, the platen by that minus F / k_frame, and the
    /// displacement is read at the actuator; 0 = a rigid frame (the platen is the actuator)
    double frame_stiffness = 0.0;
    /// Damping ratio zeta of the frame's dashpot, c = 2 zeta sqrt(k_frame m_platen) [-]
    double frame_damping_ratio = 1.0;
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
  /// its path, and the rock block. The tip angle in degrees: the cutting driver converts it.
  struct CutterParameters
  {
    std::string shape = "disc";     ///< wedge, cone, flat (cylindrical punch) or disc (CCS disc)
    double tip_angle = 90.0;        ///< wedge / cone included angle [deg] (fem::BodyGeometry: radians)
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
    std::string name;                ///< case name; empty = the case file's stem (results/<name>)
    std::string test = "UCS";        ///< UCS, BTS, CTCS, indentation or linear-cutting
    double diameter = 0.05;          ///< specimen diameter [m]
    double length = 0.1;             ///< UCS/CTCS: length; BTS: disc thickness [m]
    double confining_pressure = 0.0; ///< CTCS lateral pressure [Pa], compression positive
    /// BTS: loading angle 2 alpha of a flattened Brazilian disc [rad] (two flats 2 R sin(alpha)
    /// wide, the platens on them); 0 = the round disc
    double flat_angle = 0.0;
    sph::MaterialParameters rock = case_rock(); ///< the rock material (group values resolved)
    RockCase rock_case;              ///< the rock's group, strength source and scatter
    sph::Parameters sph;             ///< SPH numerics (TSSFAC as given; the body takes min(TSSFAC, 1))
    bool loaded_face_correction = true; ///< UCS/CTCS: boundary term lumped on the loaded layer
    /// UCS/CTCS cylinder, BTS disc: particles on a cubic lattice or body-fitted rings
    sph::ParticleArrangement particle_arrangement = sph::ParticleArrangement::lattice;
    PlatenParameters platens;
    LoadingParameters loading;
    OutputParameters output;
    CutterParameters cutter;         ///< indentation and linear-cutting only
  };
  /// The interface a case runs with: Platens/Contact method, automatic resolved to kinematic for
  /// UCS, BTS and CTCS (no stiffness to choose: the strengths, moduli and waves come out of the
  /// rock and steel alone) and to penalty for indentation and linear cutting (the cutter drivers
  /// have the penalty contact only).
  inline ContactMethod contact_method(const CaseParameters &p)
  {
    if (p.platens.contact_method != ContactMethod::automatic)
      return p.platens.contact_method;
    return p.test == "UCS" || p.test == "BTS" || p.test == "CTCS" ? ContactMethod::kinematic
                                                                  : ContactMethod::penalty;
  }

  /// The diameter of a UCS/CTCS cylinder platen: Platens/Diameter, 0 = 1.2 D, a size of the
  /// machine's, not of the discretisation (the overhang sets the peak on frictionless elastic
  /// steel: cases/studies/platens/README.md) [m].
  inline double cylinder_platen_diameter(const CaseParameters &p)
  {
    return p.platens.diameter > 0 ? p.platens.diameter : 1.2 * p.diameter;
  }

} // namespace coupling
