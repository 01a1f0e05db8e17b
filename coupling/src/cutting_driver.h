#pragma once
/// @file
/// Cutter-rock interaction: an FEM cutter (wedge, cone or flat indenter; CCS disc cutter), rigid or
/// elastic steel, pressed into (indentation) or drawn across (linear cutting) an SPH rock block
/// whose bottom and sides are held. Penalty contact with Coulomb friction, sub-cycling and the
/// energy account as in the laboratory driver (specimen_driver.h). Internal to the coupling library;
/// run_case() dispatches to run_cutting_case().
///
/// Frame: the block fills [0, L] x [-W/2, W/2] x [-H, 0]; its free top face is z = 0. The cutter
/// indenter tip starts on that face and moves down (-z) to the penetration; a disc cutter starts
/// outside the free entry face x = 0 with its tip at the penetration depth and moves along +x. The disc slides without rotating: with frictionless contact (the default) a
/// freely rolling disc and a sliding one take the same traction from the rock, as a free disc
/// carries no moment about its axle; with friction the sliding disc over-states the rolling force.

#include <coupling/case_parameters.h>
#include <coupling/contact.h>
#include <coupling/run_output.h>

#include <array>
#include <memory>
#include <vector>

namespace sph
{
  template <int dim>
  class Body;
}
namespace fem
{
  class SteelBody;
}

namespace coupling
{
  /// The CSM (Colorado School of Mines) estimate for a CCS disc cutter (Rostami 1997).
  struct CsmEstimate
  {
    double contact_angle = 0; ///< phi = acos((R - p) / R) [rad]
    double base_pressure = 0; ///< P0 in the crushed zone [Pa]
    double total         = 0; ///< resultant F_t [N]
    double normal        = 0; ///< F_n = F_t cos(phi / 2) [N]
    double rolling       = 0; ///< F_r = F_t sin(phi / 2) [N]
  };

  /// CSM: P0 = C (S sigma_c^2 sigma_t / (phi sqrt(R T)))^(1/3), C = 2.12, F_t = P0 phi R T /
  /// (1 + psi). ucs, bts [Pa]; radius R, tip width T, penetration p, line spacing S [m]; psi the
  /// pressure-distribution exponent [-] (0.2 for a CCS tip of 12-13 mm).
  CsmEstimate csm_cutter_force(double ucs, double bts, double radius, double tip_width,
                               double penetration, double spacing, double psi = 0.2);

  /// Sneddon: force [N] of a rigid cone of half-angle alpha [rad] at depth h [m] in an elastic
  /// half-space (E [Pa], nu): F = 2/pi E/(1 - nu^2) tan(alpha) h^2.
  double sneddon_cone_force(double youngs, double nu, double half_angle, double depth);

  /// Boussinesq: force [N] of a rigid flat cylindrical punch of radius a [m] at depth h [m] in an
  /// elastic half-space: F = 2 a E/(1 - nu^2) h.
  double flat_punch_force(double youngs, double nu, double radius, double depth);

  /// Johnson's expanding-cavity model: mean contact pressure [Pa] under a sharp indenter of
  /// half-angle alpha [rad] in an elastic-perfectly-plastic solid of yield stress Y [Pa]:
  /// p_m = 2/3 Y (1 + ln(E cot(alpha) / (3 Y))), E [Pa] (Young's modulus of the solid).
  double cavity_expansion_pressure(double youngs, double yield, double half_angle);

  class CuttingDriver
  {
  public:
    explicit CuttingDriver(const CaseParameters &parameters);
    ~CuttingDriver();
    /// Runs to the end of the cutter's path. With `resume` (a state from RunObserver::checkpoint
    /// of a run with the same parameters and thread count) continues that run bitwise: its
    /// history rows are reported again first. Checkpoints as the laboratory driver takes them
    /// (Output/Checkpoint interval, minutes; a final one and RunInterrupted when the observer asks
    /// to stop or after Output/Stop after steps).
    Summary run(RunObserver &observer, const StateArrays *resume = nullptr);

    /// The run's state as named arrays (body., cutter., contact., driver.*). Defined in
    /// cutting_driver_state.cc.
    void save_state(StateArrays &out) const;
    /// Restores what save_state wrote. InputError when the state is of another case.
    void load_state(const StateArrays &in);

    /// Number of block particles held (bottom and side layers).
    std::size_t n_fixed() const { return n_fixed_; }

  private:
    void build_block();
    void build_cutter();
    void choose_time_step();
    /// Prescribed cutter velocity (x, z) [m/s] at time t [s].
    std::array<double, 2> cutter_velocity(double t) const;
    /// Cutting: particles that failed (damage 1) and are no longer compressed (mean stress >= 0)
    /// leave the contact for good (stiffness factor 0): they are chip, broken out of the groove.
    /// Failed particles under compression stay: the confined crushed zone carries the cutter.
    /// The released particles' penalty energy is booked as dissipated (released_energy_).
    void release_failed_particles();
    void step();
    HistoryRow measure();
    void check_stability() const;
    ParticleSnapshot particle_snapshot() const;
    std::vector<MeshSnapshot> mesh_snapshots() const;

    CaseParameters prm_;
    bool cutting_ = false;
    std::unique_ptr<sph::Body<3>> body_;
    std::unique_ptr<fem::SteelBody> cutter_;
    std::unique_ptr<PenaltyContact> contact_;
    std::vector<double> volume0_; ///< initial particle volumes [m^3]
    std::size_t n_fixed_ = 0;
    /// Half the lattice cell along z (the block's height is split into round(H / dx) layers):
    /// the top layer's surface and so the cutter's contact radius [m].
    double contact_radius_ = 0;
    double start_x_      = 0; ///< tip x at the start [m]
    // path: vertical phase [0, t_down_], dwell to t_cut_start_, cut [t_cut_start_, t_end_]
    double ramp_down_ = 0, t_down_ = 0, t_cut_start_ = 0, ramp_cut_ = 0, t_end_ = 0;
    double dt_           = 0;
    int n_substeps_      = 1;
    double time_         = 0;
    std::size_t n_steps_ = 0;
    double frame_work_   = 0;
    double travel_ = 0, depth_ = 0; ///< cutter x travel and tip depth below z = 0 [m]
    double domain_size_ = 0;
    // contact force on the cutter and support force on the block, integrated since the last row
    std::array<double, 3> impulse_{{0, 0, 0}};
    double support_impulse_z_ = 0, impulse_time_ = 0;
    std::vector<double> force_on_particles_, force_on_cutter_;
    std::size_t n_in_contact_ = 0; ///< particles in contact at the last step
    double contact_stiffness_ = 0; ///< penalty stiffness per particle [N/m]
    std::vector<char> released_;   ///< per particle: failed and released from the contact
    std::size_t n_released_  = 0;
    double released_energy_  = 0; ///< penalty energy the released particles took with them [J]
    // run-loop state, members so that a checkpoint holds them
    double next_row_ = 0, next_snap_ = 0; ///< times of the next history row and snapshot [s]
    std::vector<HistoryRow> rows_;
    /// per row: the rock's own kinetic and elastic energies [J] (the quasi-static check)
    std::vector<double> rock_kinetic_, rock_internal_;
  };

  /// Runs one indentation or linear-cutting case (see CuttingDriver); `resume` as in run_case.
  Summary run_cutting_case(const CaseParameters &parameters, RunObserver &observer,
                           const StateArrays *resume = nullptr);
} // namespace coupling
