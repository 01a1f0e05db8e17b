#include <sph/kernels.h>
#include <sph/lattice.h>

#include <gtest/gtest.h>

#include <cmath>

namespace
{
  using namespace sph;

  template <int dim>
  double max_partition_error(const KernelType kernel, const double cslh)
  {
    // interior of a lattice of unit spacing: every particle more than 2h from the faces
    const int         n = 16;
    Vector<dim>       lo = Vector<dim>::Zero(), hi = Vector<dim>::Constant(n);
    const Lattice<dim> lat = make_block<dim>(lo, hi, 1.0);
    const double h = cslh;
    double       worst = 0;
    for (std::size_t i = 0; i < lat.positions.size(); ++i)
      {
        const auto &xi = lat.positions[i];
        if ((xi.array() < 2 * h + 0.5).any() || (xi.array() > n - 2 * h - 0.5).any())
          continue;
        double s = 0;
        for (std::size_t j = 0; j < lat.positions.size(); ++j)
          s += lat.volumes[j] * kernels::w<dim>(kernel, (xi - lat.positions[j]).norm(), h);
        worst = std::max(worst, std::abs(s - 1.0));
      }
    return worst;
  }

  TEST(SphKernel, PartitionOfUnityInsideLattice)
  {
    // A cubic lattice: sum_j V_j W_ij = 1 up to the kernel's discretisation error, which the
    // brief bounds by 1e-3. The cubic spline meets it at h = 1.2 dx (LS-DYNA's default, 8e-4 in
    // 3-D); Wendland C2 is wider and needs h = 2 dx (at 1.2 dx its error is 1.7e-2).
    EXPECT_LT(max_partition_error<2>(KernelType::cubic_spline, 1.2), 1e-3);
    EXPECT_LT(max_partition_error<3>(KernelType::cubic_spline, 1.2), 1e-3);
    // 2-D Wendland at 2 dx: 1.2e-3 measured, so 2e-3 here
    EXPECT_LT(max_partition_error<2>(KernelType::wendland_c2, 2.0), 2e-3);
    EXPECT_LT(max_partition_error<3>(KernelType::wendland_c2, 2.0), 1e-3);
  }

  template <int dim>
  double radial_integral(const KernelType kernel, const double h)
  {
    // int W dV by the midpoint rule in r: 2 pi r dr (2-D), 4 pi r^2 dr (3-D)
    const int    n  = 200000;
    const double dr = 2.0 * h / n;
    double       s  = 0;
    for (int k = 0; k < n; ++k)
      {
        const double r = (k + 0.5) * dr;
        s += kernels::w<dim>(kernel, r, h) * (dim == 2 ? 2 * kernels::pi * r :
                                                         4 * kernels::pi * r * r) * dr;
      }
    return s;
  }

  TEST(SphKernel, NormalisedInTwoAndThreeDimensions)
  {
    // midpoint rule with 2e5 intervals: error ~1e-10, far below 1e-8
    for (const KernelType k : {KernelType::cubic_spline, KernelType::wendland_c2})
      {
        EXPECT_NEAR(radial_integral<2>(k, 0.7), 1.0, 1e-8);
        EXPECT_NEAR(radial_integral<3>(k, 0.7), 1.0, 1e-8);
      }
  }

  TEST(SphKernel, DerivativeMatchesFiniteDifference)
  {
    // central difference with step 1e-6 h: truncation ~1e-12, round-off ~1e-10 relative
    const double h = 0.3, e = 1e-6 * h;
    for (const KernelType k : {KernelType::cubic_spline, KernelType::wendland_c2})
      for (double q = 0.05; q < 2.0; q += 0.0737)
        {
          const double r  = q * h;
          const double fd = (kernels::w<3>(k, r + e, h) - kernels::w<3>(k, r - e, h)) / (2 * e);
          EXPECT_NEAR(kernels::dw_dr<3>(k, r, h), fd, 1e-6 * std::abs(fd) + 1e-9);
        }
  }

  TEST(SphKernel, GradientAntisymmetric)
  {
    // grad W is dW/dr (x_ij / r): negating x_ij negates every product exactly
    const Vector<3> xij(0.1234, -0.0456, 0.2001);
    const Vector<3> a = kernels::grad_w<3>(KernelType::cubic_spline, xij, 0.2);
    const Vector<3> b = kernels::grad_w<3>(KernelType::cubic_spline, Vector<3>(-xij), 0.2);
    ASSERT_GT(a.norm(), 0.0) << "the pair must be inside the support";
    EXPECT_LT((a + b).norm(), 1e-15 * a.norm());
  }
} // namespace
