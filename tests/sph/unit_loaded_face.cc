// Loaded faces (Body::add_loaded_face): a uniform stress is in equilibrium with a load on the
// outer layer alone, and the loaded areas add up to the face.
#include <sph/body.h>
#include <sph/fitted_bodies.h>
#include <sph/lattice.h>

#include <gtest/gtest.h>

#include <cmath>

namespace
{
  using namespace sph;

  /// An elastic cylinder D 50 x 100 mm (dx 5 mm), compressed affinely by 0.1 % along z with
  /// free lateral strain (uniaxial stress), its two end faces declared loaded or not.
  struct CompressedCylinder
  {
    Lattice<3> lattice;
    Body<3>    body;
    double     sigma = 0; // axial stress of the affine state [Pa], tension +

    /// `fitted`: the body-fitted cylinder of rings (sph/fitted_bodies.h), same layers along z
    explicit CompressedCylinder(const bool loaded, const bool single_precision = true,
                                const bool fitted = false)
      : lattice(fitted ? make_fitted_cylinder(0.05, 0.1, 0.005) : make_cylinder<3>(0.05, 0.1, 0.005))
      , body(numerics(single_precision), rock(), lattice.positions, lattice.volumes)
    {
      if (loaded)
        {
          body.add_loaded_face(Vector<3>(0, 0, 1));
          body.add_loaded_face(Vector<3>(0, 0, -1));
        }
      const double eps = -1e-3, nu = 0.25, dt = 1e-6;
      Tensor<3>    G   = Tensor<3>::Zero();
      G(0, 0) = G(1, 1) = -nu * eps / dt;
      G(2, 2)           = eps / dt;
      body.compute_forces();
      for (unsigned i = 0; i < body.n_particles(); ++i)
        body.set_velocity(i, G * body.positions()[i]);
      body.integrate(dt);
      for (unsigned i = 0; i < body.n_particles(); ++i)
        body.set_velocity(i, Vector<3>::Zero());
      body.compute_forces();
      sigma = 50e9 * eps;
    }
    static Parameters numerics(const bool single_precision = true)
    {
      Parameters p;
      p.spacing          = 0.005;
      p.single_precision = single_precision;
      p.hourglass = 0; // the affine state has no hourglass mode; keep the forces pure stress
      return p;
    }
    static MaterialParameters rock()
    {
      MaterialParameters m;
      m.model          = RockModel::elastic;
      m.youngs_modulus = 50e9;
      m.poissons_ratio = 0.25;
      return m;
    }
    /// axial force on the particles of lattice layer k from the top (0 = outer) [N]
    double layer_force(const int k) const
    {
      double f = 0;
      for (unsigned i = 0; i < body.n_particles(); ++i)
        if (std::lround((0.0975 - lattice.positions[i][2]) / 0.005) == k)
          f += body.internal_forces()[i][2] + body.pressure_forces()[i][2];
      return f;
    }
  };

  TEST(SphLoadedFace, UniformStressIsBalancedByTheOuterLayerAlone)
  {
    // the pair force in double precision: the layers beneath the outer one then feel round-off
    // only (the mixed-precision pair force: the next test)
    CompressedCylinder plain(false, false), loaded(true, false);
    const double       load = -plain.sigma * plain.lattice.true_section_area; // > 0: pushes out
    // Without the correction the symmetric force spreads the boundary term over three layers,
    // about (1.46, -0.41, -0.04) of the load (the defect that made the end layer yield first).
    EXPECT_GT(plain.layer_force(0) / load, 1.3);
    EXPECT_LT(plain.layer_force(1) / load, -0.3);
    // With it the outer layer takes the whole load: the layer force is the axial stress times
    // the loaded area, which is the true section within 0.2 % (lattice volumes are scaled to
    // the true volume; the rest is the faceted rim); the layers beneath feel round-off only.
    EXPECT_NEAR(loaded.layer_force(0) / load, 1.0, 2e-3);
    for (int k = 1; k < 5; ++k)
      EXPECT_NEAR(loaded.layer_force(k) / load, 0.0, 1e-9) << "layer " << k;
    // the correction only moves force within each column: the total is unchanged
    double total_plain = 0, total_loaded = 0;
    for (int k = 0; k < 20; ++k)
      total_plain += plain.layer_force(k), total_loaded += loaded.layer_force(k);
    EXPECT_NEAR(total_loaded, total_plain, 1e-9 * load);
  }

  TEST(SphLoadedFace, UniformStressIsBalancedInMixedPrecision)
  {
    // Parameters::single_precision (where the CPU has AVX2): each pair term is rounded to float
    // (6e-8 of it) and a layer of ~80 particles sums ~2,000 terms of both signs that cancel to
    // zero beneath the outer layer: they leave 2e-8 of the load (measured); 1e-6 is the float
    // round-off bound with a margin, and still 1e5 times below the 0.4 of the load that an
    // uncorrected face puts there
    CompressedCylinder loaded(true, true);
    const double       load = -loaded.sigma * loaded.lattice.true_section_area;
    EXPECT_NEAR(loaded.layer_force(0) / load, 1.0, 2e-3);
    for (int k = 1; k < 5; ++k)
      EXPECT_NEAR(loaded.layer_force(k) / load, 0.0, 1e-6) << "layer " << k;
  }

  TEST(SphLoadedFace, LoadedAreasAddUpToTheFace)
  {
    CompressedCylinder c(true);
    double             top = 0, bottom = 0;
    for (unsigned i = 0; i < c.body.n_particles(); ++i)
      {
        const double a = c.body.loaded_face_areas()[i];
        EXPECT_GE(a, 0.0);
        (c.lattice.positions[i][2] > 0.05 ? top : bottom) += a;
      }
    // the discrete face area is the section the volumes stand for (true volume / length):
    // within 0.2 % of pi R^2 (faceted rim of a 10-particle-wide lattice)
    EXPECT_NEAR(top / c.lattice.true_section_area, 1.0, 2e-3);
    EXPECT_NEAR(bottom / c.lattice.true_section_area, 1.0, 2e-3);
  }

  TEST(SphLoadedFace, BodyFittedCylinderOuterLayerTakesTheLoad)
  {
    // the same on the cylinder of rings: every column is one ring particle through all layers
    // (a column key of a whole spacing merged ring particles that round to one lattice cell)
    CompressedCylinder loaded(true, false, true);
    std::size_t        n_layer = 0;
    for (const auto &p : loaded.lattice.positions)
      n_layer += p[2] < 0.005 ? 1 : 0;
    std::size_t n_outer_top = 0;
    double      top = 0, bottom = 0;
    for (unsigned i = 0; i < loaded.body.n_particles(); ++i)
      {
        const double a = loaded.body.loaded_face_areas()[i];
        EXPECT_GE(a, 0.0);
        if (a > 0)
          n_outer_top += loaded.lattice.positions[i][2] > 0.05 ? 1 : 0;
        (loaded.lattice.positions[i][2] > 0.05 ? top : bottom) += a;
      }
    EXPECT_EQ(n_outer_top, n_layer) << "one column per particle of the end layer";
    // the rings' volumes are the true section exactly; the loaded areas add up to it within the
    // 0.2 % of the lattice test (their sum is the kernel sum of s_i, not the volumes)
    EXPECT_NEAR(top / loaded.lattice.true_section_area, 1.0, 2e-3);
    EXPECT_NEAR(bottom / loaded.lattice.true_section_area, 1.0, 2e-3);
    // a uniform stress is balanced by a load on the outer layer alone: the layer force is the
    // stress times the true section (2e-3 as for the lattice), the layers beneath round-off only
    const double load = -loaded.sigma * loaded.lattice.true_section_area;
    EXPECT_NEAR(loaded.layer_force(0) / load, 1.0, 2e-3);
    for (int k = 1; k < 5; ++k)
      EXPECT_NEAR(loaded.layer_force(k) / load, 0.0, 1e-9) << "layer " << k;
  }

  TEST(SphLoadedFace, ZeroNormalIsRefused)
  {
    CompressedCylinder c(false);
    EXPECT_THROW(c.body.add_loaded_face(Vector<3>::Zero()), std::invalid_argument);
  }

  TEST(SphLoadedFace, OverlappingFacesAreRefused)
  {
    // a loaded face takes the particles within two kernel supports (4h = 24 mm here) of it: the
    // same face declared twice, or the far face of a plate thinner than 8h, overlaps
    CompressedCylinder c(false);
    c.body.add_loaded_face(Vector<3>(0, 0, 1));
    EXPECT_THROW(c.body.add_loaded_face(Vector<3>(0, 0, 1)), std::invalid_argument);
    const Lattice<3> lat = make_block<3>(Vector<3>(0, 0, 0), Vector<3>(0.05, 0.05, 0.02), 0.005);
    Body<3> plate(CompressedCylinder::numerics(), CompressedCylinder::rock(), lat.positions,
                  lat.volumes);
    plate.add_loaded_face(Vector<3>(0, 0, 1));
    EXPECT_THROW(plate.add_loaded_face(Vector<3>(0, 0, -1)), std::invalid_argument);
  }
} // namespace

namespace
{
  TEST(SphPressure, HydrostaticStateIsInEquilibriumAtEveryParticle)
  {
    // A cylinder with loaded end faces under a pressure p, deformed affinely to the strain of the
    // stress -p I: internal and pressure forces cancel at every particle, edges and loaded-face
    // columns included. 1e-3 of a face particle's load: the stress is the small-strain response
    // to the strain 6.7e-5 while the pressure acts on the area pushed forward exactly, so the two
    // differ at the order of the strain (measured 1e-4); the former kernel-sum area vectors,
    // calibrated on a flat face, left 0.19 of the load unbalanced at the rim and the ends.
    using namespace sph;
    const double     p = 10e6, K = 50e9 / (3 * (1 - 2 * 0.25)), eps = -p / (3 * K);
    // the lattice and the body-fitted cylinder (CTCS's confining pressure on its round surface)
    for (const Lattice<3> &lat : {make_cylinder<3>(0.05, 0.1, 0.005), make_fitted_cylinder(0.05, 0.1, 0.005)})
      {
        Parameters prm;
        prm.spacing   = 0.005;
        prm.hourglass = 0;
        MaterialParameters m;
        m.model          = RockModel::elastic;
        m.youngs_modulus = 50e9;
        m.poissons_ratio = 0.25;
        Body<3> body(prm, m, lat.positions, lat.volumes);
        body.add_loaded_face(Vector<3>(0, 0, 1));
        body.add_loaded_face(Vector<3>(0, 0, -1));
        const double dt = 1e-6;
        body.compute_forces();
        for (unsigned i = 0; i < body.n_particles(); ++i)
          body.set_velocity(i, (eps / dt) * body.positions()[i]);
        body.integrate(dt);
        for (unsigned i = 0; i < body.n_particles(); ++i) // at rest: no viscous force
          body.set_velocity(i, Vector<3>::Zero());
        body.set_surface_pressure(p); // from now on: the deformed state is the hydrostatic one
        body.compute_forces();
        const double scale = p * 0.005 * 0.005;
        double       worst = 0;
        for (unsigned i = 0; i < body.n_particles(); ++i)
          worst = std::max(worst, (body.internal_forces()[i] + body.pressure_forces()[i]).norm());
        EXPECT_LT(worst, 1e-3 * scale);
      }
  }
} // namespace

namespace
{
  /// Sum of loaded areas over sum of cell areas (volume / layer thickness) of the top face's
  /// particles whose radius lies in [r0, r1) [mm], for a 50 x 100 mm cylinder at 2.5 mm.
  struct SideRings
  {
    sph::Lattice<3> lattice;
    sph::Body<3>    body;
    explicit SideRings(const bool fitted)
      : lattice(fitted ? sph::make_fitted_cylinder(0.05, 0.1, 0.0025) : sph::make_cylinder<3>(0.05, 0.1, 0.0025))
      , body(numerics(), material(), lattice.positions, lattice.volumes)
    {
      body.add_loaded_face(sph::Vector<3>(0, 0, 1));
    }
    static sph::Parameters numerics()
    {
      sph::Parameters p;
      p.spacing = 0.0025;
      return p;
    }
    static sph::MaterialParameters material()
    {
      sph::MaterialParameters m;
      m.model          = sph::RockModel::elastic;
      m.youngs_modulus = 50e9;
      m.poissons_ratio = 0.25;
      return m;
    }
    double ratio(const double r0, const double r1) const
    {
      double loaded = 0, cell = 0;
      for (unsigned i = 0; i < body.n_particles(); ++i)
      {
        const double a = body.loaded_face_areas()[i];
        const double r = 1e3 * std::hypot(lattice.positions[i][0], lattice.positions[i][1]);
        if (a > 0 && r >= r0 && r < r1)
          loaded += a, cell += lattice.volumes[i] / lattice.cell_size[2];
      }
      return loaded / cell;
    }
  };
} // namespace

TEST(SphLoadedFace, NearTheSideTheLoadedAreasAreNotTheCells)
{
  // The discrete area through which a uniform stress loads an end particle (the kernel sum
  // that keeps the stress in equilibrium) is its cell's inside but not within two kernel
  // supports of the side: the row two in carries more, the outer row less. A platen that
  // loads the particles by their cells (an elastic steel face under the contact) then sees a
  // ring over and a rim under its uniform pressure: coupling's contact remap
  // (ContactParameters::face_radius_mapped) moves the loads for exactly this. Measured at
  // 2.5 mm (lattice / body-fitted): rings 21.25-22.5 mm 1.234 / 1.273, 23.75-25 mm 0.659 /
  // 0.728, the lattice's inside (r < 16.25 mm) 1.0000. Bounds: the measured values with room
  // for the kernel's parameters, tight enough to say the effect is a quarter and a third.
  for (const bool fitted : {false, true})
  {
    SCOPED_TRACE(fitted ? "body-fitted" : "lattice");
    const SideRings c(fitted);
    EXPECT_GT(c.ratio(21.25, 22.5), 1.15);
    EXPECT_LT(c.ratio(21.25, 22.5), 1.35);
    EXPECT_GT(c.ratio(23.75, 25.01), 0.6);
    EXPECT_LT(c.ratio(23.75, 25.01), 0.8);
    if (!fitted) // 1e-3: the sums' round-off is far below; a cell inside has its own area
      EXPECT_NEAR(c.ratio(0, 16.25), 1.0, 1e-3);
  }
}
