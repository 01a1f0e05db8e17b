#pragma once
/// @file
/// What a running case hands to whoever records it (the app writes files; tests keep it in
/// memory). Plain data only: no deal.II, no file formats here.

#include <fem/mesh_snapshot.h>
#include <sph/state_arrays.h>

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace coupling
{
  /// One row of history.csv. Stress and strain are compression-positive, as the paper reports them.
  struct HistoryRow
  {
    double time = 0;             ///< [s]
    double displacement = 0;     ///< platen approach (top minus bottom) [m], positive closing
    double force = 0;            ///< load cell: reaction on the loaded platen [N], compression +
    double force_bottom = 0;     ///< reaction on the other platen [N], compression +
    double stress = 0;           ///< UCS/CTCS: force / true area; BTS: 2P/(pi D t) [Pa]
    double strain = 0;           ///< displacement / specimen length (BTS: / diameter) [-]
    double axial_gauge_strain = 0; ///< UCS/CTCS axial strain over the middle half, compression + [-]
    double radial_strain = 0;    ///< UCS/CTCS lateral strain at mid-height, extension + [-]
    double kinetic_energy = 0;   ///< rock + platens [J]
    double internal_energy = 0;  ///< elastic strain energy, rock + platens [J]
    double dissipated_energy = 0; ///< plastic + viscous + friction dissipation [J]
    double external_work = 0;    ///< work of the loading and confinement [J]
    double n_failed = 0;         ///< number of failed / fully damaged particles
    double rolling_force = 0;    ///< cutting: force resisting the cutter's travel (+x motion) [N]
    double side_force = 0;       ///< cutting / indentation: force on the cutter along y [N]
  };

  /// Particle fields at one instant, flat arrays: vectors as x0,y0,z0,x1,...; stress as the six
  /// components xx,yy,zz,yz,xz,xy per particle, tension positive [Pa].
  /// A serial body's snapshot holds the n particles in order (global_index empty); a distributed
  /// body's holds on each MPI rank the rows of the particles that rank owns, global_index naming
  /// each row's place among the body's n particles (ascending), and results.h5 is written by all
  /// ranks together (app::ResultsFile).
  struct ParticleSnapshot
  {
    std::size_t n = 0; ///< particles of the whole body
    std::vector<std::int64_t> global_index; ///< each row's particle (empty: rows 0..n-1)
    std::vector<double> position;        ///< [m]
    std::vector<double> velocity;        ///< [m/s]
    std::vector<double> displacement;    ///< [m]
    std::vector<double> stress;          ///< [Pa]
    std::vector<double> plastic_strain;  ///< equivalent plastic strain [-]
    std::vector<double> damage;          ///< [0,1]
    /// how each particle failed, sph::FailureMode as an integer: 0 none, 1 tensile, 2 shear,
    /// 3 crushed (empty: not recorded)
    std::vector<int> failure_mode;
    /// Number of rows held here.
    std::size_t n_rows() const { return global_index.empty() ? n : global_index.size(); }
  };

  /// A platen or cutter mesh at one instant (fem's type; MeshSnapshot::name names it in the
  /// output, e.g. "platen_top", "cutter").
  using fem::MeshSnapshot;

  /// Results of one run, as summary.json holds them (docs/design.md).
  struct Summary
  {
    std::string test;
    std::size_t n_particles = 0;
    std::size_t n_steps = 0;
    double wall_seconds = 0;
    double peak_stress = 0;           ///< [Pa]
    double peak_force = 0;            ///< [N]
    double strain_at_peak = 0;        ///< [-]
    double youngs_modulus = 0;        ///< secant 40-60 % of peak on the gauge strain [Pa]
    double platen_modulus = 0;        ///< the same on the platen strain (what a frame sees) [Pa]
    double poissons_ratio = -1;       ///< < 0 when not measured
    double max_displacement = 0;      ///< [m]
    double max_kinetic_to_internal_energy = 0;
    double max_force_imbalance = 0;   ///< max |F_top - F_bottom| / peak force past 10 % load
    double energy_balance_error = 0;  ///< |E_kin + E_int + E_diss - W_ext| / W_ext at the end
    /// Largest, over the steps, of |sum of contact forces on rock + on both platens| divided by
    /// the sum of the contact-force magnitudes on the rock [-]: round-off when forces are
    /// exchanged conservatively; 0 when nothing touched
    double max_exchange_imbalance = 0;
    bool quasi_static = false;
    double true_area = 0;             ///< specimen cross-section pi D^2/4 (UCS) or D t (BTS) [m^2]
    double lattice_area = 0;          ///< cross-section of the particle lattice [m^2]
    double strain_rate = 0;           ///< nominal strain rate used [1/s]
    double time_step = 0;             ///< SPH time step [s]
    std::string stop_reason;          ///< "post-peak drop", "end strain", ...
    /// Particles owned by each MPI rank (one entry on one rank); its size is the rank count.
    std::vector<std::size_t> particles_per_rank;
    /// Further results of a test type, written to summary.json as they are named (units in the
    /// name), e.g. {"mean_normal_force_kN", 12.3}; a NaN is written as null.
    std::vector<std::pair<std::string, double>> extra;
  };

  /// The further result `name` of a run (Summary::extra); empty when the run has none.
  inline std::optional<double> find_extra(const Summary &s, const std::string &name)
  {
    for (const auto &[key, value] : s.extra)
      if (key == name)
        return value;
    return std::nullopt;
  }

  /// The full state of a running case as named flat arrays of doubles (a checkpoint; sph's type,
  /// which the body, the steel bodies and the coupler save into): with it, a case built from the
  /// same parameters continues bitwise (same thread count).
  using sph::StateArrays;

  /// A distributed run's share of a checkpoint: the arrays of its StateArrays named in `width`
  /// hold only this rank's rows of a whole-body array (`width` doubles per particle, the rows of
  /// the particles `global_index`, ascending) of `n_global` rows; every other array is whole and
  /// the same on every rank.
  struct StateRows
  {
    std::vector<std::int64_t>  global_index;
    std::size_t                n_global = 0;
    std::map<std::string, int> width;
  };

  /// Receives what a run produces, in order: any number of progress / history / snapshot calls.
  class RunObserver
  {
  public:
    virtual ~RunObserver() = default;
    /// Called every few steps. fraction: share of the planned load path done, in [0, 1].
    virtual void progress(std::size_t step, double time, double fraction) {}
    virtual void history(const HistoryRow &row) {}
    virtual void snapshot(double time, const ParticleSnapshot &particles,
                          const std::vector<MeshSnapshot> &meshes) {}
    /// Polled once per step: true asks the run to stop after this step, with a final checkpoint
    /// (the app answers true after SIGINT / SIGTERM).
    virtual bool stop_requested() { return false; }
    /// A checkpoint is due (Output/Checkpoint interval / minutes, or the run was asked to stop):
    /// `state` continues the run from after step `step` when given back to run_case. A
    /// distributed run: called on every rank, `rows` says which arrays are this rank's rows (the
    /// whole arrays are then never held by one rank); nullptr: every array is whole.
    virtual void checkpoint(std::size_t step, const StateArrays &state, const StateRows *rows) {}
    /// The run went unstable: called once, just before run_case throws InstabilityError, with
    /// the last state that passed every stability check (after step `step`, at time [s]).
    virtual void last_good_state(std::size_t step, double time, const ParticleSnapshot &particles) {}
  };
} // namespace coupling
