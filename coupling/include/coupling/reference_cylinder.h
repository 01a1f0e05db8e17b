#pragma once
/// @file
/// An independent reference for the coupled UCS: a quasi-static, implicit finite element model of
/// the rock cylinder between platens (deal.II, axisymmetric in (r, z), small strain, Newton with a
/// finite-difference consistent tangent, displacement-controlled increments). The rock is linear
/// elastic + perfectly plastic Mohr-Coulomb (non-associated, dilation psi, optional tension
/// cut-off) or Hoek-Brown (its plastic potential as sph's), updated by the SPH rock's own return
/// mapping (sph/rock_models.h), with softening and strength scatter switched off. The platens
/// are rigid (prescribed axial displacement of the end
/// faces) or elastic steel meshed as their own regions, tied to the rock at conforming interface
/// nodes: bonded (u_r and u_z tied) or free-slip (u_z tied, u_r free, no friction). The tie assumes
/// the interface never opens, which holds while the specimen is compressed.
///
/// Stresses are tension-positive inside; everything this header returns is compression-positive
/// (as the paper's tables), SI units. No deal.II types here: the header is included by app/.

#include <coupling/case_parameters.h>
#include <sph/rock_models.h>

#include <array>
#include <string>
#include <vector>

namespace coupling
{
  /// How the platens hold the rock's end faces.
  enum class ReferenceInterface
  {
    bonded,   ///< both displacement components tied (no slip)
    free_slip ///< only u_z tied; u_r free (frictionless)
  };

  /// What the platens are.
  enum class ReferencePlatens
  {
    rigid,  ///< the rock's end faces are displaced as a rigid platen would
    elastic ///< steel platens meshed as their own regions, displaced on their outer faces
  };

  /// Numerics and loading of the reference.
  struct ReferenceOptions
  {
    ReferenceInterface interface = ReferenceInterface::free_slip;
    ReferencePlatens platens     = ReferencePlatens::rigid;
    unsigned int n_radial = 8; ///< elements across the specimen radius (axially: the same size)
    unsigned int degree   = 2; ///< polynomial degree of the quadrilaterals (1 or 2)
    unsigned int n_increments =
      50;                     ///< load increments up to end_strain (halved where Newton fails)
    double end_strain = 0.01; ///< platen displacement / specimen length at the end [-]
  };

  /// One converged load increment.
  struct ReferenceCurveRow
  {
    double platen_displacement = 0; ///< approach of the two loaded faces [m]
    double strain           = 0; ///< specimen axial strain: approach of its end faces / length [-]
    double radial_strain    = 0; ///< u_r / R at the specimen's mid-height surface (expansion +) [-]
    double force            = 0; ///< axial force on the loaded face (compression +) [N]
    double stress           = 0; ///< force / initial cross-section (compression +) [Pa]
    unsigned int iterations = 0; ///< Newton iterations of the increment
  };

  /// Stress at one Gauss point (compression +).
  struct ReferenceStressSample
  {
    double r = 0, z = 0;      ///< position [m]
    double axial_stress  = 0; ///< -sigma_zz [Pa]
    double radial_stress = 0; ///< -sigma_rr [Pa]
  };

  /// What a reference run gives.
  struct ReferenceResult
  {
    std::vector<ReferenceCurveRow>
      curve;                         ///< one row per converged increment, from the unloaded state
    double peak_force           = 0; ///< largest axial force [N]
    double peak_stress          = 0; ///< peak_force / initial cross-section [Pa]
    double strain_at_peak       = 0; ///< specimen strain at the peak [-]
    double displacement_at_peak = 0; ///< platen displacement at the peak [m]
    double half_peak_force      = 0; ///< force of the profiles below [N] (peak / 2 on the way up)
    /// Stress at half the peak load along the top end face, vs r: the Gauss points nearest the face
    /// (z tells how near), interpolated linearly in the force between two increments.
    std::vector<ReferenceStressSample> end_face;
    /// The same along the axis, vs z: the Gauss points nearest r = 0.
    std::vector<ReferenceStressSample> axis;
    double platen_diameter = 0; ///< elastic platens [m]; 0 with rigid ones
    unsigned int n_cells = 0, n_dofs = 0;
    unsigned int n_newton_iterations = 0; ///< over all increments
    unsigned int n_cutbacks          = 0; ///< increments halved after a failed Newton solve
    /// Why the curve ends: "end strain", "limit load: ..." (the force constant over three
    /// increments) or "Newton did not converge at ..." (the curve is cut short)
    std::string end_reason;
    /// True when the curve reached the end strain or the limit load.
    bool complete() const { return end_reason.rfind("Newton", 0) != 0; }
    double wall_seconds = 0;
  };

  /// Runs the reference for the UCS case `prm` (its specimen, rock and platens). InputError (one
  /// line) for a case it cannot model: not UCS, bad options.
  ReferenceResult run_reference_cylinder(const CaseParameters &prm,
                                         const ReferenceOptions &options);

  /// The case's rock as the reference uses it: perfectly plastic (no softening, no residual
  /// friction angle, no scatter).
  sph::MaterialParameters reference_rock(const CaseParameters &prm);

  /// Diameter of the elastic platens [m]: Platens/Diameter, or, where it is 0, the coupled
  /// driver's rule (specimen diameter + 4 particle spacings).
  double reference_platen_diameter(const CaseParameters &prm);

  /// Axisymmetric Voigt vectors: (rr, zz, theta-theta, rz); strains with the engineering shear
  /// gamma_rz = 2 eps_rz, stresses tension-positive [Pa].
  using Voigt4 = std::array<double, 4>;
  /// d sigma / d eps in that order [Pa].
  using Tangent4 = std::array<std::array<double, 4>, 4>;

  /// The stress update of one rock point and its tangent.
  struct ReferencePointUpdate
  {
    Voigt4 stress;            ///< new stress [Pa]
    Tangent4 tangent;         ///< d stress / d strain increment [Pa]
    sph::MaterialState state; ///< new history
    bool plastic = false;     ///< the return mapping was active
  };

  /// sph's update of `model` from the converged stress and history by `strain_increment` (3x3
  /// tensors with r -> 0, z -> 1, theta -> 2), with the tangent: isotropic elastic where the
  /// update is elastic, else forward differences of the update (step 1e-9 in each strain).
  ReferencePointUpdate reference_point_update(const sph::rock::Model &model,
                                              const sph::rock::ModelConstants &constants,
                                              const Voigt4 &stress_old,
                                              const sph::MaterialState &state_old,
                                              const Voigt4 &strain_increment);
} // namespace coupling
