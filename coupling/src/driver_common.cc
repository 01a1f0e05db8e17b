#include "driver_common.h"

#include <coupling/run_case.h>

#include <fem/steel_body.h>
#include <sph/body.h>
#include <sph/domain.h>
#include <sph/lattice.h>
#include <sph/rate_strength.h>
#include <sph/strength_scatter.h>

#include <Eigen/Dense>

#include <omp.h>

#include <algorithm>
#include <cstdint>
#include <sstream>

namespace coupling
{
  int mpi_ranks()
  {
    int initialised = 0, finalised = 0;
    MPI_Initialized(&initialised);
    MPI_Finalized(&finalised);
    if (!initialised || finalised)
      return 1;
    int size = 1;
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    return size;
  }

  RockPart make_rock_part(const CaseParameters &p, const sph::Lattice<3> &lattice,
                          const double strain_rate)
  {
    RockPart part;
    int n_ranks = 1, rank = 0;
    MPI_Comm_size(MPI_COMM_WORLD, &n_ranks);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    const std::vector<int> owners = sph::bisection_owners<3>(lattice.positions, n_ranks);
    const double radius           = 2.0 * (p.sph.cslh * p.sph.spacing); // sph::Body's pair cut-off
    // four hops of ghosts, for the set-up: the column area of an owned outer particle of a
    // loaded face needs L of its lowest member's neighbours (three hops) and L the positions
    // around them (four). A step then refreshes only the ghosts it reads: the neighbours of the
    // owned particles and the outer particles of their columns (sph::Body::restrict_to_owned)
    part.domain = std::make_unique<sph::Domain>(
      MPI_COMM_WORLD, owners, sph::local_particles<3>(lattice.positions, owners, rank, radius, 4));
    const sph::Domain &domain = *part.domain;
    sph::Lattice<3> mine      = lattice;
    mine.positions.clear();
    mine.volumes.clear();
    for (const std::int32_t g : domain.global_ids())
    {
      mine.positions.push_back(lattice.positions[g]);
      mine.volumes.push_back(lattice.volumes[g]);
    }
    part.body          = make_rock_body(p, mine, strain_rate);
    sph::Body<3> &body = *part.body;
    body.set_owned(domain.owned());
    {
      sph::Vector<3> lo = lattice.positions[0], hi = lo; // as sph::Body finds its centre
      for (const auto &X : lattice.positions)
      {
        lo = lo.cwiseMin(X);
        hi = hi.cwiseMax(X);
      }
      body.set_reference_centre(0.5 * (lo + hi));
    }
    // the chunks of the serial body (its pair loops add every sum in their order): from the
    // owned particles' pair counts, which are complete
    std::vector<double> count(body.n_particles(), 0.0);
    for (const std::int32_t i : domain.owned_indices())
      count[i] = body.n_pairs_as_first(i);
    const std::vector<double> all = domain.gather(count.data(), 1);
    std::vector<std::int64_t> pair_begin(all.size() + 1, 0);
    for (std::size_t i = 0; i < all.size(); ++i)
      pair_begin[i + 1] = pair_begin[i] + static_cast<std::int64_t>(all[i]);
    part.n_global_pairs                    = static_cast<std::size_t>(pair_begin.back());
    const std::vector<std::int32_t> starts = sph::Body<3>::work_chunks(pair_begin, p.sph.chunks);
    std::vector<std::int32_t> chunk_of;
    for (const std::int32_t g : domain.global_ids())
      chunk_of.push_back(static_cast<std::int32_t>(
                           std::upper_bound(starts.begin(), starts.end(), g) - starts.begin()) -
                         1);
    body.set_chunks(chunk_of);
    return part;
  }

  void report_split(const sph::Domain &domain, const std::size_t n_summed,
                    const double wait_before, Summary &s)
  {
    // each rank's time in the exchanges and collectives since wait_before (its wait_seconds
    // when the run loop began): the slowest rank waits least
    const std::vector<double> waits = domain.all_gather({domain.wait_seconds() - wait_before});
    s.extra.push_back({"mpi_wait_seconds_min", *std::min_element(waits.begin(), waits.end())});
    s.extra.push_back({"mpi_wait_seconds_max", *std::max_element(waits.begin(), waits.end())});
    // a step's two exchanges per refreshed ghost: position and velocity (exchange_ghosts), and
    // P L, F, stress and density (compute_forces)
    constexpr int halo_doubles_per_ghost = 6 + 9 + 9 + 9 + 1;
    const std::vector<double> counts =
      domain.all_gather({static_cast<double>(domain.owned_indices().size())});
    for (const double c : counts)
      s.particles_per_rank.push_back(static_cast<std::size_t>(c));
    const std::vector<double> g =
      domain.sum({static_cast<double>(domain.n_ghosts()),
                  static_cast<double>(domain.n_sent(halo_doubles_per_ghost))});
    s.extra.push_back({"ghost_fraction", g[0] / static_cast<double>(domain.n_global())});
    s.extra.push_back({"halo_bytes_per_step", 8.0 * g[1]});
    s.extra.push_back({"allreduce_bytes_per_rank_per_step", 8.0 * static_cast<double>(n_summed)});
  }

  void OwnedParticles::reset(const sph::Body<3> &body, const sph::Domain &domain)
  {
    x_.resize(3 * domain.owned_indices().size());
    v_.resize(x_.size());
    m_.clear();
    for (const std::int32_t i : domain.owned_indices())
      m_.push_back(body.masses()[i]);
  }

  ContactParticles OwnedParticles::pack(const sph::Body<3> &body, const sph::Domain &domain,
                                        const std::vector<double> *force,
                                        const std::vector<double> *deformation,
                                        const std::vector<double> *self_gradient)
  {
    const auto &owned = domain.owned_indices();
    const auto &x     = body.positions();
    const auto &v     = body.velocities();
    // owned particles in one run of local indices (a cut across the lattice's slowest index,
    // as the UCS cylinder's on 2 ranks): the body's own rows, nothing copied
    if (!owned.empty() &&
        owned.back() - owned.front() + 1 == static_cast<std::int32_t>(owned.size()))
    {
      const std::size_t b = static_cast<std::size_t>(owned.front());
      ContactParticles particles{x[b].data(), v[b].data(), body.masses().data() + b, owned.size()};
      if (force)
        particles.force = force->data() + 3 * b;
      if (deformation)
        particles.deformation = deformation->data() + 9 * b;
      if (self_gradient)
        particles.self_gradient = self_gradient->data() + 3 * b;
      return particles;
    }
    f_.resize(force ? x_.size() : 0);
    F_.resize(deformation ? 9 * owned.size() : 0);
    g_.resize(self_gradient ? 3 * owned.size() : 0);
    if (deformation)
      for (std::size_t k = 0; k < owned.size(); ++k)
        for (int c = 0; c < 9; ++c)
          F_[9 * k + c] = (*deformation)[9 * owned[k] + c];
    for (std::size_t k = 0; k < owned.size(); ++k)
      for (int d = 0; d < 3; ++d)
      {
        x_[3 * k + d] = x[owned[k]][d];
        v_[3 * k + d] = v[owned[k]][d];
        if (force)
          f_[3 * k + d] = (*force)[3 * owned[k] + d];
        if (self_gradient)
          g_[3 * k + d] = (*self_gradient)[3 * owned[k] + d];
      }
    ContactParticles particles{x_.data(), v_.data(), m_.data(), owned.size()};
    if (force)
      particles.force = f_.data();
    if (deformation)
      particles.deformation = F_.data();
    if (self_gradient)
      particles.self_gradient = g_.data();
    return particles;
  }

  void add_contact_forces(sph::Body<3> &body, const sph::Domain *domain,
                          const std::vector<double> &force)
  {
    auto &f_ext = body.external_forces();
    if (domain)
    {
      const auto &owned = domain->owned_indices();
      for (std::size_t k = 0; k < owned.size(); ++k)
        for (int d = 0; d < 3; ++d)
          f_ext[owned[k]][d] += force[3 * k + d];
    }
    else
      for (unsigned int i = 0; i < body.n_particles(); ++i)
        for (int d = 0; d < 3; ++d)
          f_ext[i][d] += force[3 * i + d];
  }

  std::vector<double> owned_rows(const sph::Domain &domain, const std::vector<double> &global,
                                 const std::size_t width)
  {
    std::vector<double> rows;
    rows.reserve(width * domain.owned_indices().size());
    for (const std::int32_t i : domain.owned_indices())
    {
      const std::size_t g = static_cast<std::size_t>(domain.global_ids()[i]);
      rows.insert(rows.end(), global.begin() + width * g, global.begin() + width * (g + 1));
    }
    return rows;
  }

  namespace
  {
    /// The body's accounts that each rank of a distributed run sums over its own particles.
    bool rank_share(const std::string &name)
    {
      return name == "body.viscous" || name == "body.hourglass" || name == "body.external";
    }

    bool starts_with(const std::string &text, const std::string &prefix)
    {
      return text.compare(0, prefix.size(), prefix) == 0;
    }

    bool ends_with(const std::string &text, const std::string &suffix)
    {
      return text.size() >= suffix.size() &&
             text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
    }
  } // namespace

  void save_rock_state(const sph::Body<3> &body, const sph::Domain *domain,
                       const std::vector<std::pair<std::string, const PenaltyContact *>> &contacts,
                       StateArrays &out, StateRows *rows)
  {
    if (!domain)
    {
      body.save_state(out, "body.");
      for (const auto &[prefix, contact] : contacts)
        contact->save_state(out, prefix);
      return;
    }
    // this rank's rows of the whole-body arrays, the accounts summed: the checkpoint file holds
    // the whole body in global order, which a run on any number of ranks continues
    StateArrays local;
    body.save_state(local, "body.");
    for (const auto &[prefix, contact] : contacts)
      contact->save_state(local, prefix);
    rows->global_index.clear();
    for (const std::int32_t i : domain->owned_indices())
      rows->global_index.push_back(domain->global_ids()[i]);
    rows->n_global             = domain->n_global();
    const std::size_t n_local = body.n_particles();
    for (auto &[name, a] : local) // (the same names in the same order on every rank)
    {
      if (rank_share(name) || ends_with(name, ".scalars"))
        out[name] = domain->sum(a);
      else if (starts_with(name, "body."))
      {
        if (a.size() >= n_local && a.size() % n_local == 0)
        {
          const std::size_t w = a.size() / n_local;
          std::vector<double> mine;
          mine.reserve(w * domain->owned_indices().size());
          for (const std::int32_t i : domain->owned_indices())
            mine.insert(mine.end(), a.begin() + w * i, a.begin() + w * (i + 1));
          out[name]         = std::move(mine);
          rows->width[name] = static_cast<int>(w);
        }
        else
          out[name] = std::move(a); // pressure, dt_last: the same on every rank
      }
      else // the contacts' arrays of the owned particles
      {
        rows->width[name] = ends_with(name, "tangential_force") ? 3 : 1;
        out[name]         = std::move(a);
      }
    }
  }

  void load_rock_state(sph::Body<3> &body, const sph::Domain *domain,
                       const std::vector<std::pair<std::string, PenaltyContact *>> &contacts,
                       const StateArrays &in)
  {
    if (!domain)
    {
      body.load_state(in, "body.");
      for (const auto &[prefix, contact] : contacts)
        contact->load_state(in, prefix);
      return;
    }
    // this rank's rows of the global arrays; the accounts on rank 0 (they are summed)
    const std::size_t n_all = domain->n_global();
    auto of_contact         = [&](const std::string &name) {
      for (const auto &c : contacts)
        if (starts_with(name, c.first))
          return true;
      return false;
    };
    StateArrays local;
    const double share = domain->rank() == 0 ? 1.0 : 0.0;
    for (const auto &[name, a] : in)
    {
      if (rank_share(name) || (of_contact(name) && ends_with(name, ".scalars")))
      {
        std::vector<double> b(a);
        for (double &value : b)
          value *= share;
        local[name] = std::move(b);
      }
      else if (starts_with(name, "body."))
        local[name] = a.size() >= n_all && a.size() % n_all == 0
                        ? domain->scatter(a, static_cast<int>(a.size() / n_all))
                        : a;
      else if (of_contact(name))
        local[name] = owned_rows(*domain, a, a.size() / n_all);
    }
    body.load_state(local, "body.");
    for (const auto &[prefix, contact] : contacts)
      contact->load_state(local, prefix);
  }

  double n_failed_particles(const sph::Body<3> &body, const sph::Domain *domain)
  {
    double failed = 0;
    if (domain)
    {
      for (const std::int32_t i : domain->owned_indices())
        failed += body.damage(i) >= 1.0 ? 1.0 : 0.0;
      return domain->sum(failed);
    }
    for (unsigned int i = 0; i < body.n_particles(); ++i)
      failed += body.damage(i) >= 1.0 ? 1.0 : 0.0;
    return failed;
  }

  namespace
  {
    /// non_affine_kinetic_energy of a distributed body: the same sums over the owned particles,
    /// each summed over the ranks.
    double non_affine_kinetic_energy(const sph::Body<3> &body, const sph::Domain &domain)
    {
      const auto &x = body.positions();
      const auto &v = body.velocities();
      const auto &m = body.masses();
      std::vector<double> c(4, 0.0);
      for (const std::int32_t i : domain.owned_indices())
      {
        for (int d = 0; d < 3; ++d)
          c[d] += m[i] * x[i][d];
        c[3] += m[i];
      }
      c = domain.sum(c);
      const double mass = c[3];
      if (mass <= 0)
        return 0;
      const Eigen::Vector3d centre = Eigen::Vector3d(c[0], c[1], c[2]) / mass;
      std::vector<double> ab(16 + 12, 0.0);
      for (const std::int32_t i : domain.owned_indices())
      {
        const Eigen::Vector4d phi(1, x[i][0] - centre[0], x[i][1] - centre[1], x[i][2] - centre[2]);
        for (int r = 0; r < 4; ++r)
        {
          for (int k = 0; k < 4; ++k)
            ab[4 * r + k] += m[i] * phi[r] * phi[k];
          for (int d = 0; d < 3; ++d)
            ab[16 + 3 * r + d] += m[i] * phi[r] * v[i][d];
        }
      }
      ab = domain.sum(ab);
      Eigen::Matrix4d A;
      Eigen::Matrix<double, 4, 3> b;
      for (int r = 0; r < 4; ++r)
      {
        for (int k = 0; k < 4; ++k)
          A(r, k) = ab[4 * r + k];
        for (int d = 0; d < 3; ++d)
          b(r, d) = ab[16 + 3 * r + d];
      }
      const Eigen::Matrix<double, 4, 3> fit_coefficients = A.ldlt().solve(b);
      double energy = 0;
      for (const std::int32_t i : domain.owned_indices())
      {
        const Eigen::Vector4d phi(1, x[i][0] - centre[0], x[i][1] - centre[1], x[i][2] - centre[2]);
        const Eigen::RowVector3d fit = phi.transpose() * fit_coefficients;
        energy += 0.5 * m[i] * (Eigen::RowVector3d(v[i][0], v[i][1], v[i][2]) - fit).squaredNorm();
      }
      return domain.sum(energy);
    }
  } // namespace

  double non_affine_kinetic_energy(const sph::Body<3> &body, const sph::Domain *domain)
  {
    if (domain)
      return non_affine_kinetic_energy(body, *domain);
    const auto &x = body.positions();
    const auto &v = body.velocities();
    const auto &m = body.masses();
    // normal equations of the fit v_d = c_d . (1, x, y, z), mass weighted, about the centre of
    // mass (better conditioned)
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    double mass            = 0;
    for (std::size_t i = 0; i < x.size(); ++i)
    {
      centre += m[i] * Eigen::Vector3d(x[i][0], x[i][1], x[i][2]);
      mass += m[i];
    }
    if (mass <= 0)
      return 0;
    centre /= mass;
    Eigen::Matrix4d A = Eigen::Matrix4d::Zero();
    Eigen::Matrix<double, 4, 3> b = Eigen::Matrix<double, 4, 3>::Zero();
    for (std::size_t i = 0; i < x.size(); ++i)
    {
      const Eigen::Vector4d phi(1, x[i][0] - centre[0], x[i][1] - centre[1], x[i][2] - centre[2]);
      A += m[i] * phi * phi.transpose();
      b += m[i] * phi * Eigen::RowVector3d(v[i][0], v[i][1], v[i][2]);
    }
    const Eigen::Matrix<double, 4, 3> c = A.ldlt().solve(b);
    double energy                        = 0;
    for (std::size_t i = 0; i < x.size(); ++i)
    {
      const Eigen::Vector4d phi(1, x[i][0] - centre[0], x[i][1] - centre[1], x[i][2] - centre[2]);
      const Eigen::RowVector3d fit = phi.transpose() * c;
      energy += 0.5 * m[i] * (Eigen::RowVector3d(v[i][0], v[i][1], v[i][2]) - fit).squaredNorm();
    }
    return energy;
  }

  fem::Parameters fem_parameters(const PlatenParameters &platens, const double default_element_size)
  {
    fem::Parameters fp = platens.steel;
    if (platens.element_size_from_spacing)
      fp.element_size = default_element_size;
    return fp;
  }

  fem::Parameters specimen_platen_parameters(const CaseParameters &p)
  {
    return fem_parameters(p.platens, 2.0 * p.sph.spacing);
  }

  namespace
  {
    /// The angles about the z axis (ascending) of a cylinder platen's rim vertices, the contact
    /// face's nodes on its largest radius, which it returns in `radius`.
    std::vector<double> rim_vertex_angles(const fem::SteelBody &platen, double &radius)
    {
      const std::vector<double> x = platen.contact_positions();
      radius                      = 0;
      for (std::size_t i = 0; i < x.size(); i += 3)
        radius = std::max(radius, std::hypot(x[i], x[i + 1]));
      std::vector<double> angle;
      for (std::size_t i = 0; i < x.size(); i += 3)
        if (std::hypot(x[i], x[i + 1]) > (1 - 1e-9) * radius)
          angle.push_back(std::atan2(x[i + 1], x[i]));
      std::sort(angle.begin(), angle.end());
      return angle;
    }
  } // namespace

  double rim_sagitta(const fem::SteelBody &platen)
  {
    double radius   = 0;
    const double n  = static_cast<double>(rim_vertex_angles(platen, radius).size());
    return n >= 3 ? radius * (1 - std::cos(M_PI / n)) : 0.0;
  }

  void set_rim_polygon(ContactParameters &cp, const fem::SteelBody &platen, const double specimen_radius)
  {
    double radius                   = 0;
    const std::vector<double> angle = rim_vertex_angles(platen, radius);
    if (angle.size() < 3)
      return;
    double widest = 2 * M_PI - (angle.back() - angle.front());
    for (std::size_t k = 1; k < angle.size(); ++k)
      widest = std::max(widest, angle[k] - angle[k - 1]);
    // the polygon's chords lie at R cos(a) from the axis, a the largest half-angle
    if (specimen_radius >= radius * std::cos(0.5 * widest))
      cp.rim_angles = angle;
  }

  void set_face_remap(ContactParameters &cp, const std::vector<sph::Vector<3>> &x0,
                      const std::vector<double> &loaded_area, const std::vector<double> &cell_area,
                      const double dx)
  {
    double r_max = 0;
    for (std::size_t i = 0; i < loaded_area.size(); ++i)
      if (loaded_area[i] > 0)
        r_max = std::max(r_max, std::hypot(x0[i][0], x0[i][1]));
    if (!(r_max > 0))
      return;
    // E(r) on edges of dx / 8 out to the outermost cell's far side
    const double bin        = dx / 8;
    const std::size_t edges = static_cast<std::size_t>(std::ceil((r_max + dx) / bin)) + 1;
    std::vector<double> excess(edges, 0.0); // per bin, then summed to the edges
    for (std::size_t i = 0; i < loaded_area.size(); ++i)
    {
      if (!(loaded_area[i] > 0))
        continue;
      const double r = std::hypot(x0[i][0], x0[i][1]);
      const double a = 0.5 * (loaded_area[i] - cell_area[i]); // two end faces
      const double lo = std::max(0.0, r - 0.5 * dx), hi = r + 0.5 * dx;
      for (std::size_t k = 0; k + 1 < edges; ++k)
      {
        // evenly over the annulus's area, so that near the axis E(r) grows as r^2 does
        const double e0 = std::max(lo, k * bin), e1 = std::min(hi, (k + 1) * bin);
        if (e1 > e0)
          excess[k] += a * (e1 * e1 - e0 * e0) / (hi * hi - lo * lo);
      }
    }
    cp.face_remap_step = bin;
    cp.face_radius_mapped.assign(edges, 0.0);
    double sum = 0;
    for (std::size_t k = 0; k < edges; ++k)
    {
      const double r           = k * bin;
      cp.face_radius_mapped[k] = std::sqrt(std::max(0.0, r * r + sum / M_PI));
      sum += excess[k];
    }
  }

  unsigned int contact_patch_points(const CaseParameters &p)
  {
    if (p.platens.contact_patch_points > 0)
      return static_cast<unsigned int>(p.platens.contact_patch_points);
    // A point load on a face takes its nodes' shares at one point: where the lattice and the
    // platen mesh do not line up, a uniform stress loads the nodes of elements of two spacings
    // unevenly (M1 at half its strength, 2.5 mm: neighbouring rings of the face's nodes up to
    // 0.7 um apart at one point, a smooth profile at 4 x 4), and a softening rock's end layer
    // fails early (M1 on a platen of its own diameter, 2.5 mm, body-fitted: 272.6 MPa at one
    // point, 282.3 at 4 x 4). So the
    // cylinder platens take 4 x 4 points at any element size. BTS (a line contact): elements of
    // one spacing take about one particle and dimple under each, so they take (2 dx / h)^2
    // points along each side, as far as 4.
    if (p.test != "BTS")
      return 4;
    const double dx = p.sph.spacing;
    const double h  = specimen_platen_parameters(p).element_size;
    const double n  = std::ceil(std::pow(2.0 * dx / h, 2) - 1e-9);
    return static_cast<unsigned int>(std::clamp(n, 1.0, 4.0));
  }

  sph::Parameters sph_numerics(const sph::Parameters &sph)
  {
    sph::Parameters p = sph;
    p.tssfac          = std::min(sph.tssfac, 1.0);
    return p;
  }

  std::unique_ptr<sph::Body<3>> make_rock_body(const CaseParameters &p, const sph::Lattice<3> &lattice,
                                               const double strain_rate)
  {
    const RockCase &rc = p.rock_case;
    if (rc.rate_sensitivity != 0 && !(strain_rate > 0))
      throw InputError("Rock/Rate sensitivity: " + p.test +
                       " has no nominal strain rate to scale the strength with; set it to 0 (rate-dependent "
                       "strength is for UCS, BTS and CTCS)");
    const sph::MaterialParameters material =
      sph::at_strain_rate(p.rock, strain_rate, rc.rate_sensitivity, rc.reference_strain_rate);
    std::unique_ptr<sph::Body<3>> body;
    try
    {
      body = std::make_unique<sph::Body<3>>(sph_numerics(p.sph), material, lattice.positions, lattice.volumes);
    }
    catch (const std::invalid_argument &e)
    {
      throw InputError(e.what());
    }
    const RockCase &rock = p.rock_case;
    if (rock.strength_scatter > 0)
    {
      // the hash cell of each particle's draw: a lattice's cell (one particle each); body-fitted
      // rings put particles anywhere, at least 0.85 dx apart, so cells of dx / 4 (diagonal
      // 0.43 dx) hold one particle each and every particle draws its own strength
      // (a flattened disc's rows are closer than dx: its cells too). With Rock/Scatter length
      // the cells are the heterogeneity's, fixed in space: every particle in one shares its factor
      const double cell = rock.scatter_length > 0 ? rock.scatter_length
                          : p.particle_arrangement == sph::ParticleArrangement::lattice && p.flat_angle == 0 ?
                            p.sph.spacing :
                            0.25 * p.sph.spacing;
      body->set_strength_factors(sph::weibull_strength_factors<3>(
        body->reference_positions(), cell, rock.strength_scatter,
        static_cast<std::uint64_t>(rock.scatter_seed)));
    }
    return body;
  }

  ParticleSnapshot particle_snapshot(const sph::Body<3> &body, const sph::Domain *domain)
  {
    if (domain)
    {
      // the owned particles' rows, named by their global index: results.h5 is written by all
      // ranks together (no gather on one rank)
      ParticleSnapshot s;
      s.n = domain->n_global();
      const auto &x  = body.positions();
      const auto &v  = body.velocities();
      const auto &x0 = body.reference_positions();
      for (const std::int32_t i : domain->owned_indices())
      {
        s.global_index.push_back(domain->global_ids()[i]);
        for (int d = 0; d < 3; ++d)
        {
          s.position.push_back(x[i][d]);
          s.velocity.push_back(v[i][d]);
          s.displacement.push_back(x[i][d] - x0[i][d]);
        }
        const auto &t = body.stress3(i);
        s.stress.insert(s.stress.end(), {t(0, 0), t(1, 1), t(2, 2), t(1, 2), t(0, 2), t(0, 1)});
        s.plastic_strain.push_back(body.plastic_strain(i));
        s.damage.push_back(body.damage(i));
        s.failure_mode.push_back(static_cast<int>(body.history(i).failure_mode));
      }
      return s;
    }
    ParticleSnapshot s;
    const unsigned int n = body.n_particles();
    s.n                  = n;
    const auto &x        = body.positions();
    const auto &v        = body.velocities();
    const auto &x0       = body.reference_positions();
    s.position.reserve(3 * n);
    for (unsigned int i = 0; i < n; ++i)
      for (int d = 0; d < 3; ++d)
      {
        s.position.push_back(x[i][d]);
        s.velocity.push_back(v[i][d]);
        s.displacement.push_back(x[i][d] - x0[i][d]);
      }
    for (unsigned int i = 0; i < n; ++i)
    {
      const auto &t = body.stress3(i);
      s.stress.insert(s.stress.end(), {t(0, 0), t(1, 1), t(2, 2), t(1, 2), t(0, 2), t(0, 1)});
      s.plastic_strain.push_back(body.plastic_strain(i));
      s.damage.push_back(body.damage(i));
      s.failure_mode.push_back(static_cast<int>(body.history(i).failure_mode));
    }
    return s;
  }

  MeshSnapshot mesh_snapshot(const std::string &name, const fem::SteelBody &platen)
  {
    MeshSnapshot m = platen.mesh_snapshot();
    m.name         = name;
    return m;
  }

  ContactSurface contact_surface(const fem::SteelBody &platen)
  {
    ContactSurface s;
    s.position = platen.contact_positions();
    s.velocity = platen.contact_velocities();
    s.mass     = platen.contact_masses();
    if (platen.is_rigid())
      std::fill(s.mass.begin(), s.mass.end(), 0.0);
    s.faces = quad_faces(platen.contact_faces());
    return s;
  }

  ContactSurface predicted_contact_surface(const fem::SteelBody &platen, const double dt)
  {
    ContactSurface s = contact_surface(platen);
    if (platen.is_rigid())
      return s;
    const std::vector<double> a = platen.contact_free_accelerations();
    for (std::size_t i = 0; i < s.velocity.size(); ++i)
      s.velocity[i] += dt * a[i];
    return s;
  }

  void append_history_row(std::vector<double> &out, const HistoryRow &r, const std::size_t width)
  {
    const double all[] = {r.time,
                          r.displacement,
                          r.force,
                          r.force_bottom,
                          r.stress,
                          r.strain,
                          r.axial_gauge_strain,
                          r.radial_strain,
                          r.kinetic_energy,
                          r.internal_energy,
                          r.dissipated_energy,
                          r.external_work,
                          r.n_failed,
                          r.rolling_force,
                          r.side_force};
    static_assert(sizeof(all) == sizeof(HistoryRow), "a HistoryRow field is missing here");
    out.insert(out.end(), all, all + width);
  }

  HistoryRow history_row_at(const std::vector<double> &a, const std::size_t k,
                            const std::size_t width)
  {
    const double *p = a.data() + width * k;
    double        all[15] = {};
    std::copy(p, p + width, all);
    HistoryRow r;
    r.time               = all[0];
    r.displacement       = all[1];
    r.force              = all[2];
    r.force_bottom       = all[3];
    r.stress             = all[4];
    r.strain             = all[5];
    r.axial_gauge_strain = all[6];
    r.radial_strain      = all[7];
    r.kinetic_energy     = all[8];
    r.internal_energy    = all[9];
    r.dissipated_energy  = all[10];
    r.external_work      = all[11];
    r.n_failed           = all[12];
    r.rolling_force      = all[13];
    r.side_force         = all[14];
    return r;
  }

  ThreadLimit::ThreadLimit(const int n_threads)
    : saved_(omp_get_max_threads())
  {
    if (n_threads > 0)
      omp_set_num_threads(n_threads);
  }

  ThreadLimit::~ThreadLimit()
  {
    omp_set_num_threads(saved_);
  }
} // namespace coupling
