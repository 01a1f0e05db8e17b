#pragma once
/// @file
/// Small fixed-size vector and tensor types of the SPH library (Eigen, no allocation).

#include <Eigen/Dense>

namespace sph
{
  /// A point or vector in `dim` dimensions [SI units of the quantity].
  template <int dim>
  using Vector = Eigen::Matrix<double, dim, 1>;

  /// A second-order tensor in `dim` dimensions (row = first index).
  template <int dim>
  using Tensor = Eigen::Matrix<double, dim, dim>;

  /// Full 3x3 tensor: constitutive updates always work in 3-D (2-D bodies are plane strain, the
  /// out-of-plane stress is kept in the (2,2) entry).
  using Tensor3 = Eigen::Matrix3d;

  /// Embeds a `dim` tensor into the upper-left block of a 3x3 tensor (zeros elsewhere).
  template <int dim>
  inline Tensor3 embed(const Tensor<dim> &t)
  {
    Tensor3 r = Tensor3::Zero();
    r.template topLeftCorner<dim, dim>() = t;
    return r;
  }
} // namespace sph
