// The coupled laboratory tests on body-fitted particles (SPH/Particle arrangement = body-fitted,
// sph/fitted_bodies.h): the elastic cylinder gives the rock's modulus as the lattice does, the
// elastic round disc carries its rim load as the line-load solution's centre stresses say (it does
// not split from its centre: on flat platens it fails at the contact first, cases/bts/README.md),
// and the elastic flattened disc carries the load on its flats as Hondros's solution says.
#include "hondros.h"
#include "run_helpers.h"

#include <coupling/reference_disc.h>
#include <coupling/run_case.h>
#include <sph/fitted_bodies.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>

using namespace coupling;
using namespace coupling::test;

namespace
{
  CaseParameters body_fitted(const std::string &test)
  {
    CaseParameters p;
    p.test                  = test;
    p.particle_arrangement  = sph::ParticleArrangement::body_fitted;
    p.rock.youngs_modulus   = 97.07e9; // group M1, Table 3
    p.rock.poissons_ratio   = 0.28;
    p.output.n_history_rows = 200;
    p.sph.n_threads         = 1; // small runs: one thread costs no more than two (no waits)
    return p;
  }
} // namespace

TEST(CoupledBodyFitted, ElasticUcsGivesTheRockModulus)
{
  CaseParameters p     = body_fitted("UCS");
  p.rock.model         = sph::RockModel::elastic;
  p.sph.spacing        = 5e-3; // D/10, the coarsest the case files accept (for time)
  p.loading.end_strain = 1e-3;
  Keep rows;
  const Summary s = run_case(p, rows);
  ASSERT_GT(rows.rows.size(), 50u);
  // the run is on the rings: their count, not the lattice's
  EXPECT_EQ(s.n_particles, sph::make_fitted_cylinder(p.diameter, p.length, p.sph.spacing).positions.size());
  // the secant modulus from the gauges (middle half of the specimen) is E of the closed form
  // sigma = E eps. 2 %: the requirement; the corrected gradients (FORM 8) are exact for the
  // uniform field on any particle set, what remains is the explicit loading's dynamics
  EXPECT_NEAR(s.youngs_modulus / 97.07e9, 1.0, 0.02);
  // nu from the outer ring at mid-height: 5 % at D/10, where the ring's radial strain is read
  // from 10 rings (the lattice test asks 3 % at D/20)
  EXPECT_NEAR(s.poissons_ratio / 0.28, 1.0, 0.05);
  // energy and the two load cells: the lattice test's bounds (5 %: central differences' shadow
  // energy and the hourglass and viscous work; 0.1: twice the quasi-static limit)
  EXPECT_LT(s.energy_balance_error, 0.05);
  EXPECT_LT(s.max_force_imbalance, 0.1);
}

namespace
{
  /// Keeps the history rows and the last particle snapshot with its time.
  struct RowsAndLastSnapshot : Keep
  {
    double           snapshot_time = 0;
    ParticleSnapshot particles;
    void snapshot(double t, const ParticleSnapshot &p, const std::vector<MeshSnapshot> &) override
    {
      snapshot_time = t;
      particles     = p;
    }
    /// The mean of the two load cells at time t [N], linear between the rows.
    double load_at(const double t) const
    {
      for (std::size_t k = 1; k < rows.size(); ++k)
        if (rows[k].time >= t)
          {
            const HistoryRow &a = rows[k - 1], &b = rows[k];
            const double      w = (t - a.time) / (b.time - a.time);
            return 0.5 * ((1 - w) * (a.force + a.force_bottom) + w * (b.force + b.force_bottom));
          }
      return 0.5 * (rows.back().force + rows.back().force_bottom);
    }
  };

  /// An elastic body-fitted disc of case `p` (25 mm thick, as cases/bts) at spacing dx, loaded to
  /// d/D = end_strain: the run with its last snapshot, the mean load P [N] and nominal stress T
  /// = 2P/(pi D t) [Pa] at that snapshot, and the particle set the run was built of (one rank:
  /// the snapshot is in the set's order).
  struct ElasticDisc
  {
    RowsAndLastSnapshot run;
    double              P = 0, T = 0;
    sph::Lattice<3>     set;
  };
  ElasticDisc run_elastic_disc(CaseParameters p, const double dx, const double end_strain)
  {
    p.length             = 0.025;
    p.rock.model         = sph::RockModel::elastic;
    p.sph.spacing        = dx;
    p.loading.end_strain = end_strain;
    p.output.n_snapshots = 4;
    ElasticDisc d;
    run_case(p, d.run);
    d.P   = d.run.load_at(d.run.snapshot_time);
    d.T   = 2 * d.P / (3.14159265358979323846 * p.diameter * p.length);
    // the driver's set: its inner volumes consistent with the case's kernel
    d.set = sph::make_fitted_disc(p.diameter, p.length, dx, p.flat_angle, sph::summed_with(p.sph));
    return d;
  }
} // namespace

TEST(CoupledBodyFitted, ElasticDiscCarriesTheRimLoadAsTheLineLoadSolution)
{
  // An elastic disc pressed across a diameter by flat rigid platens. Its round rim touches each
  // platen along one line (in every layer the ring particle on the loaded diameter), the load
  // case of the Brazilian test's closed form (plane elasticity, Hondros with a vanishing contact
  // arc): at the centre sigma_xx = 2P/(pi D t) (tension), sigma_zz = -6P/(pi D t).
  const CaseParameters p = body_fitted("BTS");
  // 2.5 mm: D/20, the default spacing (1 s); to d/D = 5e-4
  const ElasticDisc d      = run_elastic_disc(p, 2.5e-3, 5e-4);
  const double      P      = d.P;
  const double      sigma0 = d.T;
  ASSERT_GT(sigma0, 1e6) << "the disc must carry load";
  const ParticleSnapshot &q   = d.run.particles;
  const sph::Lattice<3>  &set = d.set;
  ASSERT_EQ(q.n, set.positions.size());
  // Equilibrium (the virial of the static body): the loads -P at z = D and +P at z = 0 give
  // int sigma_zz dV = -P D and int sigma_xx dV = 0, whatever the stress field. 0.90-1.0: the
  // stress lags the platen force in the loading at the derived rate (measured 0.952 here; the
  // lattice disc 0.95); xx: 1 % of P D, measured 5e-4
  double vzz = 0, vxx = 0;
  for (std::size_t i = 0; i < q.n; ++i)
    vzz += set.volumes[i] * q.stress[6 * i + 2], vxx += set.volumes[i] * q.stress[6 * i];
  EXPECT_GT(vzz / (-P * p.diameter), 0.90);
  EXPECT_LT(vzz / (-P * p.diameter), 1.0);
  EXPECT_NEAR(vxx / (P * p.diameter), 0.0, 0.01);
  // the centre (the particle column on the disc axis): the ratio sigma_xx / sigma_zz is -1/3
  // for a line load and -(sin 2a - a)/(sin 2a + a) for a load spread over an arc 2a (-0.31 for
  // the lattice's top flat at 2.5 mm, 2a = 35 deg). 10 %: measured -0.341. The magnitude:
  // measured 0.995 of 2P/(pi D t); 0.92-1.05 bounds it. With the annuli's shares as volumes
  // (no sph::SummedWith) the centre was a hard spot: 0.85 (0.94 at 4 mm)
  const double R = 0.5 * p.diameter;
  double       sxx = 0, szz = 0, n = 0;
  for (std::size_t i = 0; i < q.n; ++i)
    if (std::hypot(set.positions[i][0], set.positions[i][2] - R) < 1e-9)
      sxx += q.stress[6 * i], szz += q.stress[6 * i + 2], n += 1;
  ASSERT_GT(n, 0.0);
  std::printf("virial %.4f; centre sigma_xx %.4f T, sigma_xx / sigma_zz %.4f\n", vzz / (-P * p.diameter),
              sxx / n / sigma0, sxx / szz);
  EXPECT_NEAR((sxx / szz) / (-1.0 / 3.0), 1.0, 0.1);
  EXPECT_GT(sxx / n / sigma0, 0.92);
  EXPECT_LT(sxx / n / sigma0, 1.05);
}

namespace
{
  /// The flattened disc's tension across the loaded diameter on its mid-plane and on its faces
  /// against the 3-D elastic FE reference (coupling/reference_disc.h, 3 refinements; Hondros's
  /// arcs, not flats: the same load away from the rim). The 25 mm thick disc is not plane: at
  /// r/R 0.53 its face layer carries 1.14 T, its mid-plane 0.67 T (FE, 1.25 mm face depth).
  void through_the_thickness(const CaseParameters &p, const ElasticDisc &d, const double a,
                             const double dx)
  {
    const ParticleSnapshot &q   = d.run.particles;
    const sph::Lattice<3>  &set = d.set;
    // the particles on the loaded diameter (x = 0), by ring (rho) and layer (y)
    double y_lo = 1e300, y_hi = -1e300;
    for (const auto &x : set.positions)
      y_lo = std::min(y_lo, x[1]), y_hi = std::max(y_hi, x[1]);
    const double R = 0.5 * p.diameter, t = y_hi - y_lo + dx; // layers dx / 2 inside the faces
    std::map<long, std::array<double, 4>> rings; // rho key -> mid sum, mid n, face sum, face n
    for (std::size_t i = 0; i < q.n; ++i)
    {
      const auto &x = set.positions[i];
      if (std::abs(x[0]) > 1e-9)
        continue;
      const double rho = std::abs(x[2] - R) / R, y = x[1] - 0.5 * (y_lo + y_hi); // from the mid-plane
      if (rho > 0.85)
        continue;
      auto &r = rings[std::lround(rho * 1e4)];
      if (std::abs(y) < 0.6 * dx)
        r[0] += q.stress[6 * i], r[1] += 1;
      if (std::abs(y) > 0.5 * t - 0.6 * dx)
        r[2] += q.stress[6 * i], r[3] += 1;
    }
    std::vector<double> rho;
    for (const auto &[k, r] : rings)
      if (r[1] > 0 && r[3] > 0)
        rho.push_back(k * 1e-4);
    const DiscReferenceProfile fe = elastic_disc_reference(p.diameter, t, a, p.rock.youngs_modulus,
                                                           p.rock.poissons_ratio, 1e5, rho, 3, 0.5 * dx);
    const double T_fe = 2 * fe.load / (3.14159265358979323846 * p.diameter * t);
    double ss_mid = 0, ss_face = 0, n = 0, ratio_sph = 0, ratio_fe = 0, rho_ratio = 0;
    for (std::size_t k = 0; k < rho.size(); ++k)
    {
      const auto &r      = rings[std::lround(rho[k] * 1e4)];
      const double mid   = r[0] / r[1] / d.T, face = r[2] / r[3] / d.T;
      const double f_mid = fe.mid_stress[k][0] / T_fe, f_face = fe.face_stress[k][0] / T_fe;
      std::printf("rho %.3f: SPH mid %.3f face %.3f; FE mid %.3f face %.3f\n", rho[k], mid, face,
                  f_mid, f_face);
      // the centre column (rho 0): with the annuli's shares as volumes its tension was 0.70
      // (mid-plane) and 0.85 (face) T against the FE's 0.90 and 1.09 (a hard spot where the
      // centre and the first rings over-sum the kernel, sph::SummedWith); with volumes
      // consistent with the kernel 0.85 and 1.02. 8 %: within what the spacing leaves at the
      // rings beside it (measured -5.9 / -5.9 %)
      if (rho[k] < 1e-9)
      {
        EXPECT_NEAR(mid / f_mid, 1.0, 0.08);
        EXPECT_NEAR(face / f_face, 1.0, 0.08);
      }
      // the RMS away from the centre and from the rim (flats here, arcs there)
      if (rho[k] < 0.07 || rho[k] > 0.65)
        continue;
      ss_mid += std::pow(mid - f_mid, 2), ss_face += std::pow(face - f_face, 2), n += 1;
      if (std::abs(rho[k] - 0.5) < std::abs(rho_ratio - 0.5))
        rho_ratio = rho[k], ratio_sph = face / mid, ratio_fe = f_face / f_mid;
    }
    ASSERT_GE(n, 8.0);
    // 6 % of T RMS over rho 0.1-0.63: the FE profile moves 3 % of T between 2 and 3
    // refinements, the SPH field 2-5 % with its spacing; measured 3.3 % (mid-plane) and 2.5 %
    // (face layer, dx / 2 inside the face); Hondros's plane field would be 10-40 % off both
    EXPECT_LT(std::sqrt(ss_mid / n), 0.06);
    EXPECT_LT(std::sqrt(ss_face / n), 0.06);
    // the faces carry much more tension than the mid-plane at half the radius: measured 1.71
    // (SPH) against 1.71 (FE) at rho 0.53; 10 %
    EXPECT_NEAR(ratio_sph / ratio_fe, 1.0, 0.1) << "rho " << rho_ratio;
    EXPECT_GT(ratio_fe, 1.5);
  }
} // namespace

TEST(CoupledBodyFitted, ElasticFlattenedDiscCarriesItsFlatsLoadAsHondrosSays)
{
  // The reference study's flattened disc (flats of 2 alpha = 20 deg) built of rings pulled onto
  // the flats: the rigid platens press the flats whole at every spacing. Its stress against
  // Hondros's plane solution for the load spread over the flats' arcs (at the centre 0.960 T
  // across, -2.960 T along the load), volume means over the particles within 0.3 R of the
  // centre, all layers (the field falls to 0.86 T there).
  const double a = 10 * 3.14159265358979323846 / 180;
  // 1.25 mm: 2 %, measured +1.2 % (sigma_xx) and +0.9 % (sigma_zz) (with the annuli's shares as
  // volumes +0.9 / +0.8 %, the centre itself 22 % low; 1 mm within 0.1 % both, the plane
  // solution holding for the 25 mm thick disc's mean); 2.5 mm, the case's spacing: 8 %,
  // measured +6.5 / +2.9 % (the outer ring evenly spaced, its particles covering 82 % of each
  // flat: +7.6 / +3.5 %). The round lattice disc with the same flats cut in is 22 / 8 % low at
  // 2.5 mm and 12 / 4 % low at 1.25 mm (its top row is a wider flat), the reason its BTS moves
  // with the spacing
  for (const auto &[dx, tol] : {std::pair{2.5e-3, 0.08}, std::pair{1.25e-3, 0.02}})
    {
      CaseParameters p = body_fitted("BTS");
      p.flat_angle     = 2 * a;
      const ElasticDisc d = run_elastic_disc(p, dx, 4e-4);
      const double      T = d.T;
      ASSERT_GT(T, 1e6) << "the disc must carry load";
      const ParticleSnapshot &q   = d.run.particles;
      const sph::Lattice<3>  &set = d.set;
      ASSERT_EQ(q.n, set.positions.size());
      const double R = 0.5 * p.diameter;
      double       sxx = 0, szz = 0, hxx = 0, hzz = 0, v = 0;
      for (std::size_t i = 0; i < q.n; ++i)
        {
          const double x = set.positions[i][0] / R, z = (set.positions[i][2] - R) / R;
          if (std::hypot(x, z) >= 0.3)
            continue;
          const auto [ex, ez] = hondros(x, z, a);
          const double w      = set.volumes[i];
          sxx += w * q.stress[6 * i], szz += w * q.stress[6 * i + 2];
          hxx += w * ex * T, hzz += w * ez * T, v += w;
        }
      ASSERT_GT(v, 0.0);
      std::printf("dx %g: within 0.3 R sigma_xx %.4f, sigma_zz %.4f of Hondros's\n", dx, sxx / hxx,
                  szz / hzz);
      EXPECT_NEAR(sxx / hxx, 1.0, tol) << "dx " << dx;
      EXPECT_NEAR(szz / hzz, 1.0, tol) << "dx " << dx;
      if (dx < 2e-3)
        through_the_thickness(p, d, a, dx);
    }
}
