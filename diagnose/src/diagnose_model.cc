// The material-point surrogate of `cosim diagnose` and its TAO fit (see diagnose_model.h).
//
// Strength (compression +, MPa): the baseline envelope is linear Mohr-Coulomb through the group's
// UCS with slope k = (1 + sin phi)/(1 - sin phi) (Eq. 14 of the reference study); its tensile
// strength is the uniaxial-tension point UCS / k (Eq. 15), the convention of the data format (a BTS
// row is sigma1 = 0, sigma3 = -BTS). The extensions act as written beside each below; the laws of
// closure, scatter and rate are the pure functions in sph/rock_models.h.
//
// Curves: the specimen axis is driven by the deviatoric stress q = F / A on top of the confinement
// (a material point: uniform stress, as in a frictionless specimen); the platen displacement is
// L eps(q) plus, with a machine, F / k_machine (a series spring).
#include "diagnose_model.h"

#include <coupling/run_case.h>
#include <sph/rock_models.h>

#include <Eigen/Dense>
#include <petsctao.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace diagnose
{
  namespace
  {
    constexpr double pi             = 3.14159265358979323846;
    constexpr double reference_rate = 1e-5; ///< quasi-static strain rate of strength rows [1/s]
    constexpr double deg            = pi / 180.0;
    bool has(const EffectSet &e, const char *n)
    {
      return e.count(n) > 0;
    }
  } // namespace

  double closure_axial_strain(const double q, const double s3, const double E, const double r,
                              const double sigma_cc)
  {
    if (r >= 1.0)
      return q / E;
    return sph::rock::crack_closure_strain(s3, s3 + q, E, r * E, sigma_cc);
  }

  Surrogate::Surrogate(const std::vector<GroupBase> &groups, const EffectSet &effects,
                       const bool refit)
      : groups_(groups)
      , effects_(effects)
      , refit_(refit)
  {
    const bool curved = has(effects, "envelope_curvature");
    if (refit)
    {
      for (const auto &g : groups)
        parameters_.push_back({"UCS_" + g.group, "MPa", 0.3 * g.ucs, 3.0 * g.ucs, g.ucs, true, 0});
      if (!curved)
      {
        double phi = 0;
        for (const auto &g : groups)
          phi += g.phi / groups.size();
        parameters_.push_back({"phi", "deg", 5.0, 85.0, phi, false, 0});
      }
    }
    // the effects, in the fixed order of effect_names()
    if (has(effects, "tension_cutoff")) // Rankine cut-off T0 = ratio * UCS (MC + cut-off)
      parameters_.push_back({"T0_ratio", "-", 0.003, 0.5, 0.04, true, 0.5});
    if (curved) // Hoek-Brown, s = 1, a = 1/2: sigma1 = s3 + UCS sqrt(m_i s3 / UCS + 1)
      parameters_.push_back({"m_i", "-", 1.0, 100.0, 15.0, true, 0});
    if (has(effects, "crack_closure")) // toe: E0 = ratio E at zero stress, closing over sigma_cc
    {
      parameters_.push_back({"E0_ratio", "-", 0.03, 1.0, 0.4, true, 1.0});
      parameters_.push_back({"sigma_cc", "MPa", 0.5, 400.0, 20.0, true, 0});
    }
    if (has(effects, "machine_compliance")) // series spring of the frame
      parameters_.push_back({"k_machine", "kN/mm", 5.0, 1e5, 300.0, true, 1e5});
    if (has(effects, "end_friction")) // Siebel: mean platen pressure = q (1 + mu D / (3 L))
      parameters_.push_back({"mu", "-", 0.0, 1.0, 0.2, false, 0.0});
    if (has(effects, "heterogeneity")) // Weibull weakest link: q ~ (V / V_ref)^(-1/m)
      parameters_.push_back({"weibull_m", "-", 1.5, 200.0, 10.0, true, 200.0});
    if (has(effects, "loading_rate")) // q ~ 1 + A log10(rate / 1e-5 s^-1)
      parameters_.push_back({"rate_A", "-", 0.0, 0.5, 0.05, false, 0.0});
  }

  std::vector<double> Surrogate::initial() const
  {
    std::vector<double> p;
    for (const auto &q : parameters_)
      p.push_back(q.init);
    return p;
  }

  int Surrogate::group_index(const std::string &g) const
  {
    for (std::size_t i = 0; i < groups_.size(); ++i)
      if (groups_[i].group == g)
        return static_cast<int>(i);
    throw std::logic_error("diagnose: unknown group " + g);
  }

  double Surrogate::value(const std::string &name, const std::vector<double> &p,
                          const double fallback) const
  {
    for (std::size_t i = 0; i < parameters_.size(); ++i)
      if (parameters_[i].name == name)
        return p[i];
    return fallback;
  }

  double Surrogate::envelope(const std::string &group, const double s3,
                             const std::vector<double> &p) const
  {
    const GroupBase &g = groups_[group_index(group)];
    const double ucs   = value("UCS_" + g.group, p, g.ucs);
    if (has(effects_, "envelope_curvature"))
    {
      const double mi = value("m_i", p, 10.0);
      return s3 + ucs * std::sqrt(std::max(mi * s3 / ucs + 1.0, 0.0));
    }
    const double sphi = std::sin(value("phi", p, g.phi) * deg);
    return ucs + (1.0 + sphi) / (1.0 - sphi) * s3;
  }

  double held_end_shortening(const double nu)
  {
    return nu * nu * (0.526 + 0.022 * nu + 0.476 * nu * nu);
  }

  double Surrogate::tensile_strength(const std::string &group, const std::vector<double> &p) const
  {
    const GroupBase &g = groups_[group_index(group)];
    const double ucs   = value("UCS_" + g.group, p, g.ucs);
    double t;
    if (has(effects_, "envelope_curvature"))
    {
      const double mi = value("m_i", p, 10.0);
      t               = ucs * (std::sqrt(mi * mi + 4.0) - mi) / 2.0; // sigma1 = 0 on Hoek-Brown
    }
    else
    {
      const double sphi = std::sin(value("phi", p, g.phi) * deg);
      t                 = ucs * (1.0 - sphi) / (1.0 + sphi); // Eq. 15
    }
    if (has(effects_, "tension_cutoff"))
      t = std::min(t, value("T0_ratio", p, 1.0) * ucs);
    return t;
  }

  double Surrogate::predict(const Datum &d, const std::vector<double> &p) const
  {
    if (d.kind == Datum::strength)
    {
      if (d.test == "BTS")
        return tensile_strength(d.group, p);
      double q = envelope(d.group, d.sigma3, p) - d.sigma3; // deviatoric strength
      if (has(effects_, "end_friction"))
        q *= 1.0 + value("mu", p, 0) / (3.0 * d.slenderness);
      if (has(effects_, "heterogeneity"))
        q *= sph::rock::weakest_link_strength_factor(d.volume_ratio, value("weibull_m", p, 1e9));
      if (has(effects_, "loading_rate") && d.strain_rate > 0)
        q *= sph::rock::rate_strength_factor(d.strain_rate, reference_rate, value("rate_A", p, 0));
      return d.sigma3 + q;
    }
    const GroupBase &g = groups_[group_index(d.group)];
    const double q     = d.force * 1e3 / d.area; // MPa
    double eps         = q / g.E;
    if (has(effects_, "crack_closure"))
      eps =
        closure_axial_strain(q, d.sigma3, g.E, value("E0_ratio", p, 1), value("sigma_cc", p, 1));
    double disp = eps * d.length;
    if (d.platen && has(effects_, "end_friction"))
      disp = eps * (d.length - held_end_shortening(g.nu) * d.length / d.slenderness);
    if (d.platen && has(effects_, "machine_compliance"))
      disp += d.force / value("k_machine", p, 1e300);
    return disp;
  }

  // ------------------------------------------------------------------------------------------
  // TAO fit
  namespace
  {
    struct FitContext
    {
      const Surrogate *model;
      const std::vector<Datum> *data;
      std::vector<double> sd;
      int n_evaluations = 0;
    };

    double to_physical(const Parameter &q, const double x)
    {
      const double t = std::clamp(x, 0.0, 1.0);
      return q.log ? q.lo * std::pow(q.hi / q.lo, t) : q.lo + (q.hi - q.lo) * t;
    }

    double to_internal(const Parameter &q, const double v)
    {
      const double c = std::clamp(v, q.lo, q.hi);
      return q.log ? std::log(c / q.lo) / std::log(q.hi / q.lo) : (c - q.lo) / (q.hi - q.lo);
    }

    std::vector<double> physical(const Surrogate &m, const std::vector<double> &x)
    {
      std::vector<double> p(x.size());
      for (std::size_t i = 0; i < x.size(); ++i)
        p[i] = to_physical(m.parameters()[i], x[i]);
      return p;
    }

    void residuals(const FitContext &c, const std::vector<double> &p, double *r)
    {
      for (std::size_t j = 0; j < c.data->size(); ++j)
      {
        const Datum &d = (*c.data)[j];
        r[j]           = (c.model->predict(d, p) - d.measured) / c.sd[j];
      }
    }

    PetscErrorCode tao_residual(Tao, Vec X, Vec F, void *ctx)
    {
      auto &c = *static_cast<FitContext *>(ctx);
      const PetscScalar *x;
      PetscScalar *f;
      PetscInt n;
      PetscCall(VecGetLocalSize(X, &n));
      PetscCall(VecGetArrayRead(X, &x));
      std::vector<double> xi(x, x + n);
      PetscCall(VecRestoreArrayRead(X, &x));
      PetscCall(VecGetArray(F, &f));
      residuals(c, physical(*c.model, xi), f);
      PetscCall(VecRestoreArray(F, &f));
      ++c.n_evaluations;
      return 0;
    }

    void petsc_check(const PetscErrorCode e, const char *what)
    {
      if (e != 0)
      {
        const char *text = nullptr;
        PetscErrorMessage(e, &text, nullptr);
        throw std::runtime_error(std::string("PETSc/TAO failed in ") + what + " (" +
                                 (text ? text : "unknown error") + ")");
      }
    }

    void ensure_petsc()
    {
      PetscBool up = PETSC_FALSE;
      PetscInitialized(&up);
      if (!up)
      {
        petsc_check(PetscInitializeNoArguments(), "PetscInitialize");
        PetscPushErrorHandler(PetscReturnErrorHandler, nullptr); // errors become exceptions here
        std::atexit([] { PetscFinalize(); });
      }
    }

    /// One POUNDERS run from internal start x0; returns the internal optimum and chi2.
    std::pair<std::vector<double>, double> pounders(FitContext &c, const std::vector<double> &x0)
    {
      const PetscInt n = static_cast<PetscInt>(x0.size());
      const PetscInt m = static_cast<PetscInt>(c.data->size());
      Vec X, F, LB, UB;
      Tao tao;
      petsc_check(VecCreateSeq(PETSC_COMM_SELF, n, &X), "VecCreateSeq");
      petsc_check(VecCreateSeq(PETSC_COMM_SELF, m, &F), "VecCreateSeq");
      petsc_check(VecDuplicate(X, &LB), "VecDuplicate");
      petsc_check(VecDuplicate(X, &UB), "VecDuplicate");
      petsc_check(VecSet(LB, 0.0), "VecSet");
      petsc_check(VecSet(UB, 1.0), "VecSet");
      PetscScalar *x;
      petsc_check(VecGetArray(X, &x), "VecGetArray");
      for (PetscInt i = 0; i < n; ++i)
        x[i] = std::clamp(x0[i], 0.051, 0.949); // POUNDERS needs the start a trust radius inside
      petsc_check(VecRestoreArray(X, &x), "VecRestoreArray");
      petsc_check(TaoCreate(PETSC_COMM_SELF, &tao), "TaoCreate");
      petsc_check(TaoSetType(tao, TAOPOUNDERS), "TaoSetType");
      petsc_check(TaoSetSolution(tao, X), "TaoSetSolution");
      petsc_check(TaoSetResidualRoutine(tao, F, tao_residual, &c), "TaoSetResidualRoutine");
      petsc_check(TaoSetVariableBounds(tao, LB, UB), "TaoSetVariableBounds");
      petsc_check(TaoSetTolerances(tao, 1e-10, 1e-10, 1e-10), "TaoSetTolerances");
      petsc_check(TaoSetMaximumFunctionEvaluations(tao, 300 + 60 * n),
                  "TaoSetMaximumFunctionEvaluations");
      petsc_check(TaoSetMaximumIterations(tao, 400 + 60 * n), "TaoSetMaximumIterations");
      petsc_check(PetscOptionsSetValue(nullptr, "-tao_pounders_delta", "0.05"),
                  "PetscOptionsSetValue");
      petsc_check(TaoSetFromOptions(tao), "TaoSetFromOptions");
      if (const PetscErrorCode solved = TaoSolve(tao); solved != 0)
      {
        TaoDestroy(&tao); // free before the exception leaves: the caller tries the next start
        VecDestroy(&X);
        VecDestroy(&F);
        VecDestroy(&LB);
        VecDestroy(&UB);
        petsc_check(solved, "TaoSolve");
      }
      std::vector<double> xs(n);
      const PetscScalar *xr;
      petsc_check(VecGetArrayRead(X, &xr), "VecGetArrayRead");
      for (PetscInt i = 0; i < n; ++i)
        xs[i] = std::clamp(static_cast<double>(xr[i]), 0.0, 1.0);
      petsc_check(VecRestoreArrayRead(X, &xr), "VecRestoreArrayRead");
      TaoDestroy(&tao);
      VecDestroy(&X);
      VecDestroy(&F);
      VecDestroy(&LB);
      VecDestroy(&UB);
      std::vector<double> r(m);
      residuals(c, physical(*c.model, xs), r.data());
      double chi2 = 0;
      for (double v : r)
        chi2 += v * v;
      return {xs, chi2};
    }
  } // namespace

  FitResult fit(const Surrogate &model, const std::vector<Datum> &data,
                const std::function<double(const Datum &)> &noise,
                const std::vector<std::vector<double>> &starts, const bool polish)
  {
    FitContext c{&model, &data, {}, 0};
    for (const auto &d : data)
      c.sd.push_back(noise(d));
    const auto &prm     = model.parameters();
    const std::size_t n = prm.size();
    FitResult result;
    if (n == 0)
    {
      std::vector<double> r(data.size());
      residuals(c, {}, r.data());
      for (double v : r)
        result.chi2 += v * v;
      return result;
    }
    ensure_petsc();
    double best = std::numeric_limits<double>::infinity();
    std::vector<double> x_best;
    std::string failure;
    for (const auto &s : starts)
    {
      std::vector<double> x0(n);
      for (std::size_t i = 0; i < n; ++i)
        x0[i] = to_internal(prm[i], s[i]);
      // POUNDERS can stop with a LAPACK error when its interpolation set degenerates (seen with
      // 13 parameters from a warm start): that start is dropped, the others are kept
      std::pair<std::vector<double>, double> first;
      try
      {
        first = pounders(c, x0);
      }
      catch (const std::runtime_error &e)
      {
        failure = e.what();
        continue;
      }
      if (first.second < best)
      {
        best   = first.second;
        x_best = first.first;
      }
    }
    // a second pass from the best optimum with a fresh trust region polishes the minimum
    if (polish && !x_best.empty())
    {
      try
      {
        auto [x2, chi22] = pounders(c, x_best);
        if (chi22 < best)
        {
          x_best = x2;
          best   = chi22;
        }
      }
      catch (const std::runtime_error &)
      {}
    }
    if (x_best.empty())
      throw std::runtime_error(failure);
    result.values        = physical(model, x_best);
    result.chi2          = best;
    result.n_evaluations = c.n_evaluations;
    // standard errors: covariance (J^T J)^-1 of the weighted residuals, by central differences in
    // the physical parameters, scaled by the reduced chi2 when that exceeds 1
    const std::size_t m = data.size();
    Eigen::MatrixXd J(m, n);
    for (std::size_t i = 0; i < n; ++i)
    {
      const double h = 1e-5 * std::max(std::abs(result.values[i]), 1e-3 * (prm[i].hi - prm[i].lo));
      std::vector<double> pp = result.values, pm = result.values;
      pp[i] += h;
      pm[i] -= h;
      std::vector<double> rp(m), rm(m);
      residuals(c, pp, rp.data());
      residuals(c, pm, rm.data());
      for (std::size_t j = 0; j < m; ++j)
        J(j, i) = (rp[j] - rm[j]) / (2 * h);
    }
    const Eigen::MatrixXd JtJ = J.transpose() * J;
    const Eigen::MatrixXd cov = JtJ.completeOrthogonalDecomposition().pseudoInverse();
    const double scale        = m > n ? std::max(1.0, best / static_cast<double>(m - n)) : 1.0;
    for (std::size_t i = 0; i < n; ++i)
      result.standard_errors.push_back(std::sqrt(std::max(cov(i, i), 0.0) * scale));
    return result;
  }
} // namespace diagnose
