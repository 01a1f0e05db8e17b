#pragma once
/// @file
/// One SPH rock body: particles, neighbour pairs, formulation, rock model, constraints, energies.
///
/// Lifecycle of a time step (what the coupling layer calls, in this order):
///   1. `compute_forces()`   stress update to the current positions, internal, viscous,
///                            hourglass and surface-pressure forces (once per step);
///   2. the caller adds its forces to `external_forces()` [N] (contact, gravity, ...) and may set
///      prescribed velocities with `constrain()`;
///   3. `dt = min(stable_time_step(), ...)`;
///   4. `integrate(dt)`      symplectic Euler: v += dt (f_int + f_pressure + f_ext)/m, constrained
///                            components set to their prescribed velocity (reaction recorded),
///                            x += dt v; external forces are cleared afterwards.
/// Units SI; stress tension-positive; energies in J (2-D: J per metre of thickness).

#include <sph/crack_closure.h>
#include <sph/neighbour_search.h>
#include <sph/parameters.h>
#include <sph/particle_store.h>
#include <sph/rock_models.h>
#include <sph/state_arrays.h>
#include <sph/types.h>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace sph
{
  class Domain;

  /// Energy account of a body [J] (2-D: per unit thickness).
  struct Energies
  {
    double kinetic      = 0; ///< 1/2 sum m v^2
    double internal     = 0; ///< elastic strain energy sum V 1/2 sigma:C^-1:sigma
    double plastic      = 0; ///< plastic dissipation (integrated stress power - elastic energy)
    double viscous      = 0; ///< dissipated by artificial viscosity
    double hourglass    = 0; ///< work done against the hourglass forces
    double external     = 0; ///< work of external forces, surface pressure and constraints
    /// plastic + viscous + hourglass
    double dissipated() const { return plastic + viscous + hourglass; }
    /// external - (kinetic + internal + dissipated): zero for an exact integrator
    double balance_error() const { return external - kinetic - internal - dissipated(); }
  };


  /// An SPH rock body (dim = 2: plane strain, per unit thickness; dim = 3).
  template <int dim>
  class Body
  {
  public:
    /// Particles at `positions` [m] with `volumes` [m^dim] (e.g. from make_cylinder), at rest and
    /// stress-free. Throws std::invalid_argument for inconsistent parameters.
    Body(const Parameters &parameters, const MaterialParameters &material,
         const std::vector<Vector<dim>> &positions, const std::vector<double> &volumes);

    /// Number of particles.
    unsigned int n_particles() const { return static_cast<unsigned int>(p_.size()); }
    /// Current positions [m].
    const std::vector<Vector<dim>> &positions() const { return p_.x; }
    /// Velocities [m/s].
    const std::vector<Vector<dim>> &velocities() const { return p_.v; }
    /// Sets the velocity of particle i [m/s] (initial conditions).
    void set_velocity(unsigned int i, const Vector<dim> &v) { p_.v[i] = v; }
    /// Reference (initial) positions [m].
    const std::vector<Vector<dim>> &reference_positions() const { return p_.x0; }
    /// Masses [kg] (2-D: kg per metre of thickness).
    const std::vector<double> &masses() const { return p_.mass; }
    /// Current volumes [m^dim].
    const std::vector<double> &volumes() const { return p_.volume; }
    /// Smoothing lengths [m].
    const std::vector<double> &smoothing_lengths() const { return p_.h; }
    /// Cauchy stress of particle i, in-plane block [Pa], tension +.
    Tensor<dim> stress(unsigned int i) const
    {
      return p_.stress[i].template topLeftCorner<dim, dim>();
    }
    /// Full 3x3 Cauchy stress of particle i [Pa] (2-D: sigma_zz of plane strain at (2,2)).
    const Tensor3 &stress3(unsigned int i) const { return p_.stress[i]; }
    /// Deformation gradient of particle i [-] (total Lagrangian; identity-based in FORM 0/1).
    const Tensor<dim> &deformation_gradient(unsigned int i) const { return p_.F[i]; }
    /// Material history of particle i (plastic strain, damage).
    const MaterialState &history(unsigned int i) const { return p_.history[i]; }
    /// Equivalent plastic strain of particle i [-].
    double plastic_strain(unsigned int i) const { return p_.history[i].plastic_strain; }
    /// Damage of particle i in [0, 1].
    double damage(unsigned int i) const { return p_.history[i].damage; }
    /// Sets each particle's strength relative to the rock's (cohesion, tensile strength and the
    /// Hoek-Brown s are multiplied by it; 1 everywhere by default): a heterogeneous rock. Constant
    /// during a run (not part of save_state: the caller sets it again before load_state). Throws
    /// std::invalid_argument unless there is one finite positive factor per particle.
    void set_strength_factors(const std::vector<double> &factors);
    /// Particle i's strength factor (see set_strength_factors) [-].
    double strength_factor(unsigned int i) const { return p_.history[i].strength; }
    /// The whole particle store (read only).
    const ParticleStore<dim> &particles() const { return p_; }

    /// Forces [N] the caller adds before `integrate`; cleared by `integrate`.
    std::vector<Vector<dim>> &external_forces() { return p_.f_ext; }
    /// Internal force of the last `compute_forces` [N] (stress + viscosity + hourglass).
    const std::vector<Vector<dim>> &internal_forces() const { return p_.f_int; }
    /// True when the pair forces run four at a time (3-D, AVX2, Parameters::vectorised).
    bool vectorised() const { return simd_; }
    /// True when the vectorised pair force runs in mixed precision (Parameters::single_precision).
    bool single_precision() const { return mixed_; }
    /// Surface-pressure force of the last `compute_forces` [N].
    const std::vector<Vector<dim>> &pressure_forces() const { return p_.f_pressure; }

    /// Component `component` of particle i moves at `velocity` [m/s] until released.
    void constrain(unsigned int i, unsigned int component, double velocity);
    /// Frees component `component` of particle i.
    void release(unsigned int i, unsigned int component);
    /// Frees every constraint.
    void release_all();
    /// Whether component `component` of particle i is constrained.
    bool is_constrained(unsigned int i, unsigned int component) const
    {
      return (constrained_[i] >> component) & 1u;
    }
    /// Force the constraint exerted on particle i in the last `integrate` [N] (zero in free
    /// components): what a frictionless rigid wall would feel, with opposite sign.
    const Vector<dim> &reaction_force(unsigned int i) const { return reaction_[i]; }

    /// Pressure p [Pa], compression +, on the free surface from the next `compute_forces` on.
    /// Surface: the area vector of particle i is a_i = -s_i, s_i = sum_j V_i V_j (L_i + L_j)
    /// grad W_ij, the force a uniform stress P exerts on i being P s_i (outward; zero inside a
    /// full support; the sum over a closed body vanishes), so the uniform state -p I is in
    /// equilibrium with the pressure at every particle; on loaded faces (add_loaded_face) the
    /// normal parts are lumped like the force. Total Lagrangian: a_i is computed in the
    /// reference configuration and pushed forward with Nanson's formula J F^{-T}.
    void set_surface_pressure(double p) { pressure_ = p; }
    /// Current surface pressure [Pa], compression +.
    double surface_pressure() const { return pressure_; }

    /// Declares the flat end face with outward normal `n` (reference configuration) a loaded
    /// face: a platen presses on its outermost particle layer. The symmetric SPH force spreads a
    /// uniform stress P over the particles near a boundary as P s_i, s_i = sum_j V_i V_j (L_i +
    /// L_j) grad W_ij; at a flat lattice face the normal parts of s_i in a column of particles are
    /// about (1.46, -0.41, -0.04) dx^2 from the surface inwards (cubic spline, CSLH 1.2), so a
    /// contact load on the outer layer alone leaves that layer at ~0.6 of the bulk stress, and it
    /// yields first. From then on the normal parts of s_k in each column (the particles within
    /// two support radii of the face whose positions across n agree to 1e-3 spacings) are moved to the column's outer particle o, each
    /// with its own stress: f_k += P_k ds_k, ds_k = -(n.s_k) n (k != o), f_o -= sum_{k != o}
    /// P_k ds_k. The corrections of a column sum to zero (momentum is kept exactly) and vanish
    /// inside; a uniform stress is then in equilibrium with a load on the outer layer alone, and
    /// a member's correction depends on its own state only (with o's stress for every member, an
    /// exact constraint on o fed an oscillation). They are
    /// part of `pressure_forces()` and their work is counted as external work. Returns the
    /// number of particles in the face's columns. Throws std::invalid_argument for |n| = 0 (or
    /// not finite) and when the face's columns overlap those of an earlier loaded face.
    unsigned int add_loaded_face(const Vector<dim> &n);
    /// The same with the face's height n.X [m] given (the largest over the whole body): a part
    /// of a distributed body (Domain) does not hold every particle of the face.
    unsigned int add_loaded_face(const Vector<dim> &n, double face_height);
    /// The discrete area [m^(dim-1)] a uniform normal stress on a loaded face acts on through
    /// particle i: -n . sum_k s_k over i's column for the outer particle of a loaded-face column
    /// (reference configuration), 0 for every other particle. A platen that loads the outer
    /// particles in proportion to these areas keeps a uniform stress uniform (the columns at the
    /// face's rim do not have the area of the inner ones).
    const std::vector<double> &loaded_face_areas() const { return face_area_; }

    /// tssfac * min_i h_i / (c + |v_i|) [s], c the P-wave speed sqrt((K + 4G/3)/rho).
    double stable_time_step() const;

    /// How each particle's deformation gradient moves with its own position (total Lagrangian
    /// forms): dF_i = -dx_i (x) g_i, g_i = L_i sum_j V0_j grad_i W_ij over the pairs in use (the
    /// reference kernel gradients, so constant during a run). Zero in a full neighbourhood; at a
    /// surface it points into the body (0.96 / spacing at a lattice face, FORM 8). Zero vectors in
    /// the updated Lagrangian forms, whose F is integrated from the velocity gradient.
    std::vector<Vector<dim>> self_gradients() const;
    /// Stress update to the current positions and all forces there (call once per step). A
    /// distributed body (restrict_to_owned) passes its domain: the ghosts' stress, F, P L and
    /// density from their owners between the two (collective; std::invalid_argument before
    /// restrict_to_owned).
    void compute_forces(const Domain *domain = nullptr);
    /// Advances velocities and positions by dt [s] (see the file comment).
    void integrate(double dt);

    /// Distributed bodies (sph::Domain): `owned[i]` is 1 for a particle this part owns, 0 for a
    /// ghost. Energies, external work and dissipation then count the owned particles (and the
    /// pairs whose first particle is owned) only: the sums over the parts give the whole body's.
    /// Empty (the default): every particle counts.
    void set_owned(const std::vector<std::uint8_t> &owned);
    /// Distributed bodies, once set_owned(domain.owned()), set_chunks and the loaded faces are
    /// done (total Lagrangian only): each step then computes the stress of the owned particles
    /// only, keeps only the pairs with an owned particle (the others keep their order, so every
    /// sum of an owned particle keeps its terms and their order: the same bits), and
    /// compute_forces(&domain) takes the ghosts' stress fields from their owners; `domain`
    /// exchanges only the ghosts a step reads (the other particles of those pairs and the outer
    /// particles of loaded-face columns with an owned member). Collective. Throws
    /// std::invalid_argument for an updated Lagrangian form or other owned flags.
    void restrict_to_owned(Domain &domain);
    /// Distributed bodies: the chunk (see the pair loops) of each particle, non-decreasing, as
    /// the whole body numbers them (work_chunks), so that every sum is added in the order of the
    /// serial body. Throws std::invalid_argument for a wrong size or a decreasing entry.
    void set_chunks(const std::vector<std::int32_t> &chunk_of);
    /// Distributed bodies: the centre of the whole body's reference bounding box [m] (the
    /// mixed-precision pair force reads reference positions relative to it, rounded to float:
    /// the same centre gives every part the serial body's bits). Default: this body's own.
    void set_reference_centre(const Vector<dim> &centre) { centre0_ = centre; }
    /// Number of pairs of particle i as first particle (pairs with a higher-numbered one).
    std::int32_t n_pairs_as_first(unsigned int i) const
    {
      return pair_begin_[i + 1] - pair_begin_[i];
    }
    /// The first particle of each chunk of equal work, and n at the end, for particles whose
    /// pairs as first particle start at `pair_begin` (n + 1 offsets), `chunks` as
    /// Parameters::chunks: what the body uses for its own particles.
    static std::vector<std::int32_t> work_chunks(const std::vector<std::int64_t> &pair_begin,
                                                 int chunks);

    /// Distributed bodies: the positions and velocities of the ghosts from their owners (after
    /// `integrate`, which moves the ghosts with incomplete forces). Collective over the domain.
    void exchange_ghosts(const Domain &domain);

    /// Energy account (see Energies).
    Energies energies() const;
    /// Sum of all momenta [kg m/s].
    Vector<dim> momentum() const;
    /// P-wave speed of the material [m/s].
    double wave_speed() const { return wave_speed_; }
    /// Number of neighbour pairs currently in use.
    std::size_t n_pairs() const { return pairs_.n_pairs(); }
    /// The neighbour pairs currently in use.
    const PairList &pairs() const { return pairs_; }
    /// The parameters the body was built with.
    const Parameters &parameters() const { return prm_; }
    /// The rock parameters in use.
    const rock::ModelConstants &model_constants() const { return rock_; }

    /// Adds every field that changes during a run to `out`, names prefixed by `prefix`: with
    /// load_state on a body built from the same parameters and particles, the run continues
    /// bitwise as if never interrupted (same thread count). Defined in body_state.cc.
    void save_state(StateArrays &out, const std::string &prefix) const;
    /// Restores what save_state wrote. Throws std::invalid_argument naming a missing array or one
    /// of the wrong size (a checkpoint of another case).
    void load_state(const StateArrays &in, const std::string &prefix);

  private:
    bool total_lagrangian() const;
    bool corrected() const;
    void build_pairs();            // pairs_, grad_w_ at the current positions, partition_pairs
    void partition_pairs();        // pair_begin_, chunk_begin_, cross_begin_, incoming_* from pairs_
    void compute_correction();     // L from grad_w_
    void compute_area_vectors();   // area0_ from grad_w_
    // moves the normal parts of v in each loaded-face column onto its outer particle
    void lump_loaded_faces(std::vector<Vector<dim>> &v) const;
    void update_stress_total_lagrangian();   // one pass: sums for F over the pairs + stress
    void update_stress_updated_lagrangian();
    // 3-D TL: the stress update of particles idx[0..n) (n <= 4, A in p_.F) with `model`
    template <typename Model>
    void update_stress_batch(const Model &model, const std::int32_t *idx, int n);
    double intact_hourglass_factor(std::size_t p) const; // hg V0_i V0_j W(|X|)/|X|^2 of pair p
    void set_hourglass_factor(std::size_t p, double factor); // the one the pair force reads
    void fade_hourglass();         // no hourglass force on pairs of cracked particles (cracked_now_)
    void pair_forces();            // one pass: f_int and f_pressure (loaded faces after it)
    // record_ of particles [begin, end) from the arrays (3-D, vectorised pair force)
    void pack_records(std::int32_t begin, std::int32_t end);
    void loaded_face_forces();     // see add_loaded_face (in body_loaded_face.cc)
    // calls f(name, field) for each array and scalar save_state/load_state carry as it is
    // (body_state.cc); Self is Body or const Body
    template <typename Self, typename F>
    static void for_each_state_field(Self &self, const std::string &prefix, F &&f);
    Vector<dim> loaded_face_s(unsigned int i) const; // s_i of add_loaded_face

    Parameters             prm_;
    MaterialParameters     material_;
    rock::ModelConstants   rock_;
    rock::ModelChoice      model_;
    ParticleStore<dim>     p_;
    PairList               pairs_;
    std::vector<Vector<dim>> grad_w_;     // per pair: grad_i W_ij (reference config in TL)
    // The pair loops run over the pairs of each particle i as first (pairs_ is sorted by first):
    // the share of i is summed in registers and that of the second particle j is added to j's
    // sum in memory, so every pair is visited once per pass and no per-pair result is stored.
    // The particles are cut into chunks of equal work (chunk_begin_, a number set by the
    // particle count alone), which the threads take one at a time as they finish (dynamic
    // scheduling: a thread on a slower core simply takes fewer). A chunk's pass writes only its
    // own particles' sums; a pair whose j lies in a later chunk (a cross pair:
    // particles are in Morton order, so few) adds its share of j elsewhere:
    //  - the F sums: j's chunk computes the share itself (it reads only positions and volumes)
    //    before its own pairs, so every sum receives its terms in ascending pair order;
    //  - the forces: i's chunk writes the force of the pair to force_share_, and j's chunk
    //    subtracts it after all chunks are done (after its terms as second particle in its
    //    chunk and its own pairs' sum).
    // The order of every sum is thus fixed by the chunks, which do not depend on the thread
    // count: the results are the same bits with any number of threads, whichever thread takes
    // which chunk.
    std::vector<std::int32_t> pair_begin_;     // per particle: its first pair as first
    std::vector<std::int32_t> chunk_of_;       // per particle: its chunk (set_chunks; else empty)
    std::vector<std::uint8_t> owned_;          // per particle: counted in sums (set_owned)
    // per particle, set by restrict_to_owned (empty before): owned, or a ghost a step reads
    std::vector<std::uint8_t> read_;
    std::vector<std::int32_t> chunk_begin_;    // per chunk: its first particle (and n at the end)
    std::vector<std::int32_t> cross_begin_;    // per chunk: its first cross pair (as first)
    // per chunk, the cross pairs whose j it holds in ascending pair order: their index k in
    // the list of all cross pairs in ascending pair order, i, j and grad_i W_ij (i and the
    // gradient in total Lagrangian only); incoming_begin_: offsets per chunk
    std::vector<std::int32_t> incoming_, incoming_i_, incoming_j_, incoming_begin_;
    std::vector<Vector<dim>>  incoming_g_;
    std::vector<double>       force_share_;    // per cross pair k: force on its i (scratch)
    std::vector<double>      hg_factor_;  // per pair (TL): hg V0_i V0_j W(|X_ij|)/|X_ij|^2 [N/m in 3-D]
    std::vector<std::uint8_t> hg_faded_;  // per particle (hourglass_fade): its pairs' factors are 0
    std::vector<double>      cracked_now_; // per particle (hourglass_fade): 1 cracked, ghosts' exchanged
    std::vector<Tensor<dim>> Q_;          // per particle: P L (TL) or sigma L (UL) (L = I if off)
    std::vector<Tensor<dim>> F_prev_;     // per particle: F at the last stress update
    std::vector<Vector<dim>> area0_;      // per particle: surface area vector (TL: reference)
    std::vector<std::uint8_t> constrained_;
    std::vector<Vector<dim>>  prescribed_;
    std::vector<Vector<dim>>  reaction_;
    std::vector<double>       stress_work_; // per particle: integrated stress power [J]
    std::vector<double>       volume_next_; // per particle: scratch for the UL volume update
    // 3-D on a CPU with AVX2 (and Parameters::vectorised): pair_forces runs the pair force of
    // src/pair_kernel.h, which reads each particle's fields from one record of 32 doubles
    bool                simd_ = false;
    std::vector<double> record_; // per particle: pair_kernel::record_size doubles (simd_ only)
    // simd_ and Parameters::single_precision: the mixed-precision pair force of
    // src/pair_kernel_mixed.h, which reads a float record per particle and per pair
    bool                mixed_ = false;
    std::vector<float>  frecord_;    // per particle: mixed::float_size floats (mixed_ only)
    std::vector<float>  pair_float_; // per pair: grad W and hourglass factor (mixed_ only)
    Vector<dim>         centre0_ = Vector<dim>::Zero(); // reference bounding-box centre [m]
    std::vector<double> position_volume_; // per particle: x and V0 (TL stress pass, simd_ only)
    /// One column of a loaded face: its outer particle, then the particles below it.
    struct FaceColumn
    {
      Vector<dim>               normal; // outward unit normal of the face (reference)
      std::vector<unsigned int> members; // members[0] is the outer particle
      // total Lagrangian: ds_k = -(n.s_k) n of each member (reference configuration, constant;
      // members[0]'s entry unused); empty in updated Lagrangian, where s_k changes every step
      std::vector<Vector<dim>> ds;
    };
    std::vector<FaceColumn> face_columns_;
    std::vector<double>     face_area_; // per particle: its column's loaded area (outer only)
    double pressure_      = 0;
    double wave_speed_    = 0;
    double dt_last_       = 0;
    double viscous_       = 0;
    double viscous_power_ = 0;   // AV power of the last pair_forces, sum over pairs (<= 0) [W]
    double hourglass_power_ = 0; // hourglass power of the last pair_forces [W]
    double hourglass_     = 0;
    double external_      = 0;
    int    n_threads_     = 1;
  };
} // namespace sph
