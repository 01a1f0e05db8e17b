#pragma once
/// @file
/// Struct-of-arrays particle storage, with the per-particle material history in its own array.

#include <sph/types.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace sph
{
  /// How a particle failed: the kind of the plastic return that last changed it while it still
  /// had strength to lose (rock_models.h, classify_failure). Values as written to results.h5.
  enum class FailureMode : std::uint8_t
  {
    none    = 0, ///< never yielded
    tensile = 1, ///< tension cut-off, or a Mohr-Coulomb return whose failure plane is in tension
    shear   = 2, ///< Mohr-Coulomb (Hoek-Brown) return with the failure plane in compression
    crushed = 3  ///< shear under a mean compression of at least the rock's uniaxial strength
  };

  /// History of one particle's material (step-18 style: a small plain struct).
  struct MaterialState
  {
    double plastic_strain = 0; ///< equivalent plastic strain sqrt(2/3 e_p:e_p), accumulated [-]
    double damage         = 0; ///< softening damage in [0, 1]; never decreases [-]
    double strength       = 1; ///< the particle's strength relative to the rock's (scatter) [-]
    FailureMode failure_mode = FailureMode::none; ///< how the particle failed
    /// Softened in a tensile return at least once (a crack opened here); never reset. The body
    /// drops the hourglass control of its pairs (Parameters::hourglass_fade).
    bool cracked = false;
  };

  /// All particle fields, one array per field, indexed by particle number.
  template <int dim>
  struct ParticleStore
  {
    std::vector<Vector<dim>> x;      ///< current position [m]
    std::vector<Vector<dim>> v;      ///< velocity [m/s]
    std::vector<Vector<dim>> x0;     ///< reference (initial) position [m]
    std::vector<double>      mass;   ///< mass [kg]
    std::vector<double>      volume0; ///< reference volume [m^3 in 3-D, m^2 in 2-D]
    std::vector<double>      volume; ///< current volume [m^dim]
    std::vector<double>      density; ///< current density [kg/m^dim]
    std::vector<double>      h;      ///< smoothing length [m]
    std::vector<Tensor3>     stress; ///< Cauchy stress, tension + [Pa] (3x3; 2-D: plane strain)
    std::vector<Tensor<dim>> F;      ///< deformation gradient dx/dX [-]
    std::vector<Tensor<dim>> L;      ///< kernel-gradient correction matrix [-] (identity if off)
    std::vector<Vector<dim>> f_int;  ///< internal + viscous + hourglass force [N]
    std::vector<Vector<dim>> f_ext;  ///< external force added by the user before a step [N]
    std::vector<Vector<dim>> f_pressure; ///< surface-pressure force [N]
    std::vector<MaterialState> history; ///< material history

    /// Number of particles.
    std::size_t size() const { return x.size(); }

    /// Resizes every array to `n` (new entries zero, F and L identity).
    void resize(std::size_t n)
    {
      x.resize(n, Vector<dim>::Zero());
      v.resize(n, Vector<dim>::Zero());
      x0.resize(n, Vector<dim>::Zero());
      mass.resize(n, 0.0);
      volume0.resize(n, 0.0);
      volume.resize(n, 0.0);
      density.resize(n, 0.0);
      h.resize(n, 0.0);
      stress.resize(n, Tensor3::Zero());
      F.resize(n, Tensor<dim>::Identity());
      L.resize(n, Tensor<dim>::Identity());
      f_int.resize(n, Vector<dim>::Zero());
      f_ext.resize(n, Vector<dim>::Zero());
      f_pressure.resize(n, Vector<dim>::Zero());
      history.resize(n);
    }
  };
} // namespace sph
