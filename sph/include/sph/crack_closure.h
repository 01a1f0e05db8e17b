#pragma once
/// @file
/// Crack-closure (toe) elasticity in the SPH rock: the rock's elastic moduli scale with the
/// tangent Young's modulus of rock::crack_closure_tangent_modulus (rock_models.h), the law that
/// `cosim diagnose` fits, so that a diagnosed E0 / E and closure stress mean the same in both:
///
///   1/E_t(p) = 1/E + (1/E0 - 1/E) exp(-p / sigma_cc),   p = compressive stress normal to the
///   cracks [Pa], here the most compressive principal stress (0 in tension).
///
/// The law is hypoelastic: each increment takes K and G scaled by E_t / E (Poisson's ratio kept)
/// at the midpoint stress of the increment (a predictor with the old stress, then the tangent at
/// the mean of the old and the predicted p), so a uniaxial stress path integrates
/// d(sigma) = E_t(sigma) d(eps) to second order in the increment and follows
/// rock::crack_closure_strain. The plastic models return with the same scaled moduli.
/// Stresses are tension-positive, as everywhere in the solver.
///
/// Energy: Body::energies() reports the elastic energy with the intact moduli, so the energy
/// stored by closing cracks (the toe's extra strain) is counted with the plastic work; the total,
/// and so the energy balance, is unchanged. The stable time step is the intact rock's (E_t <= E).

#include <sph/parameters.h>
#include <sph/rock_models.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <variant>

namespace sph::rock
{
  /// Constants of the closure law.
  struct CrackClosure
  {
    double E        = 1; ///< intact Young's modulus [Pa]
    double E0       = 1; ///< Young's modulus at zero compressive stress [Pa], 0 < E0 <= E
    double sigma_cc = 1; ///< closure stress [Pa], > 0
  };

  /// The most compressive principal stress of `s` as a positive pressure, 0 if none [Pa].
  inline double closure_pressure(const Tensor3 &s)
  {
    Eigen::SelfAdjointEigenSolver<Tensor3> eig;
    eig.computeDirect(s, Eigen::EigenvaluesOnly);
    return std::max(-eig.eigenvalues()[0], 0.0);
  }

  /// E_t(p) / E of the closure law, in (E0 / E, 1] [-].
  inline double closure_modulus_factor(const double p, const CrackClosure &c)
  {
    return crack_closure_tangent_modulus(p, c.E, c.E0, c.sigma_cc) / c.E;
  }

  /// The model constants with K and G scaled by `factor` (strengths unchanged).
  inline ModelConstants scaled_moduli(ModelConstants p, const double factor)
  {
    p.K *= factor;
    p.G *= factor;
    return p;
  }

  /// A rock model (Elastic, MohrCoulomb, HoekBrown) with crack-closure elasticity.
  template <typename Inner>
  struct WithCrackClosure
  {
    Inner        inner;
    CrackClosure law;

    StressUpdate operator()(const Tensor3 &s, const Tensor3 &de, const MaterialState &h,
                            const ModelConstants &p) const
    {
      const double p_old = closure_pressure(s);
      const Tensor3 predicted =
        elastic_trial(s, de, scaled_moduli(p, closure_modulus_factor(p_old, law)));
      const double p_mid = 0.5 * (p_old + closure_pressure(predicted));
      return inner(s, de, h, scaled_moduli(p, closure_modulus_factor(p_mid, law)));
    }
    /// Never: the caller's trial uses the intact moduli, so the update must always run.
    bool surely_elastic(const Tensor3 &, const MaterialState &, const ModelConstants &) const
    {
      return false;
    }
  };

  /// Run-time choice of the rock model including the closure variants (dispatched once per
  /// particle loop with std::visit, as rock::Model).
  using ModelChoice = std::variant<Elastic, MohrCoulomb, HoekBrown, WithCrackClosure<Elastic>,
                                   WithCrackClosure<MohrCoulomb>, WithCrackClosure<HoekBrown>>;

  /// True where the material has crack closure (closure_modulus_ratio < 1).
  inline bool has_crack_closure(const MaterialParameters &m)
  {
    return m.closure_modulus_ratio < 1.0;
  }

  /// The functor of a material: its RockModel, with closure where the material has it.
  inline ModelChoice make_model_choice(const MaterialParameters &m)
  {
    const Model base = make_model(m.model);
    if (!has_crack_closure(m))
      return std::visit([](const auto &b) { return ModelChoice(b); }, base);
    const CrackClosure law{m.youngs_modulus, m.closure_modulus_ratio * m.youngs_modulus,
                           m.closure_stress};
    return std::visit(
      [&law](const auto &b) {
        return ModelChoice(WithCrackClosure<std::decay_t<decltype(b)>>{b, law});
      },
      base);
  }
} // namespace sph::rock
