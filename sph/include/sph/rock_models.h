#pragma once
/// @file
/// Rock constitutive updates: pure inline functions (old stress, strain increment, history) ->
/// (new stress, new history). Stress is tension-positive. Updates work on 3x3 tensors; 2-D bodies
/// pass plane-strain increments (zero out-of-plane strain) and keep sigma_zz in the (2,2) entry.
/// Plastic returns are made in principal stresses sorted s0 >= s1 >= s2 (s0 most tensile).

#include <sph/parameters.h>
#include <sph/particle_store.h>
#include <sph/types.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <variant>

namespace sph::rock
{
  using Principal = Eigen::Vector3d;

  /// Constants of the rock model that the stress updates need (moduli, sines of the angles,
  /// Hoek-Brown constants), derived once from MaterialParameters.
  struct ModelConstants
  {
    double K = 0;                  ///< bulk modulus [Pa]
    double G = 0;                  ///< shear modulus [Pa]
    double cohesion = 0;           ///< c [Pa]
    double sin_phi = 0, cos_phi = 1; ///< friction angle phi
    double sin_psi = 0;            ///< dilation angle psi (plastic potential)
    double tensile_strength = 0;   ///< Rankine cut-off [Pa]; <= 0: none
    double hb_sigma_ci = 0, hb_mb = 1, hb_s = 1, hb_a = 0.5; ///< Hoek-Brown [Pa, -, -, -]
    double softening_strain = 0;   ///< kappa at which the strength is residual [-]; 0: no softening
    double residual_fraction = 1;  ///< residual / peak strength [-]
    double phi = 0;                ///< friction angle [rad]
    double phi_residual = -1;      ///< friction angle at damage 1 [rad]; < 0: phi throughout
    /// Crack band (SofteningLaw::fracture_energy): band width h over the fracture energy of a
    /// tensile and of a shear failure, h / G_I and h / G_II [m^3/J]; 0: the strain law
    double band_over_g_tensile = 0, band_over_g_shear = 0;
    /// Mean compression [Pa] from which a shear failure counts as crushing: the intact rock's
    /// uniaxial compressive strength (2 c cos phi / (1 - sin phi); Hoek-Brown: sigma_ci s^a)
    double crush_pressure = 0;
  };

  /// Uniaxial tensile strength of the intact rock of `m` [Pa]: the Mohr-Coulomb limit
  /// 2 c cos(phi) / (1 + sin(phi)), the cut-off where lower; Hoek-Brown: its cut-off
  /// s sigma_ci / m_b (an upper bound of the uniaxial one); elastic: infinity.
  inline double uniaxial_tensile_strength(const MaterialParameters &m)
  {
    if (m.model == RockModel::elastic)
      return HUGE_VAL;
    if (m.model == RockModel::hoek_brown)
      return m.tensile_strength > 0 ? std::min(m.tensile_strength, m.hb_s * m.hb_sigma_ci / m.hb_mb) :
                                      m.hb_s * m.hb_sigma_ci / m.hb_mb;
    const double mc =
      2.0 * m.cohesion * std::cos(m.friction_angle) / (1.0 + std::sin(m.friction_angle));
    return m.model == RockModel::mohr_coulomb_cutoff ? std::min(mc, m.tensile_strength) : mc;
  }

  /// Width of an SPH crack band [m] on a lattice of spacing dx with smoothing length
  /// h = cslh * dx: the narrowest zone of broken (stress-free) particle layers that separates
  /// the body. Across n broken layers the nearest unbroken layers are (n + 1) dx apart and
  /// share no pair once that is at least the support radius 2 h: n = ceil(2 cslh - 1) layers
  /// (cslh = 1.2: 2). The direct tension test in tests/sph measures it: without hourglass
  /// control two layers break, the force falls to zero, and the energy stays put as the gap
  /// opens further, at 2.5 and at 1.25 mm.
  inline double crack_band_width(const double spacing, const double cslh)
  {
    return std::ceil(2.0 * cslh - 1.0 - 1e-9) * spacing;
  }

  /// Widest crack band [m] that SofteningLaw::fracture_energy can soften without snap-back:
  /// in uniaxial tension the crack strain at zero stress, 2 G_I / (f_t h), must exceed the
  /// elastic strain at the peak, f_t / E, so h < 2 E G_I / f_t^2 (twice Hillerborg's
  /// characteristic length E G_I / f_t^2). Infinite for a rock without tensile strength limit.
  inline double max_crack_band_width(const MaterialParameters &m)
  {
    const double ft = uniaxial_tensile_strength(m);
    return std::isfinite(ft) && ft > 0 ? 2.0 * m.youngs_modulus * m.fracture_energy / (ft * ft) :
                                         HUGE_VAL;
  }

  /// The model constants of a material; `band_width` [m] is the crack band width h of
  /// SofteningLaw::fracture_energy (crack_band_width; unused by the strain law).
  inline ModelConstants make_model_constants(const MaterialParameters &m,
                                             const double band_width = 0.0)
  {
    ModelConstants p;
    const double E = m.youngs_modulus, nu = m.poissons_ratio;
    p.K        = E / (3.0 * (1.0 - 2.0 * nu));
    p.G        = E / (2.0 * (1.0 + nu));
    p.cohesion = m.cohesion;
    p.sin_phi  = std::sin(m.friction_angle);
    p.cos_phi  = std::cos(m.friction_angle);
    p.sin_psi  = std::sin(m.dilation_angle);
    p.tensile_strength =
      (m.model == RockModel::mohr_coulomb_cutoff) ? m.tensile_strength : 0.0;
    p.hb_sigma_ci = m.hb_sigma_ci;
    p.hb_mb       = m.hb_mb;
    p.hb_s        = m.hb_s;
    p.hb_a        = m.hb_a;
    if (m.model == RockModel::hoek_brown)
      p.tensile_strength = m.tensile_strength > 0 ? std::min(m.tensile_strength,
                                                             m.hb_s * m.hb_sigma_ci / m.hb_mb) :
                                                    m.hb_s * m.hb_sigma_ci / m.hb_mb;
    p.softening_strain  = m.softening_strain;
    p.residual_fraction = m.residual_fraction;
    p.phi               = m.friction_angle;
    p.phi_residual      = m.residual_friction_angle;
    p.crush_pressure    = (m.model == RockModel::hoek_brown) ?
                            m.hb_sigma_ci * std::pow(m.hb_s, m.hb_a) :
                            2.0 * m.cohesion * p.cos_phi / (1.0 - p.sin_phi);
    if (m.softening_law == SofteningLaw::fracture_energy)
      {
        // the strain law's variable does not soften; the crack band does (plastic_update)
        p.softening_strain = 0;
        if (m.residual_fraction < 1.0 && band_width > 0 && m.fracture_energy > 0)
          {
            p.band_over_g_tensile = band_width / m.fracture_energy;
            p.band_over_g_shear =
              band_width / (m.fracture_energy * m.shear_fracture_energy_ratio);
          }
      }
    return p;
  }

  /// New stress and history after one increment.
  struct StressUpdate
  {
    Tensor3       stress; ///< Cauchy stress, tension + [Pa]
    MaterialState state;  ///< updated history
  };

  /// Damage d = min(kappa / softening_strain, 1) (0 without softening) [-].
  inline double damage_of(const double kappa, const ModelConstants &p)
  {
    return p.softening_strain > 0 ? std::min(kappa / p.softening_strain, 1.0) : 0.0;
  }

  /// Strength factor 1 - (1 - residual_fraction) d: multiplies c and sigma_t [-].
  inline double strength_factor(const double damage, const ModelConstants &p)
  {
    return 1.0 - (1.0 - p.residual_fraction) * damage;
  }

  /// sin and cos of the Mohr-Coulomb friction angle at damage d: phi + (phi_r - phi) d with a
  /// residual angle phi_r, phi (the stored values, bit for bit) without one or at d = 0.
  struct Friction
  {
    double sin_phi, cos_phi;
  };
  inline Friction friction_at(const double damage, const ModelConstants &p)
  {
    if (p.phi_residual < 0 || damage <= 0)
      return {p.sin_phi, p.cos_phi};
    const double phi = p.phi + (p.phi_residual - p.phi) * damage;
    return {std::sin(phi), std::cos(phi)};
  }

  /// Elastic predictor: stress_old + C : de (isotropic).
  inline Tensor3 elastic_trial(const Tensor3 &stress_old, const Tensor3 &de, const ModelConstants &p)
  {
    const double tr = de.trace();
    return stress_old + 2.0 * p.G * de + (p.K - 2.0 / 3.0 * p.G) * tr * Tensor3::Identity();
  }

  /// D * b in principal space for D = lambda 1 1^T + 2G I.
  inline Principal principal_stiffness_times(const Principal &b, const ModelConstants &p)
  {
    return (p.K - 2.0 / 3.0 * p.G) * b.sum() * Principal::Ones() + 2.0 * p.G * b;
  }

  /// Plastic strain (principal) D^{-1} (s_trial - s_new).
  inline Principal principal_compliance_times(const Principal &ds, const ModelConstants &p)
  {
    const double mean = ds.sum() / 3.0;
    return (ds - mean * Principal::Ones()) / (2.0 * p.G) + mean / (3.0 * p.K) * Principal::Ones();
  }

  /// Mohr-Coulomb yield function f = s0 (1 + sin phi) - s2 (1 - sin phi) - 2 c cos phi [Pa].
  inline double mohr_coulomb_yield(const Principal &s, const double c, const double sin_phi,
                                   const double cos_phi)
  {
    return s[0] * (1.0 + sin_phi) - s[2] * (1.0 - sin_phi) - 2.0 * c * cos_phi;
  }

  /// Closest-point return (in the energy norm, non-associated flow with dilation psi) of sorted
  /// principal stresses onto the Mohr-Coulomb surface of cohesion c: main plane, the edges
  /// s0 = s1 and s1 = s2, or the apex c cot(phi). Returns false if `s` was admissible.
  inline bool return_mohr_coulomb(Principal &s, const double c, const double sin_phi,
                                  const double cos_phi, const double sin_psi,
                                  const ModelConstants &p)
  {
    const double tol = 1e-14 * (std::abs(c) + s.cwiseAbs().maxCoeff());
    const double fA  = mohr_coulomb_yield(s, c, sin_phi, cos_phi);
    if (fA <= tol)
      return false;
    const Principal aA(1.0 + sin_phi, 0.0, -(1.0 - sin_phi));
    const Principal bA(1.0 + sin_psi, 0.0, -(1.0 - sin_psi));
    const Principal DbA = principal_stiffness_times(bA, p);
    // main plane
    Principal r = s - fA / aA.dot(DbA) * DbA;
    if (r[0] >= r[1] && r[1] >= r[2])
      {
        s = r;
        return true;
      }
    // an edge: the second plane has the same form with s1 in place of s0 (edge s0 = s1) or of s2
    // (edge s1 = s2)
    const bool upper = r[1] > r[0];
    Principal  aB, bB;
    if (upper)
      {
        aB = Principal(0.0, 1.0 + sin_phi, -(1.0 - sin_phi));
        bB = Principal(0.0, 1.0 + sin_psi, -(1.0 - sin_psi));
      }
    else
      {
        aB = Principal(1.0 + sin_phi, -(1.0 - sin_phi), 0.0);
        bB = Principal(1.0 + sin_psi, -(1.0 - sin_psi), 0.0);
      }
    const double    fB  = aB.dot(s) - 2.0 * c * cos_phi;
    const Principal DbB = principal_stiffness_times(bB, p);
    const double    a11 = aA.dot(DbA), a12 = aA.dot(DbB), a21 = aB.dot(DbA), a22 = aB.dot(DbB);
    const double    det = a11 * a22 - a12 * a21;
    const double    lA  = (fA * a22 - a12 * fB) / det;
    const double    lB  = (a11 * fB - a21 * fA) / det;
    r                   = s - lA * DbA - lB * DbB;
    const bool beyond_apex = upper ? (r[2] > r[0]) : (r[0] < r[1]);
    if (lA >= 0.0 && lB >= 0.0 && !beyond_apex)
      {
        if (upper)
          r[1] = r[0]; // equal by construction; remove round-off
        else
          r[2] = r[1];
        s = r;
        return true;
      }
    // apex
    const double apex = sin_phi > 0 ? c * cos_phi / sin_phi : s.sum() / 3.0;
    s                 = Principal::Constant(apex);
    return true;
  }

  /// Rankine (tension cut-off) return with associated flow: no principal stress above `st` [Pa].
  /// Returns false if `s` was admissible.
  inline bool return_rankine(Principal &s, const double st, const ModelConstants &p)
  {
    if (s[0] <= st)
      return false;
    const double lam = p.K - 2.0 / 3.0 * p.G, d = lam + 2.0 * p.G;
    // active set grows from the most tensile principal stress
    for (int k = 1; k <= 3; ++k)
      {
        Principal r = s;
        if (k == 1)
          {
            const double dl = (s[0] - st) / d;
            r[0]            = st;
            r[1] -= dl * lam;
            r[2] -= dl * lam;
            if (r[1] <= st)
              {
                s = r;
                return true;
              }
          }
        else if (k == 2)
          {
            // [d lam; lam d] [l0; l1] = [s0 - st; s1 - st]
            const double e0 = s[0] - st, e1 = s[1] - st, det = d * d - lam * lam;
            const double l0 = (d * e0 - lam * e1) / det, l1 = (d * e1 - lam * e0) / det;
            r[0] = st;
            r[1] = st;
            r[2] -= lam * (l0 + l1);
            if (r[2] <= st && l0 >= 0 && l1 >= 0)
              {
                s = r;
                return true;
              }
          }
        else
          {
            s = Principal::Constant(st);
            return true;
          }
      }
    return true;
  }

  /// Sorted principal stresses (s0 >= s1 >= s2) and the matching eigenvectors (columns).
  inline void principal_decomposition(const Tensor3 &sigma, Principal &s, Tensor3 &Q)
  {
    Eigen::SelfAdjointEigenSolver<Tensor3> eig(sigma);
    const auto &ev = eig.eigenvalues(); // ascending
    s              = Principal(ev[2], ev[1], ev[0]);
    Q.col(0)       = eig.eigenvectors().col(2);
    Q.col(1)       = eig.eigenvectors().col(1);
    Q.col(2)       = eig.eigenvectors().col(0);
  }

  /// Linear isotropic elasticity: stress_old + C : de.
  inline StressUpdate update_elastic(const Tensor3 &stress_old, const Tensor3 &strain_increment,
                                     const MaterialState &old_state, const ModelConstants &prm)
  {
    return {elastic_trial(stress_old, strain_increment, prm), old_state};
  }

  /// The kind of a plastic return that ended at sorted principal stresses s (tension +) of a
  /// particle of strength factor `strength`: tensile where s lies on the tension cut-off `st`
  /// (> 0; <= 0: none) or where the failure plane carries a tensile normal stress - the point
  /// where Mohr's circle touches the envelope of friction angle phi, sigma_n = (s0 + s2) / 2 +
  /// (s0 - s2) / 2 sin(phi) > 0 (so the apex too); crushed where the mean compression
  /// -(s0 + s1 + s2) / 3 reaches the particle's own uniaxial compressive strength
  /// strength * crush_pressure (a UCS peak has a third of it, a confined or contact-loaded point
  /// more); shear otherwise. Uniaxial tension gives tensile, uniaxial compression shear, the BTS
  /// disc centre (s0 = T, s2 = -3 T) tensile for sin(phi) > 1/2 (phi > 30 deg).
  inline FailureMode classify_failure(const Principal &s, const double st, const double sin_phi,
                                      const double strength, const ModelConstants &p)
  {
    if (st > 0 && s[0] >= st * (1.0 - 1e-9))
      return FailureMode::tensile;
    if (0.5 * (s[0] + s[2]) + 0.5 * (s[0] - s[2]) * sin_phi > 0)
      return FailureMode::tensile;
    return -s.sum() / 3.0 >= strength * p.crush_pressure ? FailureMode::crushed :
                                                          FailureMode::shear;
  }

  /// MaterialState::cracked after a return from `old` to `now`: once softened in tension, always.
  inline bool cracked_after(const MaterialState &old, const MaterialState &now)
  {
    return old.cracked || (now.failure_mode == FailureMode::tensile && now.damage > 0);
  }

  /// Crack band softening (SofteningLaw::fracture_energy): the damage after a plastic increment
  /// that dissipated `dissipation` [J/m^3] (sigma : d eps_p) in a return of kind `mode`, from
  /// damage `damage_old`.
  ///
  /// Derivation. The strength factor 1 - (1 - r) d (r: residual fraction) scales c and sigma_t.
  /// In uniaxial tension on the cut-off the plastic strain is the crack strain eps_cr along the
  /// load (one active principal direction), and the softening variable of the strain law, the
  /// equivalent plastic strain kappa = sqrt(2/3 eps_p : eps_p), is sqrt(2/3) eps_cr. Linear
  /// softening sigma = f_t (1 - eps_cr / eps_0) over a band of width h dissipates
  /// G_f = h f_t eps_0 / 2 per unit crack area, so eps_0 = 2 G_f / (f_t h) - which is also the
  /// total strain at zero stress of the stress-strain triangle, the elastic strain being zero
  /// there; the elastic strain f_t / E at the peak only limits h (max_crack_band_width). With a
  /// residual the strength follows the same line to r f_t and stops: the strain law's
  /// softening strain equivalent to G_f is kappa_f = (1 - r) sqrt(2/3) 2 G_f / (f_t h).
  /// That equivalence holds for this one stress path only: on the Mohr-Coulomb surface with
  /// psi < phi the dissipation per unit kappa, sigma : eps_p / kappa, depends on the mean
  /// stress (psi = 0: sqrt(3)/2 (s0 - s2), four times larger at the BTS disc centre than in
  /// uniaxial tension at the same s0), so a fixed kappa_f would dissipate a path-dependent
  /// energy. Instead the damage follows the dissipated energy w per unit band volume, in units
  /// of g = G / h (G_I for tensile returns, G_II for shear and crushing): the linear-softening
  /// rule dd = dw / (2 (1 - r) g (1 - (1 - r) d)) - which is the kappa_f above on the
  /// uniaxial path, where dw = f_t (1 - (1 - r) d) sqrt(3/2) dkappa - integrates to
  /// w / g = 1 - (1 - (1 - r) d)^2 on every path. So
  ///   d = (1 - sqrt(1 - w / g)) / (1 - r),  d = 1 once w / g >= 1 - r^2,
  /// and a particle that softens to zero strength (r = 0) has dissipated exactly G h^2 per unit
  /// band volume h^3 whatever its stress path, spacing or Lode angle. The state needs no new
  /// variable: w / g follows from d.
  inline double crack_band_damage(const double damage_old, const double dissipation,
                                  const FailureMode mode, const ModelConstants &p)
  {
    const double a     = 1.0 - p.residual_fraction;
    const double left  = 1.0 - a * damage_old;
    const double scale = mode == FailureMode::tensile ? p.band_over_g_tensile : p.band_over_g_shear;
    const double rest  = left * left - std::max(dissipation, 0.0) * scale; // 1 - w / g
    if (!(rest > 0))
      return 1.0;
    return std::min(std::max((1.0 - std::sqrt(rest)) / a, damage_old), 1.0);
  }

  /// Implementation of the plastic models: `surface(s, strength, damage)` returns s onto the
  /// yield surface of a particle with scatter factor `strength` (old_state.strength) at damage
  /// `damage` (softened strength, and friction angle where it softens) and says whether it was
  /// plastic. The softening is implicit: the strength is that of the updated plastic strain, by
  /// fixed-point iteration. `surely_elastic(trial, strength, damage)` is a cheaper sufficient
  /// test for an admissible trial stress (no principal stresses needed); when it holds the step
  /// is elastic, as `surface` would find.
  template <typename Surface, typename SurelyElastic, typename Classify>
  inline StressUpdate plastic_update(const Tensor3 &stress_old, const Tensor3 &de,
                                     const MaterialState &old_state, const ModelConstants &prm,
                                     const Surface &surface, const SurelyElastic &surely_elastic,
                                     const Classify &classify)
  {
    const Tensor3 trial = elastic_trial(stress_old, de, prm);
    Principal     s_trial;
    Tensor3       Q;
    {
      if (surely_elastic(trial, old_state.strength, old_state.damage))
        return {trial, old_state};
      // cheap admissibility check next
      Eigen::SelfAdjointEigenSolver<Tensor3> eig;
      eig.computeDirect(trial, Eigen::EigenvaluesOnly);
      const Principal s(eig.eigenvalues()[2], eig.eigenvalues()[1], eig.eigenvalues()[0]);
      Principal    r      = s;
      const double scale  = 1e-9 * (s.cwiseAbs().maxCoeff() + prm.cohesion + prm.hb_sigma_ci);
      if (!surface(r, old_state.strength, old_state.damage) ||
          (r - s).cwiseAbs().maxCoeff() < scale)
        return {trial, old_state};
    }
    principal_decomposition(trial, s_trial, Q);
    const auto close = [](const double a, const double b) {
      return std::abs(a - b) <= 1e-13 * std::abs(a) + 1e-300;
    };
    if (prm.band_over_g_tensile > 0)
      {
        // crack band: the damage at the end of the step solves d = crack_band_damage(the
        // dissipation of the return at d); the return weakens as d grows, so the fixed point
        // rises monotonically from the old damage (regula falsi where it creeps)
        Principal   s;
        FailureMode mode     = FailureMode::none;
        double      kappa_dk = 0;
        const auto  damage_after = [&](const double d) {
          s = s_trial;
          surface(s, old_state.strength, d);
          const Principal ep = principal_compliance_times(s_trial - s, prm);
          kappa_dk           = std::sqrt(2.0 / 3.0 * ep.squaredNorm());
          mode               = classify(s, old_state.strength, d);
          return crack_band_damage(old_state.damage, s.dot(ep), mode, prm);
        };
        double d         = old_state.damage;
        bool   converged = false;
        for (int it = 0; it < 50 && !converged; ++it)
          {
            const double dn = damage_after(d);
            converged       = close(dn, d);
            d               = dn;
          }
        if (!converged)
          {
            double a = d, fa = damage_after(a) - a, b = 1.0, fb = damage_after(b) - b;
            int    side = 0;
            for (int it = 0; it < 100 && fa > 0 && fb < 0 && !close(a, b); ++it)
              {
                const double c  = (a * fb - b * fa) / (fb - fa);
                const double fc = damage_after(c) - c;
                if (fc > 0)
                  {
                    a = c, fa = fc;
                    if (side == 1)
                      fb *= 0.5;
                    side = 1;
                  }
                else
                  {
                    b = c, fb = fc;
                    if (side == -1)
                      fa *= 0.5;
                    side = -1;
                  }
                if (fc == 0)
                  a = b = c;
              }
            d = fb >= 0 ? b : (fa <= 0 ? a : 0.5 * (a + b));
            damage_after(d);
          }
        StressUpdate out;
        out.state                = old_state;
        out.stress               = Q * s.asDiagonal() * Q.transpose();
        out.state.plastic_strain = old_state.plastic_strain + kappa_dk;
        out.state.damage         = std::max(old_state.damage, d);
        if (old_state.damage < 1.0)
          out.state.failure_mode = mode;
        out.state.cracked = cracked_after(old_state, out.state);
        return out;
      }
    // the equivalent plastic strain of the return at the damage of a plastic strain increment
    // dk (s: the returned stress); the increment solves plastic_strain_of(dk) = dk
    const auto plastic_strain_of = [&](const double dk, Principal &s) {
      const double damage =
        std::max(old_state.damage, damage_of(old_state.plastic_strain + dk, prm));
      s = s_trial;
      surface(s, old_state.strength, damage);
      const Principal ep = principal_compliance_times(s_trial - s, prm);
      return std::sqrt(2.0 / 3.0 * ep.squaredNorm());
    };
    // g(x) = k(x) - x, k(x) = plastic_strain_of(x): k grows with x (the weaker the surface, the
    // larger the return), so a fixed-point step x -> k(x) never crosses the root. Secant steps
    // through the last two points where they stay inside the bracket of the root known so far
    // (lo: g >= 0, hi: g < 0), fixed-point steps otherwise: with linear softening k is linear
    // in x on one face of the surface, and the secant lands on the root at once.
    Principal s;
    double    dkappa    = plastic_strain_of(0.0, s);
    bool      converged = prm.softening_strain <= 0 || close(dkappa, 0.0);
    {
      double x_prev = 0, g_prev = dkappa, x = dkappa;
      double lo = 0, hi = std::numeric_limits<double>::infinity();
      for (int it = 0; it < 50 && !converged; ++it)
        {
          const double k  = plastic_strain_of(x, s);
          const double gx = k - x;
          converged       = close(k, x);
          dkappa          = k;
          if (converged)
            break;
          if (gx >= 0)
            lo = std::max(lo, x);
          else
            hi = std::min(hi, x);
          double       next  = k;
          const double slope = (gx - g_prev) / (x - x_prev);
          if (slope < 0 && std::isfinite(slope))
            {
              const double xs = x - gx / slope;
              if (xs > lo && xs < hi)
                next = xs;
            }
          x_prev = x, g_prev = gx, x = next;
        }
    }
    if (!converged)
      {
        // The fixed point creeps up on the root from below (the weaker the surface, the larger
        // the return) and can be slow where the strength falls steeply, as with a softening
        // friction angle: regula falsi (Illinois) between that lower bound, g = k(dk) - dk >= 0,
        // and the return at full damage, g <= 0.
        Principal    t;
        const auto   g  = [&](const double dk) { return plastic_strain_of(dk, t) - dk; };
        double       a  = dkappa, fa = g(a);
        double       b  = plastic_strain_of(prm.softening_strain + 1.0, t), fb = g(b);
        if (fa >= 0 && fb <= 0 && b > a)
          {
            int side = 0;
            for (int it = 0; it < 100 && !close(a, b); ++it)
              {
                const double c  = fa - fb > 0 ? (a * fb - b * fa) / (fb - fa) : 0.5 * (a + b);
                const double fc = g(c);
                if (fc > 0)
                  {
                    a = c, fa = fc;
                    if (side == 1)
                      fb *= 0.5;
                    side = 1;
                  }
                else
                  {
                    b = c, fb = fc;
                    if (side == -1)
                      fa *= 0.5;
                    side = -1;
                  }
                if (std::abs(fc) <= 1e-13 * c)
                  {
                    a = b = c;
                    break;
                  }
              }
            dkappa = plastic_strain_of(0.5 * (a + b), s);
          }
      }
    StressUpdate out;
    out.state                 = old_state;
    out.stress                = Q * s.asDiagonal() * Q.transpose();
    out.state.plastic_strain  = old_state.plastic_strain + dkappa;
    out.state.damage = std::max(old_state.damage, damage_of(out.state.plastic_strain, prm));
    if (old_state.damage < 1.0)
      out.state.failure_mode = classify(s, old_state.strength, out.state.damage);
    out.state.cracked = cracked_after(old_state, out.state);
    return out;
  }

  /// The mean stress m = tr(t) / 3 and q = sqrt(J2) of a stress, the invariants the surely-elastic
  /// bounds use: the largest principal stress is at most m + 2 q / sqrt(3), the spread s0 - s2 at
  /// most 2 q (the Lode angle within +-30 deg).
  struct MeanAndShear
  {
    double m, q;
  };
  inline MeanAndShear mean_and_shear(const Tensor3 &t)
  {
    const double m  = t.trace() / 3.0;
    double       dd = 0; // dev : dev = 2 J2
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        {
          const double d = t(r, c) - (r == c ? m : 0.0);
          dd += d * d;
        }
    return {m, std::sqrt(0.5 * dd)};
  }

  /// A sufficient test that the trial stress t lies inside the (softened) Mohr-Coulomb surface
  /// and below the tension cut-off of a particle of strength factor `strength` at `damage`.
  /// Bounds from the invariants alone: with the mean stress m, q = sqrt(J2) and the deviatoric
  /// principal stresses d0 >= d1 >= d2, the Lode angle within +-30 deg gives d0 - d2 <= 2 q,
  /// |d1| <= q / sqrt(3) and d0 <= 2 q / sqrt(3), so
  ///   f = 2 m sin(phi) + (d0 - d2) - sin(phi) d1 - 2 c cos(phi)
  ///     <= 2 m sin(phi) + q (2 + |sin(phi)| / sqrt(3)) - 2 c cos(phi),   s0 <= m + 2 q / sqrt(3).
  /// Both below the surfaces by a margin far above round-off: the trial is admissible.
  inline bool mohr_coulomb_surely_elastic(const Tensor3 &t, const double strength,
                                          const double damage, const ModelConstants &prm)
  {
    const double   factor  = strength * strength_factor(damage, prm);
    const Friction fr      = friction_at(damage, prm);
    const auto [m, q]      = mean_and_shear(t);
    const double c      = prm.cohesion * factor;
    const double margin = 1e-9 * (std::abs(m) + q + c);
    const double f_max  = 2.0 * m * fr.sin_phi +
                         q * (2.0 + std::abs(fr.sin_phi) / std::sqrt(3.0)) -
                         2.0 * c * fr.cos_phi;
    if (!(f_max < -margin))
      return false;
    return prm.tensile_strength <= 0 ||
           m + 2.0 / std::sqrt(3.0) * q < prm.tensile_strength * factor - margin;
  }

  /// Mohr-Coulomb as LS-DYNA's *MAT_MOHR_COULOMB (non-associated, dilation psi), with the
  /// Rankine tension cut-off when prm.tensile_strength > 0. Cohesion and tensile strength soften
  /// linearly with the equivalent plastic strain to residual_fraction at softening_strain.
  inline StressUpdate update_mohr_coulomb(const Tensor3 &stress_old, const Tensor3 &strain_increment,
                                          const MaterialState &old_state,
                                          const ModelConstants &prm)
  {
    const auto surface = [&prm](Principal &s, const double strength, const double damage) {
      const double   factor = strength * strength_factor(damage, prm);
      const double   c      = prm.cohesion * factor;
      const Friction fr     = friction_at(damage, prm);
      bool           pl     = false;
      if (prm.tensile_strength <= 0)
        return return_mohr_coulomb(s, c, fr.sin_phi, fr.cos_phi, prm.sin_psi, prm);
      const double st = prm.tensile_strength * factor;
      // alternate the two returns until both hold (converges in a few sweeps)
      for (int sweep = 0; sweep < 30; ++sweep)
        {
          const bool a = return_mohr_coulomb(s, c, fr.sin_phi, fr.cos_phi, prm.sin_psi, prm);
          const bool b = return_rankine(s, st, prm);
          pl           = pl || a || b;
          if (!b)
            break;
        }
      return pl;
    };
    const auto surely_elastic = [&prm](const Tensor3 &t, const double strength,
                                       const double damage) {
      return mohr_coulomb_surely_elastic(t, strength, damage, prm);
    };
    const auto classify = [&prm](const Principal &s, const double strength, const double damage) {
      const double st = prm.tensile_strength * strength * strength_factor(damage, prm);
      return classify_failure(s, st, friction_at(damage, prm).sin_phi, strength, prm);
    };
    return plastic_update(stress_old, strain_increment, old_state, prm, surface, surely_elastic,
                          classify);
  }

  /// base^a of the Hoek-Brown envelope; a square root where a = 1/2 (intact rock's usual a).
  inline double hoek_brown_power(const double base, const double a)
  {
    return a == 0.5 ? std::sqrt(base) : std::pow(base, a);
  }

  /// The tension cut-off of a Hoek-Brown rock at strength factor `factor`: the case's cut-off or
  /// the envelope's tensile apex s sigma_ci / m_b, whichever is lower, both scaled [Pa].
  inline double hoek_brown_cutoff(const ModelConstants &prm, const double factor)
  {
    return std::min(prm.tensile_strength * factor, prm.hb_s * factor * prm.hb_sigma_ci / prm.hb_mb);
  }

  /// A sufficient test that the trial stress t lies inside the (softened) Hoek-Brown envelope and
  /// below its tension cut-off, from the invariants alone (as mohr_coulomb_surely_elastic): with
  /// the mean stress m and q = sqrt(J2), s0 <= s0max = m + 2 q / sqrt(3) and s0 - s2 <= 2 q, and
  /// the envelope's strength sci (-mb s0 / sci + ss)^a falls as s0 grows, so
  ///   f <= 2 q - sci (-mb s0max / sci + ss)^a.
  /// Both that and s0max - cut-off below zero by a margin far above round-off: admissible.
  inline bool hoek_brown_surely_elastic(const Tensor3 &t, const double strength, const double damage,
                                        const ModelConstants &prm)
  {
    const double factor = strength * strength_factor(damage, prm);
    const double sci = prm.hb_sigma_ci, mb = prm.hb_mb;
    const double ss  = prm.hb_s * factor;
    const double st  = hoek_brown_cutoff(prm, factor);
    const auto [m, q]   = mean_and_shear(t);
    const double s0max  = m + 2.0 / std::sqrt(3.0) * q;
    const double margin = 1e-9 * (std::abs(m) + q + sci);
    if (!(s0max < st - margin))
      return false;
    const double base = -mb * s0max / sci + ss;
    return base > 0 && 2.0 * q < sci * hoek_brown_power(base, prm.hb_a) - margin;
  }

  /// The return of sorted principal stresses s onto the Hoek-Brown envelope
  /// F(x, z) = (x - z) - sci (-mb x / sci + ss)^a <= 0 for every pair x >= z of them, by Newton's
  /// method on the plastic multipliers, flow along D b with b = (1 + sin psi, 0, -(1 - sin psi))
  /// on each active face (dilation psi). First the main face F(s0, s2) = 0: f(l) is convex and
  /// decreasing in l (the deviator falls linearly, the strength grows as a concave power of a
  /// linearly growing base), so Newton from l = 0 climbs monotonically to the root. Where that
  /// breaks the order s0 >= s1 >= s2, the edge it crossed: s0 = s1 (F(s0, s2) = F(s1, s2) = 0)
  /// or s1 = s2 (F(s0, s2) = F(s0, s1) = 0), two multipliers, both >= 0. Returns false where this
  /// return does not apply (the trial beyond the tensile apex, an edge's Newton not converging or
  /// with a negative multiplier, the apex reached); s is then unchanged and the caller takes the
  /// general return.
  inline bool return_hoek_brown_newton(Principal &s, const double sci, const double mb,
                                       const double a, const double ss, const ModelConstants &p)
  {
    const double tol = 1e-13 * sci;
    // strength sci base^a of a principal stress x and its slope N = dF/dx (base > 0)
    const auto strength = [&](const double x, double &N) {
      const double base = -mb * x / sci + ss;
      if (!(base > 0))
        return std::numeric_limits<double>::quiet_NaN();
      const double pw = hoek_brown_power(base, a);
      N               = 1.0 + a * mb * pw / base;
      return sci * pw;
    };
    const Principal bA(1.0 + p.sin_psi, 0.0, -(1.0 - p.sin_psi));
    const Principal DbA = principal_stiffness_times(bA, p);
    double          N0  = 0;
    if (!(-mb * s[0] / sci + ss > 0))
      return false;
    // the multipliers at which the main face's return would cross an edge (s0 = s1, s1 = s2):
    // the iterates grow monotonically to the root, so one beyond an edge proves the edge active
    const double dU = DbA[0] - DbA[1], dL = DbA[1] - DbA[2];
    const double lU = dU > 0 ? (s[0] - s[1]) / dU : std::numeric_limits<double>::infinity();
    const double lL = dL > 0 ? (s[1] - s[2]) / dL : std::numeric_limits<double>::infinity();
    double       l  = 0;
    Principal    r  = s;
    bool         edge = false;
    for (int it = 0; it < 40; ++it)
      {
        r                 = s - l * DbA;
        const double k    = strength(r[0], N0);
        const double f    = (r[0] - r[2]) - k;
        const double df   = -(N0 * DbA[0] - DbA[2]);
        const double step = -f / df;
        if (!std::isfinite(step))
          return false;
        l += step;
        if (l > lU || l > lL)
          {
            edge = true;
            break;
          }
        if (std::abs(step) * (std::abs(DbA[0]) + std::abs(DbA[2])) <= tol)
          break;
      }
    r = s - l * DbA;
    if (!(l >= 0))
      return false;
    if (!edge && r[0] >= r[1] && r[1] >= r[2])
      {
        s = r;
        return true;
      }
    // an edge: the second face, its flow direction and the gradients' pattern
    const bool      upper = edge ? lU <= lL : r[1] > r[0];
    const Principal bB    = upper ? Principal(0.0, 1.0 + p.sin_psi, -(1.0 - p.sin_psi))
                                  : Principal(1.0 + p.sin_psi, -(1.0 - p.sin_psi), 0.0);
    const Principal DbB   = principal_stiffness_times(bB, p);
    double          lA = 0, lB = 0;
    bool            converged = false;
    for (int it = 0; it < 40 && !converged; ++it)
      {
        r = s - lA * DbA - lB * DbB;
        double       Na = 0, Nb = 0;
        const double ka = strength(r[0], Na);
        const double kb = strength(upper ? r[1] : r[0], Nb);
        const double fa = (r[0] - r[2]) - ka;
        const double fb = upper ? (r[1] - r[2]) - kb : (r[0] - r[1]) - kb;
        const Principal ga(Na, 0.0, -1.0);
        const Principal gb = upper ? Principal(0.0, Nb, -1.0) : Principal(Nb, -1.0, 0.0);
        const double    j11 = ga.dot(DbA), j12 = ga.dot(DbB), j21 = gb.dot(DbA), j22 = gb.dot(DbB);
        const double    det = j11 * j22 - j12 * j21;
        const double    dA  = (fa * j22 - j12 * fb) / det;
        const double    dB  = (j11 * fb - j21 * fa) / det;
        if (!std::isfinite(dA) || !std::isfinite(dB))
          return false;
        lA += dA;
        lB += dB;
        converged = (std::abs(dA) + std::abs(dB)) * DbA.cwiseAbs().maxCoeff() <= tol;
      }
    r = s - lA * DbA - lB * DbB;
    if (!converged || !(lA >= 0 && lB >= 0))
      return false;
    if (upper)
      {
        if (!(r[1] >= r[2]))
          return false;
        r[1] = r[0]; // equal at the solution; remove round-off
      }
    else
      {
        if (!(r[0] >= r[1]))
          return false;
        r[2] = r[1];
      }
    s = r;
    return true;
  }

  /// The return of sorted principal stresses s onto the Hoek-Brown envelope (as
  /// return_hoek_brown_newton) by successive tangent Mohr-Coulomb planes: the plane tangent to the
  /// envelope at the last return's s0, the Mohr-Coulomb return of the trial onto it, until two
  /// returns agree to 1e-13 sci. Linear convergence, but it takes every case: faces, edges and
  /// trials beyond the tensile apex (the tangent at the apex).
  inline void return_hoek_brown_tangent_planes(Principal &s, const double sci, const double mb,
                                               const double a, const double ss,
                                               const ModelConstants &p)
  {
    const Principal s_trial = s;
    for (int it = 0; it < 60; ++it)
      {
        // tangent plane of the envelope p1 = p3 + sci (mb p3/sci + s)^a at p3 = -s[0]
        const double p3   = std::max(-s[0], -ss * sci / mb * (1.0 - 1e-9));
        const double base = mb * p3 / sci + ss;
        const double pw   = hoek_brown_power(base, a);
        const double N    = 1.0 + a * mb * pw / base;
        const double q0   = p3 + sci * pw - N * p3;
        const double sphi = (N - 1.0) / (N + 1.0), cphi = std::sqrt(1.0 - sphi * sphi);
        const double c    = q0 * (1.0 - sphi) / (2.0 * cphi);
        Principal    t    = s_trial;
        return_mohr_coulomb(t, c, sphi, cphi, p.sin_psi, p);
        const bool done = (t - s).cwiseAbs().maxCoeff() <= 1e-13 * sci;
        s               = t;
        if (done)
          break;
      }
  }

  /// Hoek-Brown f = (s0 - s2) - sigma_ci (-m_b s0 / sigma_ci + s)^a (tension +), dilation psi as
  /// the potential, tension cut-off at s sigma_ci / m_b. On the envelope's faces and edges the
  /// return is Newton's (return_hoek_brown_newton); where that does not apply (beyond the tensile
  /// apex) by successive tangent Mohr-Coulomb planes (converged to 1e-13 sigma_ci). Softening
  /// scales s (and the cut-off) by the strength factor.
  inline StressUpdate update_hoek_brown(const Tensor3 &stress_old, const Tensor3 &strain_increment,
                                        const MaterialState &old_state, const ModelConstants &prm)
  {
    const auto surface = [&prm](Principal &s, const double strength, const double damage) {
      const double factor = strength * strength_factor(damage, prm);
      const double sci = prm.hb_sigma_ci, mb = prm.hb_mb, a = prm.hb_a;
      const double ss  = prm.hb_s * factor;
      const double st  = hoek_brown_cutoff(prm, factor);
      const auto   f   = [&](const Principal &t) {
        const double base = std::max(-mb * t[0] / sci + ss, 0.0);
        return (t[0] - t[2]) - sci * hoek_brown_power(base, a);
      };
      bool pl = false;
      if (f(s) > 1e-12 * sci)
        {
          pl = true;
          if (!return_hoek_brown_newton(s, sci, mb, a, ss, prm))
            return_hoek_brown_tangent_planes(s, sci, mb, a, ss, prm);
        }
      pl = return_rankine(s, st, prm) || pl;
      return pl;
    };
    const auto surely_elastic = [&prm](const Tensor3 &t, const double strength,
                                       const double damage) {
      return hoek_brown_surely_elastic(t, strength, damage, prm);
    };
    // the friction angle of the envelope's tangent at s0: sin = (N - 1) / (N + 1), N the slope
    // d sigma_1 / d sigma_3 (compression +); beyond the tensile apex, tensile
    const auto classify = [&prm](const Principal &s, const double strength, const double damage) {
      const double factor = strength * strength_factor(damage, prm);
      const double ss     = prm.hb_s * factor;
      const double st = hoek_brown_cutoff(prm, factor);
      const double base = -prm.hb_mb * s[0] / prm.hb_sigma_ci + ss;
      if (!(base > 0))
        return FailureMode::tensile;
      const double N = 1.0 + prm.hb_a * prm.hb_mb * std::pow(base, prm.hb_a - 1.0);
      return classify_failure(s, st, (N - 1.0) / (N + 1.0), strength, prm);
    };
    return plastic_update(stress_old, strain_increment, old_state, prm, surface, surely_elastic,
                          classify);
  }

  /// Run-time model choice: dispatched once per particle loop with std::visit.
  struct Elastic
  {
    StressUpdate operator()(const Tensor3 &s, const Tensor3 &de, const MaterialState &h,
                            const ModelConstants &p) const
    {
      return update_elastic(s, de, h, p);
    }
    /// True where the elastic trial t (elastic_trial of the same s and de) is the update.
    bool surely_elastic(const Tensor3 &, const MaterialState &, const ModelConstants &) const
    {
      return true;
    }
  };
  struct MohrCoulomb
  {
    StressUpdate operator()(const Tensor3 &s, const Tensor3 &de, const MaterialState &h,
                            const ModelConstants &p) const
    {
      return update_mohr_coulomb(s, de, h, p);
    }
    bool surely_elastic(const Tensor3 &t, const MaterialState &h, const ModelConstants &p) const
    {
      return mohr_coulomb_surely_elastic(t, h.strength, h.damage, p);
    }
  };
  struct HoekBrown
  {
    StressUpdate operator()(const Tensor3 &s, const Tensor3 &de, const MaterialState &h,
                            const ModelConstants &p) const
    {
      return update_hoek_brown(s, de, h, p);
    }
    bool surely_elastic(const Tensor3 &t, const MaterialState &h, const ModelConstants &p) const
    {
      return hoek_brown_surely_elastic(t, h.strength, h.damage, p);
    }
  };
  using Model = std::variant<Elastic, MohrCoulomb, HoekBrown>;

  /// The functor of a RockModel.
  inline Model make_model(const RockModel m)
  {
    switch (m)
      {
        case RockModel::elastic:
          return Elastic{};
        case RockModel::hoek_brown:
          return HoekBrown{};
        default:
          return MohrCoulomb{};
      }
  }

  /// Elastic strain energy density 1/2 sigma : C^{-1} : sigma [J/m^3].
  inline double elastic_energy_density(const Tensor3 &s, const ModelConstants &p)
  {
    const double  mean = s.trace() / 3.0;
    const Tensor3 dev  = s - mean * Tensor3::Identity();
    return 0.5 * (dev.squaredNorm() / (2.0 * p.G) + mean * mean / p.K);
  }

  // ---- Extensions for `cosim diagnose` (pure functions; stresses compression-positive here,
  // ---- as the closure and strength laws are written in the rock-mechanics literature). The
  // ---- surrogate calls crack_closure_strain, weakest_link_strength_factor and
  // ---- rate_strength_factor; the SPH rock's closure elasticity (crack_closure.h) and the CTCS
  // ---- confinement ramp call crack_closure_tangent_modulus; diagnose_unit_tests checks the
  // ---- closed forms against the pointwise laws (integral, Monte Carlo).

  /// Crack-closure (toe) elasticity: tangent Young's modulus at compressive stress p normal to the
  /// cracks [Pa], 1/E_t = 1/E + (1/E0 - 1/E) exp(-p / sigma_cc): E0 (<= E) at zero stress, the
  /// intact E once the cracks have closed (p >> sigma_cc, the closure stress).
  inline double crack_closure_tangent_modulus(const double p, const double E, const double E0,
                                              const double sigma_cc)
  {
    return 1.0 / (1.0 / E + (1.0 / E0 - 1.0 / E) * std::exp(-std::max(p, 0.0) / sigma_cc));
  }

  /// Strain accumulated along the loading axis while the compressive stress rises from p_from to
  /// p_to (>= 0) under crack_closure_tangent_modulus: the closed-form integral of 1/E_t [-].
  inline double crack_closure_strain(const double p_from, const double p_to, const double E,
                                     const double E0, const double sigma_cc)
  {
    const double a = std::max(p_from, 0.0), b = std::max(p_to, 0.0);
    return (p_to - p_from) / E +
           (1.0 / E0 - 1.0 / E) * sigma_cc * (std::exp(-a / sigma_cc) - std::exp(-b / sigma_cc));
  }

  /// Per-particle strength scatter: the Weibull strength factor (mean 1, modulus m) of the
  /// particle whose uniform random number is u in [0, 1) [-].
  inline double weibull_strength_factor(const double u, const double m)
  {
    return std::pow(-std::log(1.0 - u), 1.0 / m) / std::tgamma(1.0 + 1.0 / m);
  }

  /// Weakest link of Weibull-scattered particles: mean strength of a specimen of volume ratio
  /// V / V_ref relative to the reference specimen's, (V / V_ref)^(-1/m) [-].
  inline double weakest_link_strength_factor(const double volume_ratio, const double m)
  {
    return std::pow(volume_ratio, -1.0 / m);
  }

  /// Coefficient of variation of a Weibull strength of modulus m [-].
  inline double weibull_coefficient_of_variation(const double m)
  {
    const double g1 = std::tgamma(1.0 + 1.0 / m), g2 = std::tgamma(1.0 + 2.0 / m);
    return std::sqrt(g2 / (g1 * g1) - 1.0);
  }

  /// Rate-dependent strength: factor 1 + A log10(rate / reference_rate) on the quasi-static
  /// strength (A: strength gain per decade of strain rate), floored at 0.1 [-].
  inline double rate_strength_factor(const double rate, const double reference_rate,
                                     const double A)
  {
    return std::max(1.0 + A * std::log10(std::max(rate, 1e-300) / reference_rate), 0.1);
  }
} // namespace sph::rock
