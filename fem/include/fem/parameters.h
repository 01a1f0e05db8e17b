#pragma once
/// @file
/// Plain parameter structs of the fem library: the platen model and material, and its geometry.
/// No deal.II types here: coupling code includes this header and must compile fast.

namespace fem
{
  /// Rigid: prescribed motion of every node, no internal force, reaction = inertia - contact
  /// forces. Elastic: linear elastic Q1 hexahedra, explicit central differences, lumped mass.
  enum class SteelModel
  {
    rigid,
    elastic
  };

  /// Shape of the platen body.
  enum class BodyShape
  {
    cylinder, ///< disc of `diameter` and `thickness`, axis along z (UCS, CTCS)
    box,      ///< flat block `size_x` x `size_y` x `thickness` (BTS)
    jaw,      ///< ISRM curved loading jaw: the box with its contact face a concave circular arc
              ///< of radius `jaw_radius` about an axis along y, cradling the disc (BTS; ISRM:
              ///< 1.5 x the disc radius)
    wedge,    ///< wedge indenter: the box with its contact face a V of half-angle `tip_half_angle`,
              ///< the tip a line along y at x = center_x, z = contact_z
    cone,     ///< conical indenter: the cylinder with its contact face a cone of half-angle
              ///< `tip_half_angle`, the tip at (center_x, center_y, contact_z)
    disc_cutter ///< constant-cross-section (CCS) disc cutter: the lowest segment of a disc of
                ///< radius `cutter_radius`, axis along y, flat tip of width `size_y` (flanks not
                ///< modelled), chord `size_x` along x; the tip line at x = center_x, z = contact_z
  };

  /// Which side of the contact plane z = contact_z the platen body lies on.
  enum class BodySide
  {
    above, ///< top platen: body in [contact_z, contact_z + thickness], contact normal -z
    below  ///< bottom platen: body in [contact_z - thickness, contact_z], contact normal +z
  };

  /// Lateral (x, y) condition on the loaded face. z is always prescribed there.
  enum class LoadedFaceLateral
  {
    fixed, ///< x, y velocities of the loaded face are zero (a platen clamped in the frame)
    free   ///< only z is prescribed: x, y are free (frictionless machine contact)
  };

  /// Boundary ids of the platen mesh.
  namespace boundary_id
  {
    constexpr unsigned int free_faces = 0; ///< lateral hull / sides: traction free
    constexpr unsigned int loaded     = 1; ///< face opposite the contact face: prescribed motion
    constexpr unsigned int contact    = 2; ///< face in the plane z = contact_z, touches the rock
  }                                        // namespace boundary_id

  /// Geometry of one platen. Lengths [m]. The body is centred on (center_x, center_y).
  struct BodyGeometry
  {
    BodyShape shape = BodyShape::cylinder;
    double diameter   = 0.07;   ///< cylinder diameter [m]
    double size_x     = 0.07;   ///< box extent along x [m]
    double size_y     = 0.04;   ///< box extent along y [m]
    double jaw_radius = 0.0375; ///< jaw: radius of the contact arc [m]; > size_x / 2
    double thickness  = 0.02;   ///< extent along z [m]; wedge, cone, disc_cutter: tip to loaded face
    /// wedge, cone: angle between the axis (z) and a flank [rad] (0.5 x the included angle).
    double tip_half_angle = 1.0471975511965976;
    double cutter_radius  = 0.2159; ///< disc_cutter: disc radius [m] (17-inch cutter: 0.2159)
    /// wedge, cone: radius of the rounded tip [m], tangent to the flanks; 0 = sharp.
    double tip_radius = 0.0;
    double contact_z  = 0.0;    ///< z of the contact face [m]
    double center_x   = 0.0;    ///< [m]
    double center_y   = 0.0;    ///< [m]
    BodySide side   = BodySide::above;
  };

  /// Model, material and numerics of one platen. Defaults: elastic steel.
  struct Parameters
  {
    SteelModel model     = SteelModel::elastic;
    double youngs_modulus = 200e9;  ///< E [Pa]
    double poissons_ratio = 0.3;    ///< nu [-]
    double density        = 7850.0; ///< rho [kg/m^3]
    /// Stiffness-proportional (Rayleigh beta) damping: f_damp = beta K v. beta [s]; 0 = none.
    double stiffness_damping = 0.0;
    /// Target element edge length [m]; the mesh uses the nearest size its generator can make
    /// (not larger than about 1.5 times this).
    double element_size = 0.005;
    /// stable_time_step() = safety * (critical step from the power-iteration lambda_max) [-].
    double time_step_safety               = 0.9;
    LoadedFaceLateral loaded_face_lateral = LoadedFaceLateral::fixed;
    /// Elastic only: true leaves every dof free, a body with no prescribed motion (impact and
    /// wave checks). The loaded face is then traction free and reaction_force() is zero;
    /// set_loaded_face_velocity() throws.
    bool free_body = false;
    /// Power iteration for lambda_max(M^-1 K): iteration cap and relative residual to stop at.
    unsigned int power_iteration_max = 2000;
    double power_iteration_tolerance = 1e-4;
  };
} // namespace fem
