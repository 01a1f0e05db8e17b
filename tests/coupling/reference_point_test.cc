// The small pieces of the FE reference: the axisymmetric stress update and tangent around sph's
// return mapping, the platen size rule and the inputs it refuses.
#include <coupling/errors.h>
#include <coupling/reference_cylinder.h>

#include <gtest/gtest.h>

#include <cmath>

namespace
{
  using namespace coupling;

  struct Rock
  {
    sph::MaterialParameters m;
    sph::rock::ModelConstants k;
    sph::rock::Model model;
    explicit Rock(const sph::RockModel which)
    {
      CaseParameters p;
      p.rock.model = which;
      m            = reference_rock(p);
      k            = sph::rock::make_model_constants(m);
      model        = sph::rock::make_model(which);
    }
  };
} // namespace

TEST(ReferencePoint, ElasticTangentIsIsotropic)
{
  const Rock rock(sph::RockModel::mohr_coulomb);
  const ReferencePointUpdate u = reference_point_update(
    rock.model, rock.k, Voigt4{}, sph::MaterialState{}, Voigt4{{-1e-4, -2e-4, 3e-5, 1e-5}});
  EXPECT_FALSE(u.plastic);
  const double lambda = rock.k.K - 2.0 / 3.0 * rock.k.G;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
    {
      const double expected =
        i == 3 || j == 3 ? (i == j ? rock.k.G : 0.0) : lambda + (i == j ? 2 * rock.k.G : 0.0);
      EXPECT_NEAR(u.tangent[i][j], expected, 1e-12 * rock.k.K) << i << ", " << j;
    }
  // engineering shear: sigma_rz = G gamma_rz
  EXPECT_NEAR(u.stress[3], rock.k.G * 1e-5, 1e-9 * rock.k.G * 1e-5);
}

TEST(ReferencePoint, PlasticUpdateLiesOnTheSurfaceAndTheTangentPredictsIt)
{
  const Rock rock(sph::RockModel::mohr_coulomb);
  // uniaxial compression well past yield (UCS / E = 2.9e-3), with some shear
  const Voigt4 de{{1.4e-3, -5e-3, 1.3e-3, 1e-3}};
  const ReferencePointUpdate u =
    reference_point_update(rock.model, rock.k, Voigt4{}, sph::MaterialState{}, de);
  ASSERT_TRUE(u.plastic);
  // on the Mohr-Coulomb surface (principal stresses of the r-z block and theta)
  const double c = 0.5 * (u.stress[0] + u.stress[1]),
               d = std::hypot(0.5 * (u.stress[0] - u.stress[1]), u.stress[3]);
  double s[3]    = {c + d, c - d, u.stress[2]};
  std::sort(s, s + 3);
  const double f = s[2] * (1 + rock.k.sin_phi) - s[0] * (1 - rock.k.sin_phi) -
                   2 * rock.m.cohesion * rock.k.cos_phi;
  EXPECT_NEAR(f, 0.0, 1e-9 * rock.m.cohesion);
  // the tangent predicts a small further strain to first order: the error of the prediction is
  // second order, below 1e-3 of the change for a step of 1e-6 (the update's curvature scale is
  // the strain itself, ~1e-3)
  const Voigt4 step{{2e-7, -1e-6, 3e-7, 2e-7}};
  Voigt4 de2 = de;
  for (int k = 0; k < 4; ++k)
    de2[k] += step[k];
  const ReferencePointUpdate v =
    reference_point_update(rock.model, rock.k, Voigt4{}, sph::MaterialState{}, de2);
  double change = 0, error = 0;
  for (int i = 0; i < 4; ++i)
  {
    double predicted = 0;
    for (int k = 0; k < 4; ++k)
      predicted += u.tangent[i][k] * step[k];
    change = std::max(change, std::abs(v.stress[i] - u.stress[i]));
    error  = std::max(error, std::abs(v.stress[i] - u.stress[i] - predicted));
  }
  ASSERT_GT(change, 0.0);
  EXPECT_LT(error, 1e-3 * change);
}

TEST(ReferencePoint, ReferenceRockIsPerfectlyPlastic)
{
  CaseParameters p; // the case's rock softens
  ASSERT_GT(p.rock.softening_strain, 0.0);
  const sph::MaterialParameters m = reference_rock(p);
  EXPECT_EQ(m.softening_strain, 0.0);
  EXPECT_LT(m.residual_friction_angle, 0.0);
  EXPECT_EQ(m.cohesion, p.rock.cohesion);
  EXPECT_EQ(m.dilation_angle, p.rock.dilation_angle);
}

TEST(ReferencePoint, PlatenDiameterRule)
{
  CaseParameters p;
  p.sph.spacing = 0.0025;
  EXPECT_NEAR(reference_platen_diameter(p), 0.05 + 4 * 0.0025, 1e-15); // as the coupled driver
  p.platens.diameter = 0.08;
  EXPECT_EQ(reference_platen_diameter(p), 0.08);
}

TEST(ReferencePoint, RefusesWhatItCannotModel)
{
  CaseParameters p;
  ReferenceOptions o;
  p.test = "BTS";
  EXPECT_THROW(run_reference_cylinder(p, o), InputError);
  p.test       = "UCS";
  p.rock.model = sph::RockModel::mohr_coulomb;
  o.degree     = 3;
  EXPECT_THROW(run_reference_cylinder(p, o), InputError);
  o.degree   = 2;
  o.n_radial = 0;
  EXPECT_THROW(run_reference_cylinder(p, o), InputError);
}
