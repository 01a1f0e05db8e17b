#include "driver_common.h"

#include <coupling/run_case.h>

#include <fem/steel_body.h>
#include <sph/body.h>
#include <sph/domain.h>
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
      const double cell = p.particle_arrangement == sph::ParticleArrangement::lattice ?
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
