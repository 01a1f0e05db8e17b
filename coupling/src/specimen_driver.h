#pragma once
/// @file
/// The coupled laboratory test: an SPH rock specimen between two platens (FEM, rigid or elastic),
/// penalty contact with friction, a loading path, and the measurements a laboratory makes.
/// Internal to the coupling library; run_case() is the public entry.

#include "driver_common.h"
#include "run_loop.h"

#include <coupling/case_parameters.h>
#include <coupling/contact.h>
#include <coupling/run_output.h>

#include <sph/parameters.h>

#include <memory>
#include <vector>

namespace sph
{
  template <int dim>
  class Body;
  class Domain;
}
namespace fem
{
  class SteelBody;
  class LoadFrame;
}

namespace coupling
{
  class FailureWatch;

  /// Quantities derived from the case before the run: the loading path and the stop criteria.
  struct LoadingPlan
  {
    double reference_length        = 0; ///< specimen length (UCS/CTCS) or diameter (BTS) [m]
    double transit_time            = 0; ///< reference_length / sqrt(E/rho) [s]
    double expected_failure_strain = 0; ///< from the strength model, for the rate [-]
    double strain_rate             = 0; ///< nominal axial strain rate [1/s]
    double platen_speed            = 0; ///< final speed of the top platen [m/s]
    double ramp_time               = 0; ///< smooth velocity ramp [s]
    double confinement_time        = 0; ///< CTCS: pressure ramp before axial loading [s]
    double planned_strain          = 0; ///< strain at which the planned path ends [-]
  };


  /// Strength the rock model predicts in uniaxial compression and uniaxial tension [Pa].
  double model_ucs(const sph::MaterialParameters &rock);
  double model_tensile_strength(const sph::MaterialParameters &rock);

  /// The loading plan of a case (rate derived from the wave transit time unless given).
  LoadingPlan make_loading_plan(const CaseParameters &p);

  /// UCS, BTS, CTCS: builds the specimen and the platens, takes the coupled steps and measures;
  /// the run itself (rows, snapshots, checkpoints, stability) is RunLoop's.
  class SpecimenDriver : private SteppedTest
  {
  public:
    explicit SpecimenDriver(const CaseParameters &parameters);
    ~SpecimenDriver() override;
    /// Runs to the stop criterion; with `resume`, first restores that state (see run_case).
    Summary run(RunObserver &observer, const StateArrays *resume = nullptr);

  private:
    // ---- SteppedTest: what RunLoop drives
    void step() override;
    double time() const override { return time_; }
    std::size_t n_steps() const override { return n_steps_; }
    /// (distributed: up to the last step's boundary-load work, which the next step sums)
    double external_work() const override { return frame_work_ + pressure_work_; }
    /// The history row and the rock's non-affine kinetic and elastic energies.
    Measurement measure() override;
    /// Peak and failure pattern; "post-peak drop" once the load has fallen past
    /// Loading/Post-peak drop after the criterion is armed.
    std::string stop_reason(const HistoryRow &row) override;
    ParticleSnapshot particle_snapshot() const override;
    std::vector<MeshSnapshot> mesh_snapshots() const override;
    /// The body, platens, contacts and the driver's clocks and accounts.
    void save_state(StateArrays &out) const override;
    /// Restores save_state's arrays; InputError when they belong to another case.
    void load_state(const StateArrays &in) override;
    const StateRows *state_rows() const override { return domain_ ? &state_rows_ : nullptr; }

    void build_specimen();
    void build_platens();
    void choose_time_step();
    void select_gauges();
    double top_velocity(double t) const;
    double exchange_imbalance() const;
    /// Distributed runs: sums the platen forces, the particles' contact-force totals and the
    /// contact normal forces over the ranks (one MPI_Allreduce); the imbalance of the step.
    double reduce_contact_forces();
    HistoryRow history_row() const;

    CaseParameters prm_;
    LoadingPlan plan_;
    bool bts_ = false, ctcs_ = false;
    std::unique_ptr<sph::Body<3>> body_;
    // distributed runs (more than one MPI rank): this rank's part of the body (null on one
    // rank). body_ then holds the local particles (owned and ghosts, ascending global index),
    // the contacts the owned ones packed (owned_), and every sum over the particles is taken
    // over the owned ones and summed over the ranks
    std::unique_ptr<sph::Domain> domain_;
    mutable StateRows            state_rows_; // distributed: the rows of the last save_state
    OwnedParticles owned_;
    std::vector<sph::Vector<3>> x0_global_; // reference positions of the whole body [m]
    std::vector<double> cell_area_global_;   // volume / layer thickness of every particle [m^2]
    double normal_top_ = 0, normal_bottom_ = 0; // contact normal forces, all ranks [N]
    std::size_t n_global_pairs_ = 0;            // SPH pairs of the whole body
    // distributed: this rank's share of the last step's boundary-load work, summed over the
    // ranks with the next step's contact forces (pressure_work_ holds the sum before it) [J]
    double pressure_work_pending_ = 0;
    std::unique_ptr<FailureWatch> failure_; // where the damage starts, the final pattern
    std::unique_ptr<fem::SteelBody> top_, bottom_;
    /// The load-frame spring that drives the (rigid) top platen; null for a rigid frame
    /// (Platens/Frame stiffness = 0), where the top platen moves as the actuator
    std::unique_ptr<fem::LoadFrame> frame_;
    std::unique_ptr<PenaltyContact> contact_top_, contact_bottom_;
    double true_area_ = 0, lattice_area_ = 0;
    /// Half the lattice cell along the loading axis z [m]: where an outer particle's surface is,
    /// and so the platens' contact radius (the cylinder's layers are L / round(L / dx) apart).
    double contact_radius_ = 0;
    double dt_           = 0;
    int n_substeps_      = 1;
    double time_         = 0;
    std::size_t n_steps_ = 0;
    double frame_work_ = 0, pressure_work_ = 0;
    double max_exchange_imbalance_ = 0; ///< see Summary::max_exchange_imbalance
    double domain_size_ = 0;
    // gauges: particle sets for axial (two layers) and radial (outer ring at mid-height) strain
    // (local indices; distributed: of the owned members; gauge_counts_: members of all ranks)
    std::vector<unsigned int> gauge_low_, gauge_high_, gauge_ring_;
    double gauge_counts_[3] = {0, 0, 0};
    double gauge_length0_ = 0;
    std::vector<double> force_before_contact_; ///< kinematic contact: f_int + f_pressure + f_ext [N]
    std::vector<double> deformation_;          ///< kinematic contact: each particle's F, row-major [-]
    std::vector<double> self_gradient_;        ///< kinematic contact: sph::Body::self_gradients, flat [1/m]
    std::vector<double> force_on_particles_, force_on_top_, force_on_bottom_;
    // the stop criterion's state, members so that a checkpoint holds them
    double peak_force_ = 0;
    bool armed_ = false;
    bool touching_ = false;      // both platens have touched the specimen
    double touch_strain_ = 0;    // nominal strain at that moment
    // stability checks: dt_ = stable step * time_step_scale_ (TSSFAC above 1: the body is built
    // with TSSFAC 1 and the driver scales its step, so that an unstable step can be injected)
    double time_step_scale_ = 1, energy_floor_ = 0;
  };
} // namespace coupling
