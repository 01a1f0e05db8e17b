#pragma once
/// @file
/// Contact with Coulomb friction (or a bond) between rock particles (slaves) and a platen's
/// contact surface (master): quadrilateral faces over the platen's contact-face nodes, which are
/// the rock's background particles. Plain data in, plain data out; no sph or fem types here.
/// Two methods: a penalty spring (stiffness a fraction of its stability bound), or a kinematic
/// (predictor-corrector) constraint that removes the predicted penetration of each step exactly
/// and has no stiffness to choose.
///
/// Each contact force is computed once, applied to the particle, and spread over the face's four
/// nodes with the bilinear shape-function weights at the contact point (weights sum to one), so
/// the forces on rock and platen cancel to round-off.

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <utility>
#include <map>
#include <string>
#include <vector>

namespace coupling
{
  /// The master side at one instant: the platen's contact-face nodes as background particles.
  /// Flat arrays x0,y0,z0,x1,...; faces as 4 node indices whose normal (p1-p0)x(p3-p0) points out
  /// of the platen, towards the rock.
  struct ContactSurface
  {
    std::vector<double> position; ///< [m]
    std::vector<double> velocity; ///< [m/s]
    std::vector<double> mass;     ///< lumped nodal mass [kg]; 0 for a rigid platen
    std::vector<std::array<unsigned int, 4>> faces;
    std::size_t n_nodes() const { return mass.size(); }
  };

  /// Faces from a flat list of 4 node indices per face (as fem::SteelBody::contact_faces() gives).
  inline std::vector<std::array<unsigned int, 4>> quad_faces(const std::vector<unsigned int> &flat)
  {
    std::vector<std::array<unsigned int, 4>> faces(flat.size() / 4);
    for (std::size_t q = 0; q < faces.size(); ++q)
      faces[q] = {{flat[4 * q], flat[4 * q + 1], flat[4 * q + 2], flat[4 * q + 3]}};
    return faces;
  }

  /// The slave side: rock particles (flat arrays as above).
  struct ContactParticles
  {
    const double *position = nullptr; ///< [m]
    const double *velocity = nullptr; ///< [m/s]
    const double *mass     = nullptr; ///< [kg]
    std::size_t n          = 0;
    /// Force on each particle before contact this step [N] (flat, 3 n): the kinematic method
    /// predicts the step x + dt (v + dt f / m) of the symplectic Euler update with it
    const double *force = nullptr;
    /// Deformation gradient of each particle, 9 per particle, row-major [-] (optional; the
    /// kinematic method): a particle is held at r (n . F n) from a face instead of r, so that the
    /// half cell between its centre and the face strains with it. Without it the end layer's half
    /// cells are rigid and the platens read E L / (L - dx) of a specimen of length L.
    const double *deformation = nullptr;
    /// With `deformation`, how each particle's F moves with its own position, 3 per particle
    /// (sph::Body::self_gradients: dF = -dx (x) g) [1/m] (optional): the held distance is then
    /// taken at the step's end, the particle's own move in the step included, not lagged a step
    /// (a face lighter than the particle would follow the lagged target and grow unstable)
    const double *self_gradient = nullptr;
  };

  /// How the interface enforces contact.
  enum class ContactMethod
  {
    /// a normal (and tangential stick) spring of stiffness ContactParameters::stiffness
    penalty,
    /// the predicted penetration of the step removed exactly: per particle-face pair the normal
    /// force f_n = -m_eff g* / dt^2 (g* the gap the step would end with, m_eff the pair's
    /// effective mass; on a deformable face the pairs that share nodes solved together), and
    /// the tangential force that stops the relative sliding, limited to mu f_n (Coulomb stick /
    /// slip); no stiffness, no added stability bound
    kinematic,
    /// a case's default (PlatenParameters::contact_method): kinematic for the specimen tests (UCS,
    /// BTS, CTCS), penalty for the cutter tests; coupling::contact_method() resolves it
    automatic,
  };

  struct ContactParameters
  {
    double stiffness        = 0.0; ///< normal (and tangential) penalty stiffness per particle [N/m]
    double friction_static  = 0.0; ///< Coulomb static coefficient [-]
    double friction_dynamic = 0.0; ///< Coulomb dynamic coefficient [-] (<= static)
    double radius           = 0.0; ///< particle contact radius: half the particle spacing [m]
    ContactMethod method    = ContactMethod::penalty;
    /// Kinematic only: a particle that touched the face stays tied to it (normal tension and
    /// shear without limit; the friction coefficients are not used)
    bool bonded = false;
    /// Kinematic on a deformable face: the sweeps stop when every end gap and stuck slip is below
    /// this fraction of the contact radius [-]
    double tolerance = 1e-6;
    /// Kinematic on a deformable face: a particle's force is spread over its contact patch (the
    /// square of side 2 r in the face's plane, its cell's end face), sampled at patch_points x
    /// patch_points points projected onto the faces, not put on the face at one point [-]. A point
    /// load dimples an elastic face by about F / (E h): at the platen elements of a particle
    /// spacing that is the particle's own end strain, the face is bumpy at the particle scale and
    /// gets bumpier as the mesh is refined. Patches tile the end face, so a uniform pressure
    /// gives the face nodes (nearly) their consistent loads. 1 = the point (as on a rigid face,
    /// which has no stiffness of its own); elements of two spacings need no more.
    unsigned int patch_points = 1;
    /// Kinematic, flat or concave master: how far past the mesh's outer edge (tangentially) a
    /// particle keeps that edge's face [m]; at least r. A platen's rim polygon lies inside its
    /// circle by up to R (1 - cos(pi / n)) for n rim vertices, which the driver passes here.
    double rim_reach = 0.0;
    /// Kinematic on a deformable cylinder platen as wide as the specimen: its mesh's rim polygon
    /// (the rim vertices' angles about the z axis, the specimen's and the platen's, ascending in
    /// [-pi, pi)). The contact points (a particle's centre and its patch's sample points) are
    /// mapped from the circle onto the polygon, sector by sector, with a uniform area ratio
    /// (map_onto_rim_polygon), before the face is looked for. Without it a specimen as wide as
    /// its platen loads the polygon's rim elements with what lies between the chords and the
    /// circle (a 50 mm platen with 16 rim vertices: 2.6 % of the area) and the steel face
    /// dishes. Empty: no map.
    std::vector<double> rim_angles;
    /// Kinematic on a deformable face of a loaded end (sph::Body::add_loaded_face): the radius
    /// r' about the z axis that a contact point at radius r is moved to, tabulated at r = k
    /// face_remap_step (linear between, the identity beyond the table). A uniform stress pushes
    /// each end particle with its discrete loaded area A_i, which near the specimen's side is
    /// not its cell's (2.5 mm, 50 mm cylinder: 1.2 to 1.25 times the cell two rows in, 0.66
    /// times it in the outer row; tests/sph unit_loaded_face.cc), so the steel under a uniform
    /// stress saw a ring 25 % over and the rim 34 % under its pressure and bent. With pi r'^2 =
    /// the discrete area inside r the forces land where a uniform pressure would put them; the
    /// forces themselves are not changed (momentum stays exact). Empty: no remap.
    std::vector<double> face_radius_mapped;
    double face_remap_step = 0.0; ///< [m]
    /// The master surface is convex towards the rock (a wedge, cone or disc cutter): of the faces
    /// a particle projects onto, take the one it is farthest in front of (the signed distance to a
    /// convex body is the largest over its face planes), not the most penetrated one, which near
    /// an apex is the far flank and would push the particle the wrong way. false: flat or
    /// concave masters (platens, the BTS jaw), the most penetrated face. A convex master also
    /// lets a particle that projects just past an edge shared by two faces (within a particle
    /// diameter of it) take that face's plane: the largest of the face-plane distances near a
    /// convex apex is continuous where the projections onto the faces leave a gap. A flat or
    /// concave master takes a face reached across an interior edge (clamped to it, within r of
    /// it along the face) only when no face contains the particle's projection: over a ridge of
    /// a loaded, warped platen face the projections leave the same gap.
    bool convex_master = false;
    /// The master is flat (a UCS/CTCS platen): a point's projection lies inside at most one face,
    /// so a patch's sample found inside its particle's face needs no search (inside_face).
    bool flat_master = false;
  };

  /// The point (x, y) of the platen's disc (about the z axis), mapped onto the
  /// rim polygon of `p.rim_angles` (ContactParameters): in the sector between two rim vertices
  /// (half-angle a, its middle at angle m) the point at radius r and angle m + u goes to angle
  /// m + phi, tan(phi) = tan(a) u / a, and radius r cos(a) / cos(phi). The circle's arc lands on
  /// the chord, the vertices stay, and every area shrinks by the same sin(2a) / (2a) (the
  /// polygon's area over the circle's), so a uniform stress on the disc loads the polygon
  /// uniformly. Points beyond the circle are mapped by the same rule. No-op without rim_angles.
  void map_onto_rim_polygon(const ContactParameters &p, double &x, double &y);

  /// Where a contact point (x, y) of a particle's patch loads a deformable face: moved radially
  /// by ContactParameters::face_radius_mapped, then onto the rim polygon
  /// (map_onto_rim_polygon). No-op where neither is set.
  void map_contact_point(const ContactParameters &p, double &x, double &y);

  /// Largest stable penalty stiffness for a particle of mass m_s against a node of mass m_m
  /// (m_m = 0: rigid) under central differences with step dt, the spring alone:
  /// k < 4 m_eff / dt^2, where m_eff = m_s m_m / (m_s + m_m). Callers take a fraction s of it
  /// and shorten the step with coupled_time_step(): the particle's own SPH stiffness already uses
  /// most of the budget at dt (up to 95 % of it at TSSFAC 0.9, measured), so a contact spring
  /// added at the same dt can push the pair past the bound.
  double stable_contact_stiffness(double slave_mass, double master_mass, double dt);

  /// The coupled time step when the penalty stiffness (normal and tangential stick spring alike)
  /// is k = s * stable_contact_stiffness(m_s, m_m, dt_alone), dt_alone being the step at which
  /// the bodies alone are stable: dt_alone / sqrt(1 + s).
  /// Bound: central differences are stable while lambda_max dt^2 < 4, lambda_max the largest
  /// eigenvalue of M^-1 K. The contact spring adds at most k / m_eff to it, the eigenvalue of the
  /// particle-node pair alone; with lambda_body dt_alone^2 < 4 and k / m_eff = 4 s / dt_alone^2,
  /// (lambda_body + k / m_eff) dt^2 < (4 + 4 s) / (1 + s) = 4 at dt = dt_alone / sqrt(1 + s).
  /// Without this reduction a stuck block on a platen (TSSFAC 0.9, s = 0.1) grows a tangential
  /// oscillation of the base particles that the friction springs feed (tests/coupling
  /// physics_friction_test.cc).
  double coupled_time_step(double dt_alone, double stiffness_scale);

  /// Per-particle friction history (the elastic tangential spring of regularised stick).
  struct FrictionState
  {
    std::array<double, 3> tangential_force{{0, 0, 0}}; ///< [N]
    bool sliding = false;
    bool tied    = false; ///< bonded interface: touched once, tied since
  };

  /// Penalty contact between one master surface and the rock particles.
  class PenaltyContact
  {
  public:
    PenaltyContact(const ContactParameters &parameters, std::size_t n_particles);

    /// Computes the contact forces for the current positions and velocities and ADDS them to
    /// `force_on_particles` (3 n) and `force_on_nodes` (3 n_nodes) [N]. dt [s] advances the
    /// friction springs. Returns the number of particles in contact.
    std::size_t apply(const ContactParticles &particles, const ContactSurface &surface, double dt,
                      std::vector<double> &force_on_particles, std::vector<double> &force_on_nodes);

    /// The kinematic contact on a deformable face whose contacts are split over several
    /// processes (MPI ranks, each with its own particles and the whole face): `sum` replaces an
    /// array by its sum over them, `max` a value by its largest; both collective, called the same
    /// number of times on every process. With them the contacts that share face nodes are solved
    /// together across the processes, as on one. Unset: one process.
    void set_reduction(std::function<void(double *, int)> sum, std::function<double(double)> max)
    {
      reduce_sum_ = std::move(sum);
      reduce_max_ = std::move(max);
    }

    /// Per-particle factors on the penalty stiffness (size n_particles; empty = all 1), e.g. so
    /// that a rigid platen loads each particle in proportion to the area it carries.
    void set_stiffness_factors(std::vector<double> factors) { stiffness_factor_ = std::move(factors); }

    /// The penalty stiffness per particle before the stiffness factors [N/m].
    double stiffness() const { return prm_.stiffness; }
    /// Sum of the normal forces of the last apply() [N] (>= 0).
    double normal_force() const { return normal_force_; }
    /// Penalty energy stored in the last apply() [J].
    double penalty_energy() const { return penalty_energy_; }
    /// Friction work dissipated so far [J] (>= 0).
    double friction_dissipation() const { return friction_dissipation_; }
    /// Particles that slid in the last apply().
    std::size_t n_sliding() const { return n_sliding_; }

    /// Adds the friction history (stick springs, sliding flags) and the energy accounts to `out`
    /// as flat arrays named `prefix` + name (checkpoints). Defined in contact_state.cc.
    void save_state(std::map<std::string, std::vector<double>> &out, const std::string &prefix) const;
    /// Restores what save_state wrote; std::invalid_argument on a missing or mis-sized array.
    void load_state(const std::map<std::string, std::vector<double>> &in, const std::string &prefix);

  private:
    /// The most face nodes one kinematic contact's patch is shared among.
    static constexpr int max_patch_nodes = 25;
    struct Hit
    {
      int face   = -1;
      double gap = 0;                 ///< signed distance beyond the contact radius [m]
      std::array<double, 4> weight{}; ///< shape-function weights of the face nodes
      std::array<double, 3> normal{}; ///< unit, out of the platen
      double normal_force = 0;        ///< [N], this particle's share of normal_force()
      double energy       = 0;        ///< penalty + stick-spring energy [J]
      double dissipated   = 0;        ///< friction work of this apply() [J]
    };
    Hit find_face(const double *x, const ContactSurface &surface) const;
    /// find_face's answer where it surely is face `f`: on a flat master (flat_master), the point's projection
    /// inside f by a margin of 1e-2 of its parametric size and within find_face's reach of its
    /// plane (the same closest-point iteration, so the same numbers). Otherwise no face (then
    /// ask find_face). A particle's patch samples mostly lie on its own face: this spares them
    /// the search.
    Hit inside_face(const double *x, const ContactSurface &surface, int f) const;
    /// Whether p lies outside face f's box inflated by 2 r and find_face's slack (0.02 r): a
    /// flat or concave master's face cannot hold it then.
    bool outside_face_box(const std::array<double, 3> &p, int f) const
    {
      const double slack = 0.02 * prm_.radius;
      const auto &b      = face_box_[f];
      return p[0] < b[0] - slack || p[1] < b[1] - slack || p[2] < b[2] - slack || p[0] > b[3] + slack ||
             p[1] > b[4] + slack || p[2] > b[5] + slack;
    }
    /// Whether a particle at this signed distance from a face's plane is not in contact with it:
    /// more than a diameter behind it, or (flat and concave masters) in front of it by more than
    /// the reach (kinematic: 2 r, the particles the step may bring in; penalty: r).
    bool out_of_reach(const double distance) const
    {
      const double reach = prm_.method == ContactMethod::kinematic ? 2.0 * prm_.radius : prm_.radius;
      return distance < -2.0 * prm_.radius || (!prm_.convex_master && distance > reach);
    }
    /// Newton iterations from (xi, eta) for the closest point of face f to p (parametric);
    /// false where they did not converge (8 at most) or the face is degenerate there.
    bool closest_point(const std::array<double, 3> &p, const ContactSurface &surface, int f, double &xi,
                       double &eta) const;
    /// Face f's point x(xi, eta) and unit normal there; false for a degenerate face.
    bool face_point(const ContactSurface &surface, int f, double xi, double eta, std::array<double, 3> &xs,
                    std::array<double, 3> &n) const;
    /// Whether find_face surely finds no face for the particle at `x` (a test of a few
    /// comparisons, inline: most particles of a specimen are far from either platen, and the
    /// call alone cost them more than their forces).
    bool surely_clear(const double *x) const
    {
      // below the grid's lower corner: find_face's cell index is negative
      if (x[0] < grid_origin_[0] || x[1] < grid_origin_[1] || x[2] < grid_origin_[2])
        return true;
      // a flat or concave master: beyond every inflated face box, with find_face's slack
      const double slack = 0.02 * prm_.radius;
      return !prm_.convex_master &&
             (x[0] > grid_top_[0] + slack || x[1] > grid_top_[1] + slack || x[2] > grid_top_[2] + slack);
    }
    /// apply() of ContactMethod::kinematic (kinematic_contact.cc).
    std::size_t apply_kinematic(const ContactParticles &particles, const ContactSurface &surface, double dt,
                                std::vector<double> &force_on_particles, std::vector<double> &force_on_nodes);
    void build_face_grid(const ContactSurface &surface);
    /// interior_edge_[f][e]: edge e of face f is shared with another face (computed again only
    /// when the face list changes).
    void find_interior_edges(const ContactSurface &surface);

    ContactParameters prm_;
    std::vector<FrictionState> friction_;
    std::vector<double> stiffness_factor_;
    /// A particle in contact in this apply(): its face, its force on the particle [N].
    struct Contact
    {
      std::int32_t particle;
      Hit hit;
      std::array<double, 3> force;
      /// kinematic: the face nodes the force is shared among and their weights (summing to one):
      /// hit's four, or on a deformable face those of the contact patch (ContactParameters::
      /// patch_points)
      int n_nodes = 0;
      /// kinematic: the held distance's change with the particle's own normal move over the
      /// step, r d(n . F n) / d(n . x) (<= 0; 0 without ContactParticles::self_gradient) [-]
      double stretch_slope = 0;
      /// kinematic: the particle's predicted velocity along the normal, n . (v + dt f / m) [m/s]
      double own_speed = 0;
      std::array<unsigned int, max_patch_nodes> node{};
      std::array<double, max_patch_nodes> weight{};
    };
    /// Fills c's nodes and weights: hit's face, or the patch around the particle at x.
    void share_among_nodes(const double *x, Contact &c, const ContactSurface &surface, bool deformable) const;
    /// Per thread: the contacts found in its chunk of particles (contiguous chunks in thread
    /// order, so the lists end to end are in particle order). Only the few particles near the
    /// platen are stored, not a record per particle.
    std::vector<std::vector<Contact>> contacts_;
    std::vector<double> node_weight_; ///< kinematic: per node, the sum of its contact weights
    std::function<void(double *, int)> reduce_sum_; ///< kinematic: see set_reduction
    std::function<double(double)> reduce_max_;
    // uniform grid of face bounding boxes
    std::array<double, 3> grid_origin_{};
    std::array<double, 3> grid_top_{}; // the upper corner of the faces' inflated boxes
    double grid_cell_ = 1.0;
    std::array<int, 3> grid_n_{};
    std::vector<int> cell_start_, cell_faces_;
    std::vector<std::array<double, 6>> face_box_; // per face: lower, upper corner, inflated by 2 r
    std::vector<std::array<unsigned int, 4>> edge_faces_;
    std::vector<std::array<bool, 4>> interior_edge_;
    double normal_force_ = 0, penalty_energy_ = 0, friction_dissipation_ = 0;
    std::size_t n_sliding_ = 0;
  };
} // namespace coupling
