#pragma once
/// @file
/// A steel body (a loading platen or a cutter), rigid or linear elastic, for the SPH-FEM
/// co-simulation.
/// Plain data in and out, no deal.II types (the implementation lives behind a pointer).
///
/// Conventions
/// - SI units. Flat 3-vectors: x0,y0,z0,x1,y1,z1,...
/// - Forces are forces ON the platen. reaction_force() is the z-component of the force the load
///   frame applies to the platen through the loaded face (a top platen pressing down on rock
///   reads negative; compressive_force() gives it compression-positive for either side).
/// - Time levels: after step(t, dt) the platen holds u(t+dt) and v(t+dt/2). contact_positions()
///   are x0 + u(t+dt); contact_velocities() are v(t+dt/2) (the usual half-step lag of central
///   differences). Energies live at t+dt/2: kinetic 1/2 v M v with v(t+dt/2), strain
///   1/2 u(t+dt) . K u(t); kinetic + strain + damping_dissipation - external_work is then the
///   quantity central differences conserve (to round-off at constant dt).
///
/// Lifecycle per coupled time step, at time t with step dt <= stable_time_step():
///   1. read contact_positions() / contact_velocities() (and contact_faces(), fixed),
///   2. the coupler computes contact forces and calls add_contact_forces(f) (any number of times),
///   3. step(t, dt): a = M^-1 (f_ext - K u - beta K v), v += dt a, u += dt v, prescribed motion
///      imposed on the loaded face, reaction measured, external forces cleared.

#include <fem/mesh_snapshot.h>
#include <fem/parameters.h>

#include <array>
#include <cstddef>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace fem
{
  /// A rigid or elastic steel body (platen or cutter): mesh, explicit dynamics, load cell and
  /// coupling interface.
  class SteelBody
  {
  public:
    /// Builds the mesh, the lumped mass and (elastic) the stiffness. Throws std::invalid_argument
    /// with an actionable message on non-positive sizes or material constants.
    SteelBody(const BodyGeometry &geometry, const Parameters &parameters = Parameters());
    ~SteelBody();
    SteelBody(SteelBody &&) noexcept;
    SteelBody &operator=(SteelBody &&) noexcept;
    SteelBody(const SteelBody &)            = delete;
    SteelBody &operator=(const SteelBody &) = delete;

    /// Prescribed z-velocity [m/s] of the loaded face as a function of time t [s]; evaluated at
    /// half steps. Default: fixed (zero). Rigid: the velocity of the whole body.
    void set_loaded_face_velocity(std::function<double(double)> velocity_z);
    /// Prescribed x-velocity [m/s] of the loaded face (rigid: of the whole body) as a function of
    /// time t [s], for a cutter that translates. Default: zero. An elastic platen needs
    /// LoadedFaceLateral::fixed for it to act (with `free` the loaded face's x is not prescribed).
    void set_loaded_face_velocity_x(std::function<double(double)> velocity_x);

    // ---- sizes and constants ------------------------------------------------------------
    bool is_rigid() const;
    std::size_t n_nodes() const;     ///< mesh vertices
    std::size_t n_cells() const;     ///< hexahedra
    double total_mass() const;       ///< sum of the lumped nodal masses [kg]
    double mesh_volume() const;      ///< volume of the (trilinear) mesh [m^3]
    double contact_normal_z() const; ///< -1 (top platen) or +1 (bottom): outward normal z
    /// Largest eigenvalue of M^-1 K [1/s^2] by power iteration (0 for a rigid platen).
    double max_eigenvalue() const;

    // ---- coupling interface: contact-face nodes -----------------------------------------
    std::size_t n_contact_nodes() const;
    std::vector<double> contact_positions() const;  ///< current x0 + u [m], 3 per node
    std::vector<double> contact_velocities() const; ///< [m/s], 3 per node
    /// Acceleration [m/s^2] of the contact nodes from the body's own forces at the current state,
    /// M^-1 (-K u - beta K v), 3 per node: what the next step() adds to their velocity besides the
    /// contact forces (0 for a rigid body and for prescribed dofs). A constraint contact predicts
    /// with it where the face ends the step.
    std::vector<double> contact_free_accelerations() const;
    /// Lumped nodal masses [kg] (also for a rigid platen; use is_rigid() to treat it as rigid).
    std::vector<double> contact_masses() const;
    /// Tributary areas of the contact nodes, integral of the shape function over the face [m^2].
    std::vector<double> contact_areas() const;
    /// Quads over the contact nodes, 4 indices each in cyclic order, normal (p1-p0)x(p3-p0)
    /// pointing out of the platen (towards the rock).
    const std::vector<unsigned int> &contact_faces() const;
    /// Accumulate external forces [N] on the contact nodes (3 per node, forces on the platen).
    /// They act in the next step() and are cleared by it. Throws on a wrong size.
    void add_contact_forces(const std::vector<double> &forces);

    // ---- time stepping ------------------------------------------------------------------
    /// safety * critical step of central differences [s]: 2/sqrt(lambda_max), reduced for
    /// stiffness damping to (2/omega)(sqrt(1+xi^2)-xi), xi = beta omega/2. Rigid: +infinity.
    double stable_time_step() const;
    /// Advance from t to t + dt [s]. See the lifecycle in the file comment.
    void step(double t, double dt);
    double time() const; ///< time reached by the last step [s]

    // ---- load cell and energies -----------------------------------------------------------
    /// z-force [N] that the frame applies to the platen at the loaded face, along +z, at the
    /// start of the last step: M a + K u + beta K v - f_ext summed over the prescribed z dofs.
    double reaction_force() const;
    /// The full force [N] (x, y, z) that the frame applies to the platen at the loaded face at the
    /// start of the last step (rigid: M a - contact forces; z component = reaction_force()).
    std::array<double, 3> reaction_force_vector() const;
    /// reaction_force() signed so that pushing into the specimen is positive [N].
    double compressive_force() const;
    /// Mean z-displacement of the loaded face [m].
    double loaded_face_displacement() const;
    /// Mean z-displacement of the contact face [m].
    double contact_face_displacement() const;
    double kinetic_energy() const; ///< 1/2 v M v [J]
    /// 1/2 u(t+dt) . K u(t) [J], the strain energy at the half step (0 for rigid).
    double strain_energy() const;
    /// Work of contact forces and of the prescribed-motion reaction [J]: sum over steps of
    /// f(t_n) . (u(t_n+1) - u(t_n-1)) / 2, the increment that central differences conserve.
    double external_work() const;
    double damping_dissipation() const; ///< energy taken by stiffness damping [J]

    // ---- output and checks ----------------------------------------------------------------
    /// The mesh now, unnamed (MeshSnapshot::name empty: the caller names it).
    MeshSnapshot mesh_snapshot() const;
    void write_vtu(const std::string &filename) const;
    /// Reference vertex positions [m] and lumped masses [kg] in snapshot vertex order.
    std::vector<double> reference_positions() const;
    std::vector<double> nodal_masses() const;
    /// K u [N] for a vertex displacement field u (snapshot vertex order); zeros for rigid.
    std::vector<double> internal_force(const std::vector<double> &displacement) const;
    /// Overwrite the state (snapshot vertex order): for initial conditions and tests.
    void set_state(const std::vector<double> &displacement, const std::vector<double> &velocity);

    // ---- checkpoints ------------------------------------------------------------------------
    /// Adds everything that changes during a run (u, v, K u, K v, pending forces, the last
    /// increment, time, rigid velocity, reaction, work, dissipation, strain energy) to `out` as
    /// flat arrays named `prefix` + name. load_state on a platen built with the same geometry and
    /// parameters continues bitwise.
    void save_state(std::map<std::string, std::vector<double>> &out, const std::string &prefix) const;
    /// Restores what save_state wrote; std::invalid_argument on a missing or mis-sized array.
    void load_state(const std::map<std::string, std::vector<double>> &in, const std::string &prefix);

  private:
    class Impl;
    std::unique_ptr<Impl> impl_;
  };
} // namespace fem
