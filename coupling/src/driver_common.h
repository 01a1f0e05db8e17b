#pragma once
/// @file
/// Helpers shared by the two drivers (SpecimenDriver, CuttingDriver): the solver state as output
/// snapshots and an FEM body's contact face as the surface PenaltyContact sees; on more than one
/// MPI rank, a rank's part of the rock, its owned particles packed for the contact and its share
/// of checkpoints. Internal to the coupling library.

#include <coupling/case_parameters.h>
#include <coupling/contact.h>
#include <coupling/run_output.h>

#include <fem/parameters.h>
#include <sph/lattice.h>

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
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
}

namespace coupling
{
  /// Positions, velocities, displacements, stress (Voigt order xx yy zz yz xz xy), plastic strain
  /// and damage of every particle. With `domain` (a distributed body): of the whole body, in
  /// global order, on every rank (collective).
  ParticleSnapshot particle_snapshot(const sph::Body<3> &body, const sph::Domain *domain = nullptr);

  /// The SPH numerics the body takes: the case's own, with TSSFAC capped at 1 (a driver scales a
  /// larger step itself).
  sph::Parameters sph_numerics(const sph::Parameters &sph);

  /// The rock body of case `p` on `lattice` (of spacing SPH/Particle spacing): the case's
  /// numerics (sph_numerics) and rock, and for a heterogeneous rock (Rock/Strength scatter > 0)
  /// every particle's Weibull strength factor. With a rate-sensitive rock
  /// (Rock/Rate sensitivity > 0) the strengths are those at the nominal strain rate
  /// `strain_rate` [1/s] (sph/rate_strength.h); a driver without one passes 0, which such a rock
  /// refuses. InputError for what the SPH body refuses.
  std::unique_ptr<sph::Body<3>> make_rock_body(const CaseParameters &p, const sph::Lattice<3> &lattice,
                                               double strain_rate = 0.0);

  /// Number of MPI ranks of the run: the size of MPI_COMM_WORLD, 1 where MPI is not initialised
  /// (a library user's serial program).
  int mpi_ranks();

  /// One rank's part of a distributed rock body (more than one MPI rank).
  struct RockPart
  {
    /// The split: recursive coordinate bisection of the lattice over the ranks of MPI_COMM_WORLD.
    std::unique_ptr<sph::Domain> domain;
    /// This rank's particles and the ghosts within three neighbour hops of them (an owned
    /// particle's force needs its neighbours' stress, whose deformation gradient needs theirs; a
    /// loaded-face column's outer particle lies up to two hops away), in ascending global index,
    /// so that every sum over the neighbours runs as in the serial body; with the serial body's
    /// reference centre and work chunks (every pair sum added in the serial order).
    std::unique_ptr<sph::Body<3>> body;
    /// SPH pairs of the whole body.
    std::size_t n_global_pairs = 0;
  };

  /// The rock body of case `p` on `lattice` (make_rock_body) split over the ranks of
  /// MPI_COMM_WORLD: this rank's part. Collective. Total Lagrangian only: the neighbours, and
  /// so the ghosts, are those of the reference configuration.
  RockPart make_rock_part(const CaseParameters &p, const sph::Lattice<3> &lattice,
                          double strain_rate = 0.0);

  /// Distributed runs: the particles each rank owns (Summary::particles_per_rank) and what the
  /// split costs, as summary extras: ghosts held per particle of the body (ghost_fraction), the
  /// bytes a step's two halo exchanges send (positions and velocities; P L, F, stress and density
  /// of each refreshed ghost) and the bytes each rank adds to the step's one sum of the contact
  /// forces, `n_summed` doubles; and the least and most time a rank spent in the exchanges and
  /// collectives since it had waited `wait_before` seconds (sph::Domain::wait_seconds;
  /// mpi_wait_seconds_min/_max). Collective.
  void report_split(const sph::Domain &domain, std::size_t n_summed, double wait_before,
                    Summary &s);

  /// The owned particles of a distributed body packed as the contact takes them (positions,
  /// velocities, masses and optionally a force per particle, in owned_indices order), so that
  /// each rank's contact sees its own particles only.
  class OwnedParticles
  {
  public:
    /// Takes the owned particles' masses [kg] (fixed).
    void reset(const sph::Body<3> &body, const sph::Domain &domain);
    /// The owned particles' current positions and velocities; with `force` (3 per local
    /// particle [N]), theirs of it as ContactParticles::force. Valid until the next pack (and
    /// while the body's arrays stay in place: owned particles in one run of local indices are
    /// not copied but pointed at).
    /// `deformation` (9 per local particle), theirs of it as ContactParticles::deformation;
    /// `self_gradient` (3 per local particle) as ContactParticles::self_gradient.
    ContactParticles pack(const sph::Body<3> &body, const sph::Domain &domain,
                          const std::vector<double> *force = nullptr,
                          const std::vector<double> *deformation = nullptr,
                          const std::vector<double> *self_gradient = nullptr);

  private:
    std::vector<double> x_, v_, m_, f_, F_, g_;
  };

  /// Adds the contact forces `force` [N] (3 per particle: of every particle, or with `domain` of
  /// the owned ones in owned_indices order) to the body's external forces.
  void add_contact_forces(sph::Body<3> &body, const sph::Domain *domain,
                          const std::vector<double> &force);

  /// The rows of the owned particles (owned_indices order) of `global` (`width` doubles per
  /// particle of the whole body, in global order).
  std::vector<double> owned_rows(const sph::Domain &domain, const std::vector<double> &global,
                                 std::size_t width);

  /// Adds the rock body's and its contacts' state to `out` (body under "body.", each contact
  /// under its prefix). With `domain`: this rank's rows of the per-particle arrays (named in
  /// `rows`), the accounts summed over the ranks (collective); the checkpoint file made of them
  /// holds the whole body in global order, which a run on any number of ranks continues.
  void save_rock_state(const sph::Body<3> &body, const sph::Domain *domain,
                       const std::vector<std::pair<std::string, const PenaltyContact *>> &contacts,
                       StateArrays &out, StateRows *rows = nullptr);
  /// Restores what save_rock_state wrote (of any number of ranks); with `domain` this rank's
  /// rows, the summed accounts on rank 0. std::invalid_argument for arrays of another case.
  void load_rock_state(sph::Body<3> &body, const sph::Domain *domain,
                       const std::vector<std::pair<std::string, PenaltyContact *>> &contacts,
                       const StateArrays &in);

  /// Number of particles of `body` that have failed (damage 1), as history.csv counts them.
  /// With `domain`: of the whole body (collective); the same below.
  double n_failed_particles(const sph::Body<3> &body, const sph::Domain *domain = nullptr);

  /// Kinetic energy of the body's motion other than a homogeneous deformation: of v - (a + B x),
  /// with a, B the mass-weighted least-squares affine fit of the velocity field [J]. A specimen
  /// loaded quasi-statically moves affinely (rigid motion plus a uniform strain rate), so what
  /// is left are its waves and vibrations.
  double non_affine_kinetic_energy(const sph::Body<3> &body, const sph::Domain *domain = nullptr);

  /// The platens of UCS, BTS and CTCS: fem_parameters() with elements of two particle spacings
  /// unless Platens/Element size says otherwise.
  fem::Parameters specimen_platen_parameters(const CaseParameters &p);

  /// How far a cylinder platen's contact face (a polygon of n rim vertices on radius R) lies
  /// inside its circle at the chords' middles, R (1 - cos(pi / n)) [m] (ContactParameters::rim_reach).
  double rim_sagitta(const fem::SteelBody &platen);

  /// ContactParameters::rim_angles from a cylinder platen's contact face (its rim vertices: the
  /// face's nodes on its largest radius about the z axis), set only where the specimen of radius `specimen_radius` reaches past the polygon's chords
  /// (a platen as wide as the specimen, within the sagitta); on a wider platen the rock's rim
  /// lies inside the polygon and is left where it is. Leaves `cp` unchanged otherwise.
  void set_rim_polygon(ContactParameters &cp, const fem::SteelBody &platen, double specimen_radius);

  /// ContactParameters::face_radius_mapped and face_remap_step (dx / 8) from the loaded end
  /// particles about the z axis (loaded_area > 0; reference positions x0, cell areas
  /// volume / layer thickness, spacing dx): each cell's A_i - c_i spread evenly over the radii
  /// r_i +- dx / 2 and summed outwards to E(r), then r' = sqrt(r^2 + E(r) / pi), so that the
  /// circle of r' holds the discrete area inside r. Both end faces are the same: their
  /// particles are tabulated together (each face half of the sums).
  void set_face_remap(ContactParameters &cp, const std::vector<sph::Vector<3>> &x0,
                      const std::vector<double> &loaded_area, const std::vector<double> &cell_area,
                      double dx);

  /// Platens/Contact patch points as the kinematic contact on an elastic platen uses it: the
  /// case's value, or for 0: 4 for the cylinder platens of UCS and CTCS; for BTS ceil((2 dx /
  /// h)^2) for elements of size h and particle spacing dx, 1 to 4.
  unsigned int contact_patch_points(const CaseParameters &p);
  /// The FEM body (platen or cutter) of Platens/*: model, steel, and the element size, which
  /// is Platens/Element size where set, else `default_element_size` [m].
  fem::Parameters fem_parameters(const PlatenParameters &platens, double default_element_size);

  /// The deformed mesh of one platen or cutter, under the given name.
  MeshSnapshot mesh_snapshot(const std::string &name, const fem::SteelBody &platen);

  /// FEM -> SPH: the contact-face nodes of a platen or cutter as the background particles,
  /// mirrored unchanged (a rigid body's nodes with zero mass).
  ContactSurface contact_surface(const fem::SteelBody &platen);

  /// The surface as the kinematic constraint needs it for a coupled step dt that the body takes
  /// in one step (the specimen driver does not sub-cycle it): the node velocities are those of
  /// the body's free motion over the step, v + dt a with a its own acceleration
  /// (fem::SteelBody::contact_free_accelerations()), so that a force F moves a node by
  /// dt^2 F / m as the rock's step moves a particle. Without the body's own acceleration the
  /// constraint ignores the face's elastic push-back and the rock ends each step inside a loaded
  /// elastic platen. Rigid bodies: contact_surface().
  ContactSurface predicted_contact_surface(const fem::SteelBody &platen, double dt);

  /// History rows in a checkpoint: the first `width` fields of HistoryRow in declaration order
  /// (13: the laboratory tests, without the cutting forces; 15: every field).
  void append_history_row(std::vector<double> &out, const HistoryRow &r, std::size_t width);

  /// Row k of an array written by append_history_row with the same width.
  HistoryRow history_row_at(const std::vector<double> &a, std::size_t k, std::size_t width);

  /// Holds OpenMP's default thread count at `n_threads` (SPH/Threads; 0 leaves it: all cores)
  /// while it lives, so that the coupling's own parallel loops (contact, stability check) run on
  /// as many threads as the SPH body; restores the previous count when it goes.
  class ThreadLimit
  {
  public:
    explicit ThreadLimit(int n_threads);
    ~ThreadLimit();
    ThreadLimit(const ThreadLimit &)            = delete;
    ThreadLimit &operator=(const ThreadLimit &) = delete;

  private:
    int saved_;
  };
} // namespace coupling
