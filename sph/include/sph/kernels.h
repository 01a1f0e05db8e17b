#pragma once
/// @file
/// Smoothing kernels: pure inline functions, support radius 2h, normalised in 2-D and 3-D.

#include <sph/types.h>

#include <cmath>

namespace sph
{
  /// Which smoothing kernel a body uses.
  enum class KernelType
  {
    cubic_spline, ///< Monaghan's M4 cubic spline (LS-DYNA's default), support 2h
    wendland_c2   ///< Wendland C2, support 2h (no pairing instability)
  };

  namespace kernels
  {
    constexpr double pi = 3.14159265358979323846;

    /// Normalisation of the cubic spline: 10/(7 pi) in 2-D, 1/pi in 3-D.
    template <int dim>
    constexpr double cubic_spline_sigma()
    {
      return dim == 2 ? 10.0 / (7.0 * pi) : (dim == 3 ? 1.0 / pi : 2.0 / 3.0);
    }

    /// Normalisation of Wendland C2 with support 2h: 7/(4 pi) in 2-D, 21/(16 pi) in 3-D.
    template <int dim>
    constexpr double wendland_c2_sigma()
    {
      return dim == 2 ? 7.0 / (4.0 * pi) : (dim == 3 ? 21.0 / (16.0 * pi) : 0.75);
    }

    template <int dim>
    inline double h_power(const double h)
    {
      return dim == 2 ? h * h : (dim == 3 ? h * h * h : h);
    }

    /// Cubic spline W(r, h) [1/m^dim].
    template <int dim>
    inline double cubic_spline_w(const double r, const double h)
    {
      const double q = r / h;
      const double s = cubic_spline_sigma<dim>() / h_power<dim>(h);
      if (q < 1.0)
        return s * (1.0 - 1.5 * q * q + 0.75 * q * q * q);
      if (q < 2.0)
        {
          const double t = 2.0 - q;
          return s * 0.25 * t * t * t;
        }
      return 0.0;
    }

    /// Cubic spline dW/dr (r, h) [1/m^(dim+1)], <= 0.
    template <int dim>
    inline double cubic_spline_dw_dr(const double r, const double h)
    {
      const double q = r / h;
      const double s = cubic_spline_sigma<dim>() / (h_power<dim>(h) * h);
      if (q < 1.0)
        return s * (-3.0 * q + 2.25 * q * q);
      if (q < 2.0)
        {
          const double t = 2.0 - q;
          return -s * 0.75 * t * t;
        }
      return 0.0;
    }

    /// Wendland C2 W(r, h) = sigma/h^dim (1 - q/2)^4 (2q + 1), q = r/h < 2 [1/m^dim].
    template <int dim>
    inline double wendland_c2_w(const double r, const double h)
    {
      const double q = r / h;
      if (q >= 2.0)
        return 0.0;
      const double t  = 1.0 - 0.5 * q;
      const double t2 = t * t;
      return wendland_c2_sigma<dim>() / h_power<dim>(h) * t2 * t2 * (2.0 * q + 1.0);
    }

    /// Wendland C2 dW/dr = sigma/h^(dim+1) (-5 q)(1 - q/2)^3 [1/m^(dim+1)], <= 0.
    template <int dim>
    inline double wendland_c2_dw_dr(const double r, const double h)
    {
      const double q = r / h;
      if (q >= 2.0)
        return 0.0;
      const double t = 1.0 - 0.5 * q;
      return wendland_c2_sigma<dim>() / (h_power<dim>(h) * h) * (-5.0 * q) * t * t * t;
    }

    /// W of the chosen kernel [1/m^dim].
    template <int dim>
    inline double w(const KernelType type, const double r, const double h)
    {
      return type == KernelType::cubic_spline ? cubic_spline_w<dim>(r, h) :
                                                wendland_c2_w<dim>(r, h);
    }

    /// dW/dr of the chosen kernel [1/m^(dim+1)].
    template <int dim>
    inline double dw_dr(const KernelType type, const double r, const double h)
    {
      return type == KernelType::cubic_spline ? cubic_spline_dw_dr<dim>(r, h) :
                                                wendland_c2_dw_dr<dim>(r, h);
    }

    /// Gradient of W(|x_i - x_j|, h) with respect to x_i, `xij` = x_i - x_j [1/m^(dim+1)].
    /// Antisymmetric: grad_w(x_ji) == -grad_w(x_ij) bit for bit.
    template <int dim>
    inline Vector<dim> grad_w(const KernelType type, const Vector<dim> &xij, const double h)
    {
      const double r = xij.norm();
      if (r <= 0.0)
        return Vector<dim>::Zero();
      return (dw_dr<dim>(type, r, h) / r) * xij;
    }
  } // namespace kernels
} // namespace sph
