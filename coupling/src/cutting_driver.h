#pragma once
/// @file
/// Cutter-rock interaction: an FEM cutter (wedge, cone or flat indenter; CCS disc cutter), rigid or
/// elastic steel, pressed into (indentation) or drawn across (linear cutting) an SPH rock block
/// whose bottom and sides are held. Penalty contact with Coulomb friction, sub-cycling and the
/// energy account as in the laboratory driver (specimen_driver.h). Internal to the coupling
/// library; run_case() (run_case.cc) is the public entry.
///
/// Frame: the block fills [0, L] x [-W/2, W/2] x [-H, 0]; its free top face is z = 0. The cutter
/// indenter tip starts on that face and moves down (-z) to the penetration; a disc cutter starts
/// outside the free entry face x = 0 with its tip at the penetration depth and moves along +x. The
/// disc slides without rotating: with frictionless contact (the default) a freely rolling disc and
/// a sliding one take the same traction from the rock, as a free disc carries no moment about its
/// axle; with friction the sliding disc over-states the rolling force.
///
/// On more than one MPI rank the block is split as the laboratory driver splits its specimen
/// (make_rock_part): each rank's contact, chip release and sums take its owned particles, the
/// cutter is stepped on every rank with the contact force summed over the ranks.

#include "driver_common.h"
#include "run_loop.h"

#include <coupling/case_parameters.h>
#include <coupling/contact.h>
#include <coupling/run_output.h>

#include <sph/types.h>

#include <array>
#include <memory>
#include <vector>

namespace sph
{
  template <int dim>
  class Body;
  class Domain;
  struct Energies;
}
namespace fem
{
  class SteelBody;
}

namespace coupling
{
  /// Indentation and linear cutting: builds the block and the cutter, takes the coupled steps
  /// and measures; the run itself (rows, snapshots, checkpoints, stability with the last good
  /// state) is RunLoop's, as for the laboratory tests.
  class CuttingDriver : private SteppedTest
  {
  public:
    explicit CuttingDriver(const CaseParameters &parameters);
    ~CuttingDriver() override;
    /// Runs to the end of the cutter's path. With `resume` (a state from RunObserver::checkpoint
    /// of a run with the same parameters and thread count) continues that run bitwise: its
    /// history rows are reported again first. Checkpoints, stop requests and the stability check
    /// as RunLoop does them for every test type.
    Summary run(RunObserver &observer, const StateArrays *resume = nullptr);

    /// Number of block particles held (bottom and side layers).
    std::size_t n_fixed() const { return n_fixed_; }

  private:
    // ---- SteppedTest: what RunLoop drives
    void step() override;
    double time() const override { return time_; }
    std::size_t n_steps() const override { return n_steps_; }
    double external_work() const override { return frame_work_; }
    /// The history row (the forces averaged since the last row) and the rock's own kinetic and
    /// elastic energies (the cutter's kinetic energy is the rig's prescribed motion).
    Measurement measure() override;
    /// The cutter's path alone ends the run: always "".
    std::string stop_reason(const HistoryRow &) override { return ""; }
    ParticleSnapshot particle_snapshot() const override;
    std::vector<MeshSnapshot> mesh_snapshots() const override;
    /// The run's state as named arrays (body., cutter., contact., driver.*). Defined in
    /// cutting_driver_state.cc.
    void save_state(StateArrays &out) const override;
    /// Restores what save_state wrote. InputError when the state is of another case.
    void load_state(const StateArrays &in) override;
    const StateRows *state_rows() const override { return domain_ ? &state_rows_ : nullptr; }

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
    /// Takes the released particles out of the contact (their stiffness factor 0).
    void exclude_released();
    /// The history row now; resets the force integrals. `rock` receives the rock's own energies
    /// (of the whole body).
    HistoryRow history_row(sph::Energies &rock);

    CaseParameters prm_;
    bool cutting_ = false;
    std::unique_ptr<sph::Body<3>> body_;
    // distributed runs (more than one MPI rank): this rank's part of the block (null on one
    // rank). body_ then holds the local particles (owned and ghosts), the contact, the chip flags
    // and the particles' contact forces the owned ones (owned_indices order), and every sum over
    // the particles is taken over the owned ones and summed over the ranks
    std::unique_ptr<sph::Domain> domain_;
    mutable StateRows            state_rows_; // distributed: the rows of the last save_state
    OwnedParticles owned_;
    std::vector<sph::Vector<3>> x0_global_; ///< reference positions of the whole block [m]
    std::size_t n_global_pairs_ = 0;        ///< SPH pairs of the whole block
    std::unique_ptr<fem::SteelBody> cutter_;
    std::unique_ptr<PenaltyContact> contact_;
    std::vector<double> volume0_; ///< initial particle volumes [m^3] (local particles)
    std::size_t n_fixed_ = 0;     ///< held particles of the whole block
    /// Half the lattice cell along z (the block's height is split into round(H / dx) layers):
    /// the top layer's surface and so the cutter's contact radius [m].
    double contact_radius_ = 0;
    double start_x_      = 0; ///< tip x at the start [m]
    // path: vertical phase [0, t_down_], dwell to t_cut_start_, cut [t_cut_start_, t_end_]
    double ramp_down_ = 0, t_down_ = 0, t_cut_start_ = 0, ramp_cut_ = 0, t_end_ = 0;
    double dt_           = 0;
    /// dt_ = coupled stable step * time_step_scale_ (TSSFAC above 1: the body is built with
    /// TSSFAC 1 and the driver scales its step, so that an unstable step can be injected)
    double time_step_scale_ = 1;
    int n_substeps_      = 1;
    double time_         = 0;
    std::size_t n_steps_ = 0;
    double frame_work_   = 0;
    double travel_ = 0, depth_ = 0; ///< cutter x travel and tip depth below z = 0 [m]
    double domain_size_ = 0;
    // contact force on the cutter and support force on the block, integrated since the last row
    // (distributed: support_impulse_z_ of the owned particles, summed over the ranks per row)
    std::array<double, 3> impulse_{{0, 0, 0}};
    double support_impulse_z_ = 0, impulse_time_ = 0;
    std::vector<double> force_on_particles_, force_on_cutter_;
    /// particles in contact at the last step (distributed: owned ones; so are n_released_ and
    /// released_energy_, summed over the ranks where reported)
    std::size_t n_in_contact_ = 0;
    double contact_stiffness_ = 0; ///< penalty stiffness per particle [N/m]
    std::vector<char> released_;   ///< per contact particle: failed and released from the contact
    std::size_t n_released_  = 0;
    double released_energy_  = 0; ///< penalty energy the released particles took with them [J]
  };
} // namespace coupling
