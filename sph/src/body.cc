#include <sph/body.h>
#include <sph/domain.h>
#include <sph/kernels.h>

#include "chunk_queue.h"
#include "pair_kernel.h"
#include "pair_kernel_mixed.h"
#include "stress_batch.h"
#include "tensor3_kernels.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace sph
{
  namespace
  {
    /// [begin, end) of thread t's static chunk of n items among T threads.
    inline void chunk(const std::size_t n, const int t, const int T, std::size_t &begin,
                      std::size_t &end)
    {
      begin = n * t / T;
      end   = n * (t + 1) / T;
    }

    /// Sum of f(k) for k in [0, n): static chunks per thread, partial sums added in thread order,
    /// so the result is the same in every run with the same number of threads.
    template <typename Function>
    double deterministic_sum(const std::size_t n, const int n_threads, const Function &f)
    {
      std::vector<double> partial(n_threads, 0.0);
#pragma omp parallel num_threads(n_threads)
      {
        const int   t = omp_get_thread_num(), T = omp_get_num_threads();
        std::size_t b, e;
        chunk(n, t, T, b, e);
        double s = 0;
        for (std::size_t k = b; k < e; ++k)
          s += f(k);
        partial[t] = s;
      }
      double s = 0;
      for (const double v : partial)
        s += v;
      return s;
    }

    void require(const bool ok, const std::string &message)
    {
      if (!ok)
        throw std::invalid_argument("sph::Body: " + message);
    }

    /// Hughes-Winget rotation of the spin increment w (tensor3_kernels.h).
    inline Tensor3 hughes_winget(const Tensor3 &w)
    {
      Tensor3 R;
      tensor3::hughes_winget(w.data(), R.data());
      return R;
    }

    /// Cofactor matrix cof(F) = det(F) F^{-T} (3-D: tensor3_kernels.h); det(F) is the dot product
    /// of a row of F with the same row of cof(F).
    template <int dim>
    inline Tensor<dim> cofactor(const Tensor<dim> &F)
    {
      Tensor<dim> C;
      if constexpr (dim == 2)
        C << F(1, 1), -F(1, 0), -F(0, 1), F(0, 0);
      else
        tensor3::cofactor(F.data(), C.data());
      return C;
    }

    /// Sum over the pairs of particle i of V_j (f_j - f_i) (x) grad_i W_ij: the gradient of the
    /// field f at i before the correction L_i (positions in TL give F, velocities in UL grad v).
    template <int dim>
    inline Tensor<dim> pair_gradient(const PairList &pairs, const std::vector<Vector<dim>> &grad_w,
                                     const std::vector<double> &volume,
                                     const std::vector<Vector<dim>> &f, const long i)
    {
      // accumulated in plain scalars (the same products and sums as the Eigen expression
      // A += (s (f_j - f_i)) grad^T, which Eigen keeps in memory): the compiler holds A in registers
      double             a[dim][dim] = {};
      const Vector<dim> &fi          = f[i];
      for (std::int32_t k = pairs.offsets[i]; k < pairs.offsets[i + 1]; ++k)
        {
          const std::int32_t p = pairs.incidence[k];
          const std::int32_t j = pairs.other(p, i);
          const double       s = (pairs.first[p] == i) ? volume[j] : -volume[j];
          const Vector<dim> &fj = f[j];
          const Vector<dim> &g  = grad_w[p];
          double             d[dim];
          for (int r = 0; r < dim; ++r)
            d[r] = s * (fj[r] - fi[r]);
          for (int r = 0; r < dim; ++r)
            for (int c = 0; c < dim; ++c)
              a[r][c] += d[r] * g[c];
        }
      Tensor<dim> A;
      for (int r = 0; r < dim; ++r)
        for (int c = 0; c < dim; ++c)
          A(r, c) = a[r][c];
      return A;
    }
  } // namespace

  template <int dim>
  Body<dim>::Body(const Parameters &parameters, const MaterialParameters &material,
                  const std::vector<Vector<dim>> &positions, const std::vector<double> &volumes)
    : prm_(parameters)
    , material_(material)
  {
    require(prm_.spacing > 0, "Parameters::spacing must be > 0 [m]");
    require(prm_.cslh > 0, "Parameters::cslh must be > 0 (LS-DYNA default 1.2)");
    require(prm_.tssfac > 0 && prm_.tssfac <= 1.0, "Parameters::tssfac must be in (0, 1]");
    require(prm_.chunks >= 0, "Parameters::chunks must be >= 0 (0: automatic)");
    const int f = static_cast<int>(prm_.form);
    require(f == 0 || f == 1 || f == 7 || f == 8, "Parameters::form must be 0, 1, 7 or 8");
    require(prm_.av_alpha >= 0 && prm_.av_beta >= 0, "artificial viscosity must be >= 0");
    require(prm_.hourglass >= 0, "Parameters::hourglass must be >= 0");
    require(material_.density > 0, "MaterialParameters::density must be > 0 [kg/m^3]");
    require(material_.youngs_modulus > 0, "MaterialParameters::youngs_modulus must be > 0 [Pa]");
    require(material_.poissons_ratio > -1 && material_.poissons_ratio < 0.5,
            "MaterialParameters::poissons_ratio must be in (-1, 0.5)");
    require(material_.model == RockModel::elastic || material_.cohesion >= 0,
            "MaterialParameters::cohesion must be >= 0 [Pa]");
    require(material_.model != RockModel::mohr_coulomb_cutoff || material_.tensile_strength > 0,
            "mohr_coulomb_cutoff needs MaterialParameters::tensile_strength > 0 [Pa]");
    require(material_.model != RockModel::hoek_brown ||
              (material_.hb_sigma_ci > 0 && material_.hb_mb > 0 && material_.hb_s > 0 &&
               material_.hb_a > 0 && material_.hb_a < 1),
            "hoek_brown needs hb_sigma_ci > 0, hb_mb > 0, hb_s > 0 and 0 < hb_a < 1");
    require(material_.residual_fraction >= 0 && material_.residual_fraction <= 1,
            "MaterialParameters::residual_fraction must be in [0, 1]");
    require(material_.residual_friction_angle < 0 ||
              (material_.residual_friction_angle > 0 &&
               material_.residual_friction_angle < 0.5 * 3.141592653589793 &&
               material_.residual_friction_angle >= material_.dilation_angle),
            "MaterialParameters::residual_friction_angle must be < 0 (none) or in "
            "[dilation angle, pi/2)");
    require(material_.closure_modulus_ratio > 0 && material_.closure_modulus_ratio <= 1,
            "MaterialParameters::closure_modulus_ratio must be in (0, 1] (1: no crack closure)");
    require(material_.closure_modulus_ratio == 1 || material_.closure_stress > 0,
            "MaterialParameters::closure_stress must be > 0 [Pa] with crack closure");
    if (material_.softening_law == SofteningLaw::fracture_energy &&
        material_.model != RockModel::elastic)
      {
        require(material_.fracture_energy > 0 && material_.shear_fracture_energy_ratio > 0,
                "MaterialParameters::fracture_energy and shear_fracture_energy_ratio must be > 0");
        const double h_max = rock::max_crack_band_width(material_);
        const double band  = rock::crack_band_width(prm_.spacing, prm_.cslh);
        require(band < h_max,
                "the crack band (" + std::to_string(band) + " m at particle spacing " +
                  std::to_string(prm_.spacing) + " m) must be narrower than 2 E G_I / f_t^2 = " +
                  std::to_string(h_max) +
                  " m, or the softening snaps back: raise the fracture energy or refine the spacing");
      }
    require(positions.size() == volumes.size(), "positions and volumes differ in length");
    require(!positions.empty(), "no particles");

    n_threads_ = prm_.n_threads > 0 ? prm_.n_threads : omp_get_max_threads();
    rock_      = rock::make_model_constants(material_, rock::crack_band_width(prm_.spacing, prm_.cslh));
    model_     = rock::make_model_choice(material_);
    wave_speed_ = std::sqrt((rock_.K + 4.0 / 3.0 * rock_.G) / material_.density);

    const std::size_t n = positions.size();
    p_.resize(n);
    for (std::size_t i = 0; i < n; ++i)
      {
        require(volumes[i] > 0, "particle volumes must be > 0");
        p_.x[i]       = positions[i];
        p_.x0[i]      = positions[i];
        p_.volume0[i] = volumes[i];
        p_.volume[i]  = volumes[i];
        p_.density[i] = material_.density;
        p_.mass[i]    = material_.density * volumes[i];
        p_.h[i]       = prm_.cslh * prm_.spacing;
      }
    constrained_.assign(n, 0);
    prescribed_.assign(n, Vector<dim>::Zero());
    reaction_.assign(n, Vector<dim>::Zero());
    stress_work_.assign(n, 0.0);
    Q_.assign(n, Tensor<dim>::Zero());
    volume_next_.assign(n, 0.0);
    area0_.assign(n, Vector<dim>::Zero());
    simd_ = dim == 3 && prm_.vectorised && pair_kernel::avx2_available();
    mixed_ = simd_ && prm_.single_precision && prm_.spacing >= 1e-4;
    record_.assign(simd_ && !mixed_ ? n * pair_kernel::record_size : 0, 0.0);
    frecord_.assign(mixed_ ? n * pair_kernel::mixed::float_size : 0, 0.0f);
    {
      Vector<dim> lo = p_.x0[0], hi = p_.x0[0];
      for (const Vector<dim> &X : p_.x0)
        {
          lo = lo.cwiseMin(X);
          hi = hi.cwiseMax(X);
        }
      centre0_ = 0.5 * (lo + hi);
    }
    position_volume_.assign(simd_ ? 4 * n : 0, 0.0);

    build_pairs();
    compute_correction();
    compute_area_vectors();
    // F at the reference configuration: identity by construction of L
    F_prev_.assign(n, Tensor<dim>::Identity());
  }

  template <int dim>
  bool Body<dim>::total_lagrangian() const
  {
    return prm_.form == Formulation::total_lagrangian ||
           prm_.form == Formulation::total_lagrangian_corrected;
  }

  template <int dim>
  bool Body<dim>::corrected() const
  {
    return prm_.form == Formulation::total_lagrangian_corrected ||
           prm_.form == Formulation::updated_lagrangian_corrected;
  }

  template <int dim>
  void Body<dim>::build_pairs()
  {
    double h_max = 0;
    for (const double h : p_.h)
      h_max = std::max(h_max, h);
    find_pairs<dim>(p_.x, 2.0 * h_max, pairs_);
    const std::size_t n_p = pairs_.n_pairs();
    grad_w_.resize(n_p);
    const KernelType kernel = prm_.kernel;
    // total Lagrangian: pairs are built once, in the reference configuration, so the hourglass
    // factor hg V0_i V0_j W(|X_ij|) / |X_ij|^2 is a constant of the pair (cached pair geometry)
    const bool tl = total_lagrangian();
    hg_factor_.resize(tl ? n_p : 0);
#pragma omp parallel for num_threads(n_threads_) schedule(static)
    for (long p = 0; p < static_cast<long>(n_p); ++p)
      {
        const int i = pairs_.first[p], j = pairs_.second[p];
        grad_w_[p] = kernels::grad_w<dim>(kernel, p_.x[i] - p_.x[j], 0.5 * (p_.h[i] + p_.h[j]));
        // mixed precision: the gradients are floats (rounded once, 6e-8), and every sum over
        // the pairs (correction L, F, area vectors, forces) uses these same values, so a linear
        // field's gradient stays exact and the float pair data read by the kernels is exact.
        // Through a volatile float: GCC 12.2's SLP vectoriser drops the round trip
        // double -> float -> double on all but the last component (-O2 and -O3)
        if (mixed_)
          for (int d = 0; d < dim; ++d)
            {
              const volatile float rounded = static_cast<float>(grad_w_[p][d]);
              grad_w_[p][d]                = rounded;
            }
        if (tl)
          hg_factor_[p] = intact_hourglass_factor(p);
      }
    constexpr int pair_size = pair_kernel::mixed::pair_size;
    pair_float_.resize(mixed_ ? pair_size * n_p : 0);
    if (mixed_)
#pragma omp parallel for num_threads(n_threads_) schedule(static)
      for (long p = 0; p < static_cast<long>(n_p); ++p)
        {
          float *r = &pair_float_[pair_size * static_cast<std::size_t>(p)];
          for (int d = 0; d < dim; ++d)
            r[d] = static_cast<float>(grad_w_[p][d]);
          r[pair_size - 1] = tl ? static_cast<float>(hg_factor_[p]) : 0.0f;
        }
    if (mixed_) // every pair force reads the float copy: 8 bytes a pair less to hold
      std::vector<double>().swap(hg_factor_);
    // (no hourglass control, nothing to fade: no damage copy nor exchange per step)
    hg_faded_.assign(tl && prm_.hourglass_fade && prm_.hourglass > 0 ? p_.size() : 0, 0);
    partition_pairs();
  }

  template <int dim>
  double Body<dim>::intact_hourglass_factor(const std::size_t p) const
  {
    const int    i  = pairs_.first[p], j = pairs_.second[p];
    const double X2 = (p_.x0[j] - p_.x0[i]).squaredNorm();
    const double W0 = kernels::w<dim>(prm_.kernel, std::sqrt(X2), 0.5 * (p_.h[i] + p_.h[j]));
    const double hg = prm_.hourglass * material_.youngs_modulus;
    return X2 > 0 ? hg * p_.volume0[i] * p_.volume0[j] * W0 / X2 : 0.0;
  }

  template <int dim>
  void Body<dim>::set_hourglass_factor(const std::size_t p, const double factor)
  {
    constexpr int stride = pair_kernel::mixed::pair_size;
    if (mixed_)
      pair_float_[stride * p + stride - 1] = static_cast<float>(factor);
    else
      hg_factor_[p] = factor;
  }

  template <int dim>
  void Body<dim>::fade_hourglass()
  {
    // Ganzenmueller's hourglass force holds a pair at the separation the mean of the two
    // deformation gradients predicts; across a crack that is a spring of stiffness ~0.1 E
    // between the faces (a direct tension bar with the default 0.1 keeps 29 % of its strength
    // after its band has broken, and takes 1.56-1.73 G_I). The particles of an opening band
    // are described by their plastic strain, not by an affine field, so a pair stops being held
    // once either particle has softened in tension. Particles softening in shear or crushing
    // stay pressed together and carry load: without the control their zero-energy modes grow
    // (a ductile heterogeneous short cylinder with end friction ran unstable when every damaged
    // particle was faded), so they keep it. Cracked never reverts, so each pair is faded once:
    // the pairs of each particle cracked since the last pass, through its incidence list (a
    // pass over every pair cost 8 % of a flattened disc's run); the ghosts' flags are their
    // owners', exchanged with the stress
    const std::size_t n = p_.size();
    for (std::size_t i = 0; i < n; ++i)
      if (!hg_faded_[i] && cracked_now_[i] > 0)
        {
          hg_faded_[i] = 1;
          for (std::int32_t k = pairs_.offsets[i]; k < pairs_.offsets[i + 1]; ++k)
            set_hourglass_factor(pairs_.incidence[k], 0.0);
        }
  }

  template <int dim>
  void Body<dim>::partition_pairs()
  {
    const std::size_t n = p_.size(), n_p = pairs_.n_pairs();
    pair_begin_.assign(n + 1, 0);
    for (std::size_t p = 0; p < n_p; ++p)
      ++pair_begin_[pairs_.first[p] + 1];
    for (std::size_t i = 0; i < n; ++i)
      pair_begin_[i + 1] += pair_begin_[i];
    if (chunk_of_.empty())
      {
        const std::vector<std::int64_t> begin(pair_begin_.begin(), pair_begin_.end());
        chunk_begin_ = work_chunks(begin, prm_.chunks);
      }
    else // the whole body's chunks (set_chunks): a new one wherever the number changes
      {
        chunk_begin_.assign(1, 0);
        for (std::size_t i = 1; i < n; ++i)
          if (chunk_of_[i] != chunk_of_[i - 1])
            chunk_begin_.push_back(static_cast<std::int32_t>(i));
        chunk_begin_.push_back(static_cast<std::int32_t>(n));
      }
    const std::size_t K = chunk_begin_.size() - 1;
    // the cross pairs (ascending pair order, so chunk by chunk) and, per chunk, those whose
    // second particle it holds (ascending k: ascending first particle)
    std::vector<std::int32_t> chunk_of(n);
    for (std::size_t c = 0; c < K; ++c)
      std::fill(chunk_of.begin() + chunk_begin_[c], chunk_of.begin() + chunk_begin_[c + 1],
                static_cast<std::int32_t>(c));
    std::vector<std::int32_t> cross_pair; // the cross pairs in ascending order
    cross_begin_.assign(K + 1, 0);
    incoming_begin_.assign(K + 1, 0);
    for (std::size_t c = 0; c < K; ++c)
      {
        const std::int32_t e = chunk_begin_[c + 1];
        for (std::int32_t p = pair_begin_[chunk_begin_[c]]; p < pair_begin_[e]; ++p)
          if (pairs_.second[p] >= e)
            {
              cross_pair.push_back(p);
              ++incoming_begin_[chunk_of[pairs_.second[p]] + 1];
            }
        cross_begin_[c + 1] = static_cast<std::int32_t>(cross_pair.size());
      }
    for (std::size_t c = 0; c < K; ++c)
      incoming_begin_[c + 1] += incoming_begin_[c];
    // what j's chunk reads of each, contiguous in its order (the pairs themselves are spread
    // over the pair arrays: a cache miss each)
    const std::size_t n_cross = cross_pair.size();
    const bool        tl      = total_lagrangian();
    incoming_.resize(n_cross);
    incoming_i_.resize(tl ? n_cross : 0);
    incoming_j_.resize(n_cross);
    incoming_g_.resize(tl ? n_cross : 0);
    std::vector<std::int32_t> fill(incoming_begin_.begin(), incoming_begin_.end() - 1);
    for (std::size_t k = 0; k < n_cross; ++k)
      {
        const std::int32_t p = cross_pair[k], j = pairs_.second[p];
        const std::int32_t at = fill[chunk_of[j]]++;
        incoming_[at]         = static_cast<std::int32_t>(k);
        incoming_j_[at]       = j;
        if (tl)
          {
            incoming_i_[at] = pairs_.first[p];
            incoming_g_[at] = grad_w_[p];
          }
      }
    force_share_.resize(dim * n_cross);
  }

  template <int dim>
  std::vector<std::int32_t> Body<dim>::work_chunks(const std::vector<std::int64_t> &pair_begin,
                                                   const int chunks)
  {
    const std::size_t n = pair_begin.size() - 1;
    const double      n_p = static_cast<double>(pair_begin[n]);
    // chunks of equal work: a pair is one unit, a particle per_particle units (its stress
    // update plus its loop and tail-group overhead; surface chunks hold more particles per
    // pair). 8 was measured, not derived: `valgrind --tool=callgrind --separate-threads=yes
    // sph_bench 0.0025 10 2` put two static ranges' force passes within 1 % and their stress
    // passes 6 % apart with the per-particle Eigen stress update, and with the batched one
    // (stress_batch.h) 8 was still the best of 2, 4, 8 and 12.
    // The number of chunks depends on the particle count only (the results then do not depend
    // on the thread count): enough for a thread that runs slower to hand work over (a chunk is
    // at most 1/max_chunks of a pass), few enough that the cross pairs stay few (each cut
    // adds the pairs across it: see chunk_begin_ in body.h).
    constexpr double      per_particle    = 8.0;
    constexpr std::size_t chunk_particles = 128, max_chunks = 16;
    const std::size_t     K =
      chunks > 0 ? std::min<std::size_t>(static_cast<std::size_t>(chunks), std::max<std::size_t>(n, 1)) :
                        std::clamp<std::size_t>(n / chunk_particles, 1, max_chunks);
    const double          total = n_p + per_particle * n;
    std::vector<std::int32_t> chunk_begin;
    chunk_begin.assign(K + 1, static_cast<std::int32_t>(n));
    chunk_begin[0] = 0;
    for (std::size_t c = 1; c < K; ++c)
      {
        const double target = total * c / K;
        std::size_t  lo = 0, hi = n; // first i whose work before it reaches the target
        while (lo < hi)
          {
            const std::size_t mid = (lo + hi) / 2;
            if (pair_begin[mid] + per_particle * mid < target)
              lo = mid + 1;
            else
              hi = mid;
          }
        chunk_begin[c] = static_cast<std::int32_t>(lo);
      }
    return chunk_begin;
  }

  template <int dim>
  void Body<dim>::set_chunks(const std::vector<std::int32_t> &chunk_of)
  {
    require(chunk_of.size() == p_.size(), "set_chunks: one chunk number per particle");
    for (std::size_t i = 1; i < chunk_of.size(); ++i)
      require(chunk_of[i] >= chunk_of[i - 1], "set_chunks: chunk numbers must not decrease");
    chunk_of_ = chunk_of;
    partition_pairs();
  }

  template <int dim>
  void Body<dim>::set_owned(const std::vector<std::uint8_t> &owned)
  {
    require(owned.empty() || owned.size() == p_.size(), "set_owned: one flag per particle");
    owned_ = owned;
  }

  template <int dim>
  void Body<dim>::restrict_to_owned(Domain &domain)
  {
    require(total_lagrangian(), "restrict_to_owned: total Lagrangian forms only (the updated "
                                "Lagrangian ones rebuild their pairs every step)");
    require(owned_.size() == p_.size() && domain.owned() == owned_,
            "restrict_to_owned: set_owned(domain.owned()) first");
    const std::size_t n = p_.size(), n_p = pairs_.n_pairs();
    // the stress of the owned particles only; what a step reads: the owned particles, the other
    // particles of their pairs, and every member of a loaded-face column with an owned member
    // (the outer particle's correction sums the members' stresses)
    read_ = owned_;
    for (std::size_t p = 0; p < n_p; ++p)
      if (owned_[pairs_.first[p]] || owned_[pairs_.second[p]])
        read_[pairs_.first[p]] = read_[pairs_.second[p]] = 1;
    for (const FaceColumn &column : face_columns_)
      if (std::any_of(column.members.begin(), column.members.end(),
                      [&](const unsigned int k) { return owned_[k] != 0; }))
        for (const unsigned int k : column.members)
          read_[k] = 1;
    domain.restrict_exchange(read_);
    // the pairs with an owned particle, in their order, with their cached data
    constexpr int pair_size = pair_kernel::mixed::pair_size;
    std::size_t   kept      = 0;
    for (std::size_t p = 0; p < n_p; ++p)
      {
        if (!owned_[pairs_.first[p]] && !owned_[pairs_.second[p]])
          continue;
        pairs_.first[kept]  = pairs_.first[p];
        pairs_.second[kept] = pairs_.second[p];
        grad_w_[kept]       = grad_w_[p];
        if (!hg_factor_.empty())
          hg_factor_[kept] = hg_factor_[p];
        if (!pair_float_.empty())
          std::copy_n(&pair_float_[pair_size * p], pair_size, &pair_float_[pair_size * kept]);
        ++kept;
      }
    pairs_.first.resize(kept);
    pairs_.second.resize(kept);
    grad_w_.resize(kept);
    if (!hg_factor_.empty())
      hg_factor_.resize(kept);
    if (!pair_float_.empty())
      pair_float_.resize(pair_size * kept);
    for (auto *v : {&pairs_.first, &pairs_.second})
      v->shrink_to_fit();
    grad_w_.shrink_to_fit();
    hg_factor_.shrink_to_fit();
    pair_float_.shrink_to_fit();
    build_incidence(n, pairs_);
    partition_pairs();
  }

  template <int dim>
  void Body<dim>::compute_correction()
  {
    // L_i = A_i^{-T}, A_i = sum_j V_j (x_j - x_i) grad_i W_ij^T: corrected gradients reproduce the
    // gradient of any linear field exactly. TL always keeps L (F uses it); the force uses it
    // only in the corrected forms.
    const bool need = corrected() || total_lagrangian();
    const std::size_t n = p_.size();
#pragma omp parallel for num_threads(n_threads_) schedule(static)
    for (long i = 0; i < static_cast<long>(n); ++i)
      {
        if (!need)
          {
            p_.L[i].setIdentity();
            continue;
          }
        Tensor<dim> A = Tensor<dim>::Zero();
        for (std::int32_t k = pairs_.offsets[i]; k < pairs_.offsets[i + 1]; ++k)
          {
            const std::int32_t p = pairs_.incidence[k];
            const std::int32_t j = pairs_.other(p, i);
            const Vector<dim>  g = (pairs_.first[p] == i) ? grad_w_[p] : Vector<dim>(-grad_w_[p]);
            A.noalias() += p_.volume[j] * (p_.x[j] - p_.x[i]) * g.transpose();
          }
        // a particle without enough neighbours keeps plain gradients
        const double det = A.determinant();
        if (std::abs(det) > 1e-3)
          p_.L[i] = A.inverse().transpose();
        else
          p_.L[i].setIdentity();
      }
  }

  template <int dim>
  void Body<dim>::compute_area_vectors()
  {
    // a_i = -s_i, s_i = sum_j V_i V_j (L_i + L_j) grad_i W_ij (plain gradients: L = I): the
    // force f_i = P s_i the particle feels in a uniform stress P, so a pressure p applied as
    // -p a_i balances the uniform state -p I exactly at every particle (no calibration); the
    // vectors vanish inside, sum to zero over a closed body and, over a flat face, to its area.
    const std::size_t n = p_.size();
#pragma omp parallel for num_threads(n_threads_) schedule(static)
    for (long i = 0; i < static_cast<long>(n); ++i)
      area0_[i] = -loaded_face_s(static_cast<unsigned int>(i));
    lump_loaded_faces(area0_);
  }

  template <int dim>
  void Body<dim>::constrain(const unsigned int i, const unsigned int component,
                            const double velocity)
  {
    constrained_[i] |= static_cast<std::uint8_t>(1u << component);
    prescribed_[i][component] = velocity;
  }

  template <int dim>
  void Body<dim>::release(const unsigned int i, const unsigned int component)
  {
    constrained_[i] &= static_cast<std::uint8_t>(~(1u << component));
  }

  template <int dim>
  void Body<dim>::set_strength_factors(const std::vector<double> &factors)
  {
    require(factors.size() == p_.size(), "set_strength_factors: one factor per particle");
    for (const double f : factors)
      require(std::isfinite(f) && f > 0, "set_strength_factors: factors must be finite and > 0");
    for (std::size_t i = 0; i < factors.size(); ++i)
      p_.history[i].strength = factors[i];
  }

  template <int dim>
  void Body<dim>::release_all()
  {
    std::fill(constrained_.begin(), constrained_.end(), 0);
  }

  template <int dim>
  double Body<dim>::stable_time_step() const
  {
    // a minimum is exact in any order: the threads' partial minima give the same bits
    double     dt = std::numeric_limits<double>::max();
    const long n  = static_cast<long>(p_.size());
#pragma omp parallel for num_threads(n_threads_) schedule(static) reduction(min : dt)
    for (long i = 0; i < n; ++i)
      dt = std::min(dt, p_.h[i] / (wave_speed_ + p_.v[i].norm()));
    return prm_.tssfac * dt;
  }

  template <int dim>
  std::vector<Vector<dim>> Body<dim>::self_gradients() const
  {
    std::vector<Vector<dim>> g(p_.size(), Vector<dim>::Zero());
    if (!total_lagrangian())
      return g;
    // A_i = sum_j V0_j (x_j - x_i) (x) grad_i W_ij: d A_i / d x_i = -I (x) sum_j V0_j grad_i W_ij,
    // grad_j W_ji = -grad_i W_ij for the second particle of a pair
    for (std::size_t p = 0; p < pairs_.n_pairs(); ++p)
      {
        const std::int32_t i = pairs_.first[p], j = pairs_.second[p];
        g[i] += p_.volume0[j] * grad_w_[p];
        g[j] -= p_.volume0[i] * grad_w_[p];
      }
    // F = A L^T: d F / d x_i = -I (x) L_i s_i
    for (std::size_t i = 0; i < p_.size(); ++i)
      g[i] = p_.L[i] * g[i];
    return g;
  }

  template <int dim>
  void Body<dim>::update_stress_total_lagrangian()
  {
    // F_i = A_i L_i^T, A_i = sum_j V0_j (x_j - x_i) (x) grad_i W_ij: the pair (i, j) adds
    // V0_j d (x) g to A_i and -V0_i (-d) (x) g to A_j (d = x_j - x_i, g = grad_w_ of the pair).
    // A_j is summed in p_.F[j] (set to zero first) until j's own pairs finish it; then j's stress
    // is updated in the same pass (see pair_begin_ in body.h for the order of the terms).
    const bool                      cor  = corrected();
    const bool                      simd = simd_;
    const std::vector<double>      &V0  = p_.volume0;
    const std::vector<Vector<dim>> &x   = p_.x;
    const long                      n   = static_cast<long>(p_.size());
    const long                      n_chunks = static_cast<long>(chunk_begin_.size()) - 1;
    constexpr int                   dd       = dim * dim;
    ChunkQueue queue;
    queue.reset(static_cast<int>(n_chunks), n_threads_);
    std::visit(
      [&](const auto &model) {
#pragma omp parallel num_threads(n_threads_)
        {
          if (simd) // (x, V0) of every particle, read by all chunks as second particles
            {
#pragma omp for schedule(static)
              for (long i = 0; i < n; ++i)
                {
                  double *r = &position_volume_[4 * static_cast<std::size_t>(i)];
                  for (int d = 0; d < dim; ++d)
                    r[d] = x[i][d];
                  r[3] = V0[i];
                }
            }
          const int t = omp_get_thread_num();
          for (int chunk; (chunk = queue.next(t)) >= 0;)
            {
              const std::int32_t b = chunk_begin_[chunk], e = chunk_begin_[chunk + 1];
              for (std::int32_t i = b; i < e; ++i)
                p_.F[i].setZero();
              // the shares of j of the pairs from earlier chunks (ascending pair order):
              // V0_i (x_j - x_i) (x) g, as -V0_i (x_i - x_j) (the same bits)
              const std::int32_t kb = incoming_begin_[chunk], ke = incoming_begin_[chunk + 1];
              if (simd) // (3-D only) the same products and sums, vectorised
                {
                  if constexpr (dim == 3)
                    pair_kernel::incoming_gradient(
                      position_volume_.data(), incoming_i_.data() + kb, incoming_j_.data() + kb,
                      reinterpret_cast<const double *>(incoming_g_.data() + kb), ke - kb,
                      p_.F[0].data());
                }
              else
                for (std::int32_t k = kb; k < ke; ++k)
                  {
                    const std::int32_t i = incoming_i_[k], j = incoming_j_[k];
                    const Vector<dim> &g = incoming_g_[k];
                    for (int r = 0; r < dim; ++r)
                      {
                        const double d = -V0[i] * (x[i][r] - x[j][r]);
                        for (int c = 0; c < dim; ++c)
                          p_.F[j](r, c) += d * g[c];
                      }
                  }
              [[maybe_unused]] std::int32_t batch[stress_batch::lanes];
              [[maybe_unused]] int          n_batch = 0;
              for (std::int32_t i = b; i < e; ++i)
                {
                  // A_i in registers: its terms as second particle are in p_.F[i] already
                  double a[dim][dim];
                  for (int r = 0; r < dim; ++r)
                    for (int c = 0; c < dim; ++c)
                      a[r][c] = p_.F[i](r, c);
                  if (simd)
                    {
                      if constexpr (dim == 3)
                        {
                          // four pairs at a time (src/pair_kernel.h); i's own terms summed in
                          // lanes (a fixed order), after its terms as second particle
                          double own[dd];
                          pair_kernel::particle_gradient(
                            position_volume_.data(),
                            reinterpret_cast<const double *>(grad_w_.data()),
                            mixed_ ? pair_float_.data() : nullptr, i, pair_begin_[i],
                            pair_begin_[i + 1], pairs_.second.data(), e, p_.F[0].data(), own);
                          for (int r = 0; r < dim; ++r)
                            for (int c = 0; c < dim; ++c)
                              a[r][c] += own[dim * c + r];
                        }
                    }
                  else
                    {
                      // i's position and volume in locals: the stores to p_.F[j] below are
                      // through double pointers and would make the compiler reload them at
                      // every pair
                      const Vector<dim> xi  = x[i];
                      const double      V0i = V0[i];
                      for (std::int32_t p = pair_begin_[i]; p < pair_begin_[i + 1]; ++p)
                        {
                          const std::int32_t j  = pairs_.second[p];
                          const Vector<dim> &g  = grad_w_[p];
                          const Vector<dim> &xj = x[j];
                          const double       V0j = V0[j];
                          // di = V0_j d, dj = V0_i d with d = x_j - x_i (the same bits as
                          // -V0_i (x_i - x_j): IEEE negation and subtraction are exact mirrors)
                          double di[dim], dj[dim];
                          for (int r = 0; r < dim; ++r)
                            {
                              const double d = xj[r] - xi[r];
                              di[r]          = V0j * d;
                              dj[r]          = V0i * d;
                            }
                          for (int r = 0; r < dim; ++r)
                            for (int c = 0; c < dim; ++c)
                              a[r][c] += di[r] * g[c];
                          if (j < e) // else: added by j's chunk (incoming_)
                            {
                              Tensor<dim> &Aj = p_.F[j];
                              for (int r = 0; r < dim; ++r)
                                for (int c = 0; c < dim; ++c)
                                  Aj(r, c) += dj[r] * g[c];
                            }
                        }
                    }
                  if constexpr (dim == 3)
                    {
                      // A_i to p_.F[i]; the stress update of four particles at a time
                      for (int r = 0; r < dim; ++r)
                        for (int c = 0; c < dim; ++c)
                          p_.F[i](r, c) = a[r][c];
                      if (read_.empty() || owned_[i])
                        batch[n_batch++] = i;
                      if (n_batch == stress_batch::lanes || (i + 1 == e && n_batch > 0))
                        {
                          update_stress_batch(model, batch, n_batch);
                          n_batch = 0;
                        }
                    }
                  else if (read_.empty() || owned_[i])
                    {
                      Tensor<dim> A;
                      for (int r = 0; r < dim; ++r)
                        for (int c = 0; c < dim; ++c)
                          A(r, c) = a[r][c];
                      const Tensor<dim> F = A * p_.L[i].transpose();
                      // incremental objective update (Hughes-Winget) with G = dF F_mid^{-1}
                      const Tensor<dim> G = (F - F_prev_[i]) * (0.5 * (F + F_prev_[i])).inverse();
                      const Tensor3     gg = embed<dim>(G);
                      const Tensor3     de = 0.5 * (gg + gg.transpose());
                      const Tensor3     R  = hughes_winget(0.5 * (gg - gg.transpose()));
                      const Tensor3     rotated = R * p_.stress[i] * R.transpose();
                      const rock::StressUpdate up = model(rotated, de, p_.history[i], rock_);
                      const Tensor<dim> C = cofactor<dim>(F); // J F^{-T}
                      const double      J = F.row(0).dot(C.row(0));
                      stress_work_[i] +=
                        p_.volume0[i] * J * (0.5 * (rotated + up.stress)).cwiseProduct(de).sum();
                      p_.stress[i]  = up.stress;
                      p_.history[i] = up.state;
                      F_prev_[i]    = F;
                      p_.F[i]       = F;
                      p_.volume[i]  = p_.volume0[i] * J;
                      p_.density[i] = p_.mass[i] / p_.volume[i];
                      // first Piola-Kirchhoff P = J sigma F^{-T} = sigma cof(F)
                      const Tensor<dim> P = up.stress.template topLeftCorner<dim, dim>() * C;
                      Q_[i] = cor ? Tensor<dim>(P * p_.L[i]) : P;
                    }
                }
            }
        }
      },
      model_);
  }

  template <int dim>
  template <typename Model>
  void Body<dim>::update_stress_batch(const Model &model, const std::int32_t *idx, const int n)
  {
    static_assert(dim == 3);
    stress_batch::Fields f;
    f.F         = p_.F[0].data();
    f.L         = p_.L[0].data();
    f.F_prev    = F_prev_[0].data();
    f.stress    = p_.stress[0].data();
    f.Q         = Q_[0].data();
    f.volume0   = p_.volume0.data();
    f.mass      = p_.mass.data();
    f.volume    = p_.volume.data();
    f.density   = p_.density.data();
    f.work      = stress_work_.data();
    f.two_G     = 2.0 * rock_.G;
    f.lambda    = rock_.K - 2.0 / 3.0 * rock_.G;
    f.corrected = corrected();
    stress_batch::Batch b;
    stress_batch::kinematics(f, idx, n, b, simd_);
    // the next batch's fields on their way while the model and the next pairs run
    stress_batch::prefetch_next(f, idx[n - 1] + 1, static_cast<std::int32_t>(p_.x.size()),
                                p_.history.data(), sizeof(MaterialState));
    // the rock model, particle by particle, where the trial (in b.stress) is not surely elastic
    for (int l = 0; l < n; ++l)
      {
        const std::int32_t i = idx[l];
        Tensor3            trial, rotated, de;
        for (int e = 0; e < 9; ++e)
          trial.data()[e] = b.stress[e][l];
        if (model.surely_elastic(trial, p_.history[i], rock_))
          continue;
        for (int e = 0; e < 9; ++e)
          {
            rotated.data()[e] = b.rotated[e][l];
            de.data()[e]      = b.de[e][l];
          }
        const rock::StressUpdate up = model(rotated, de, p_.history[i], rock_);
        p_.history[i]               = up.state;
        for (int e = 0; e < 9; ++e)
          b.stress[e][l] = up.stress.data()[e];
      }
    stress_batch::finish(f, b, simd_);
  }

  template <int dim>
  void Body<dim>::update_stress_updated_lagrangian()
  {
    build_pairs();
    compute_correction();
    if (pressure_ != 0.0)
      compute_area_vectors();
    const std::size_t n  = p_.size();
    const double      dt = dt_last_;
    const bool        evolve_h = prm_.evolve_h;
    std::visit(
      [&](const auto &model) {
#pragma omp parallel for num_threads(n_threads_) schedule(static)
        for (long i = 0; i < static_cast<long>(n); ++i)
          {
            const Tensor<dim> A = pair_gradient<dim>(pairs_, grad_w_, p_.volume, p_.v, i);
            const Tensor<dim> grad_v = A * p_.L[i].transpose();
            const Tensor3     g      = embed<dim>(Tensor<dim>(grad_v * dt));
            const Tensor3     de     = 0.5 * (g + g.transpose());
            const Tensor3     R      = hughes_winget(0.5 * (g - g.transpose()));
            const Tensor3     rotated = R * p_.stress[i] * R.transpose();
            const rock::StressUpdate up = model(rotated, de, p_.history[i], rock_);
            stress_work_[i] += p_.volume[i] * (0.5 * (rotated + up.stress)).cwiseProduct(de).sum();
            p_.stress[i]  = up.stress;
            p_.history[i] = up.state;
            // other particles still read the old volume in this loop: write the new one aside
            const double tr = de.trace();
            volume_next_[i] = p_.volume[i] * std::exp(tr);
            p_.density[i]   = p_.mass[i] / volume_next_[i];
            if (evolve_h)
              p_.h[i] *= std::exp(tr / dim);
            p_.F[i] = (Tensor<dim>::Identity() + grad_v * dt) * p_.F[i];
            Q_[i]   = p_.stress[i].template topLeftCorner<dim, dim>() * p_.L[i];
          }
      },
      model_);
    p_.volume.swap(volume_next_);
    dt_last_ = 0; // a second call at the same positions changes nothing
  }

  template <int dim>
  void Body<dim>::pair_forces()
  {
    const bool        tl    = total_lagrangian();
    const double      alpha = prm_.av_alpha, beta = prm_.av_beta, c = wave_speed_;
    const double      hg    = tl ? prm_.hourglass * material_.youngs_modulus : 0.0;
    const bool        av    = alpha > 0 || beta > 0;
    const double      pa    = pressure_;
    // the arrays the pair force reads, as plain pointers held by value in the lambdas below: a
    // captured reference to a std::vector costs two or three dependent loads per use, and
    // there are too few registers to keep them all
    const double       *V      = (tl ? p_.volume0 : p_.volume).data();
    const Tensor<dim>  *Q      = Q_.data();
    const Tensor<dim>  *F      = p_.F.data();
    const Vector<dim>  *x      = p_.x.data();
    const Vector<dim>  *v      = p_.v.data();
    const Vector<dim>  *x0     = p_.x0.data();
    const double       *h      = p_.h.data();
    const double       *rho    = p_.density.data();
    const double       *m      = p_.mass.data();
    const Vector<dim>  *grad_w = grad_w_.data();
    const double       *hgf    = hg_factor_.data();
    const std::int32_t *second = pairs_.second.data(), *pair_begin = pair_begin_.data();
    Vector<dim>        *f_int  = p_.f_int.data();
    // what the pair force reads of particle i, copied into locals once per particle: the loop
    // writes f_int[j] through double pointers, after which the compiler must reload every double
    // it read from the particle arrays
    struct Side
    {
      Tensor<dim> Q, F;
      Vector<dim> x, v, x0;
      double      h, density, mass, V;
    };
    const auto side = [=](const int i) __attribute__((always_inline)) {
      return Side{Q[i], F[i], x[i], v[i], x0[i], h[i], rho[i], m[i], V[i]};
    };
    // force on i of pair p = (i, j) (-force on j), with its viscous and hourglass powers
    // (always inlined: called at two places, and a call per pair costs ~70 instructions).
    // Written in scalars: Eigen's packets of two on 3-vectors cost more in shuffles than they save
    const auto pair_force = [=](const std::int32_t p, const Side &si, const int j,
                                double (&f)[dim], double &power,
                                double &hg_power) __attribute__((always_inline)) {
      const Vector<dim> &gw = grad_w[p];
      const Vector<dim> &xj = x[j], &vj = v[j];
      double             xij[dim], vij[dim], r2 = 0, vr = 0;
      for (int d = 0; d < dim; ++d)
        {
          xij[d] = si.x[d] - xj[d];
          vij[d] = si.v[d] - vj[d];
          r2 += xij[d] * xij[d];
          vr += vij[d] * xij[d];
        }
      // stress: f_i = V_i V_j (P_i L_i + P_j L_j) grad W_ij, f_j = -f_i
      // (Q = P L without the volume: one sum of tensors and one product by V_i V_j per pair)
      const double       vv = si.V * V[j];
      const Tensor<dim> &Qj = Q[j];
      for (int r = 0; r < dim; ++r)
        {
          double s = 0;
          for (int k = 0; k < dim; ++k)
            s += (si.Q(r, k) + Qj(r, k)) * gw[k];
          f[r] = vv * s;
        }
      // the viscous and the hourglass forces both act along x_ij: f += (s_av + s_hg) x_ij, and
      // their powers are s x_ij . v_ij = s vr
      double s_av = 0, s_hg = 0;
      if (av && vr < 0 && r2 > 0)
        {
          const double hb     = 0.5 * (si.h + h[j]);
          const double mu     = hb * vr / (r2 + 0.01 * hb * hb);
          const double rho_ij = 0.5 * (si.density + rho[j]);
          const double Pi     = (-alpha * c * mu + beta * mu * mu) / rho_ij;
          // grad W along the current pair direction, magnitude of the cached gradient:
          // |gw| / r = sqrt(|gw|^2 / r^2), one square root instead of two
          s_av = si.mass * m[j] * Pi * std::sqrt(gw.squaredNorm() / r2);
        }
      if (hg > 0 && r2 > 0)
        {
          // Ganzenmueller (2015): mismatch of the pair separation predicted by F_i and F_j,
          // err = (F_i + F_j) X / 2 - x with X = X_j - X_i, x = x_j - x_i = -x_ij;
          // delta = err . x / r is the separation error along the pair; the force magnitude
          // g = hg V_i V_j W(|X|) delta / |X|^2 (the constant factor cached by build_pairs)
          // acts along x / r: on i -(g / r) x = -factor (err . x) / r^2 x = s_hg x_ij with
          // s_hg = -factor (e . x_ij) / r^2, e = -err = (F_i + F_j) X / 2 + x_ij
          const Tensor<dim> &Fj  = F[j];
          const Vector<dim> &x0j = x0[j];
          double             e_dot = 0;
          for (int r = 0; r < dim; ++r)
            {
              double y = 0;
              for (int k = 0; k < dim; ++k)
                y += (si.F(r, k) + Fj(r, k)) * (x0j[k] - si.x0[k]);
              e_dot += (0.5 * y + xij[r]) * xij[r];
            }
          s_hg = -hgf[p] * e_dot / r2;
        }
      const double s = s_av + s_hg;
      for (int d = 0; d < dim; ++d)
        f[d] += s * xij[d];
      power    = s_av * vr; // <= 0: rate of work of the viscous pair on the particles
      hg_power = s_hg * vr;
    };
    // dissipation powers summed per chunk in pair order, chunks added in order (the same bits
    // with any number of threads)
    std::vector<double> partial(2 * (chunk_begin_.size() - 1), 0.0);
    static_assert(dim + 2 == pair_kernel::out_size || dim != 3); // force and two powers
    // the kernel reads Eigen's small vectors and matrices as plain doubles
    static_assert(sizeof(Vector<dim>) == dim * sizeof(double) &&
                  sizeof(Tensor<dim>) == dim * dim * sizeof(double));
    // the vectorised pair force (3-D, AVX2): the same terms, four pairs at a time
    const bool        simd = simd_;
    pair_kernel::Args args;
    args.record    = record_.data();
    // (not read when there are no pairs)
    args.grad_w    = reinterpret_cast<const double *>(grad_w_.data());
    args.hg_factor = hg > 0 ? hgf : nullptr;
    args.alpha     = alpha;
    args.beta      = beta;
    args.c         = c;
    args.av        = av;
    const bool          mixed = mixed_;
    pair_kernel::mixed::Args margs;
    margs.record    = frecord_.data();
    margs.pair      = pair_float_.data();
    margs.hourglass = hg > 0;
    margs.alpha     = alpha;
    margs.beta      = beta;
    margs.c         = c;
    margs.av        = av;
    const long n_chunks = static_cast<long>(chunk_begin_.size()) - 1;
    const long n        = static_cast<long>(p_.size());
    // distributed (set_owned): the dissipation of the pairs whose first particle is owned
    const std::uint8_t *owned = owned_.empty() ? nullptr : owned_.data();
    ChunkQueue queue, gather_queue;
    queue.reset(static_cast<int>(n_chunks), n_threads_);
    gather_queue.reset(static_cast<int>(n_chunks), n_threads_);
#pragma omp parallel num_threads(n_threads_)
    {
      if (simd) // the records of every particle, read by all chunks as second particles
        {
          std::size_t b, e;
          chunk(static_cast<std::size_t>(n), omp_get_thread_num(), omp_get_num_threads(), b, e);
          pack_records(static_cast<std::int32_t>(b), static_cast<std::int32_t>(e));
#pragma omp barrier
        }
      const int t = omp_get_thread_num();
      for (int chunk; (chunk = queue.next(t)) >= 0;)
        {
          const std::int32_t b = chunk_begin_[chunk], e = chunk_begin_[chunk + 1];
          for (std::int32_t i = b; i < e; ++i)
            p_.f_int[i].setZero();
          double  sum_power = 0, sum_hg_power = 0;
          double *share     = force_share_.data() + dim * static_cast<std::size_t>(cross_begin_[chunk]);
          for (std::int32_t i = b; i < e; ++i)
            {
              Vector<dim> fi = f_int[i]; // its terms as second particle so far
              if (simd)
                {
                  // i's pairs four (eight) at a time: their sum on i in lanes (a fixed order),
                  // the second particles' shares subtracted pair by pair (each j in ascending
                  // i), those of a later chunk written to the share
                  double sum[pair_kernel::out_size];
                  if (mixed)
                    share = pair_kernel::mixed::particle_forces(
                      margs, i, pair_begin[i], pair_begin[i + 1], second, e,
                      reinterpret_cast<double *>(f_int), share, sum);
                  else
                    share = pair_kernel::particle_forces(args, i, pair_begin[i], pair_begin[i + 1],
                                                         second, e,
                                                         reinterpret_cast<double *>(f_int), share,
                                                         sum);
                  for (int d = 0; d < dim; ++d)
                    fi[d] += sum[d];
                  if (owned == nullptr || owned[i])
                    {
                      sum_power += sum[dim];
                      sum_hg_power += sum[dim + 1];
                    }
                }
              else
                {
                  const Side si = side(i);
                  for (std::int32_t p = pair_begin[i]; p < pair_begin[i + 1]; ++p)
                    {
                      const std::int32_t j = second[p];
                      double             power, hg_power, f[dim];
                      pair_force(p, si, j, f, power, hg_power);
                      for (int d = 0; d < dim; ++d)
                        fi[d] += f[d];
                      if (j < e)
                        {
                          Vector<dim> &fj = f_int[j];
                          for (int d = 0; d < dim; ++d)
                            fj[d] -= f[d];
                        }
                      else // subtracted by j's chunk after all chunks (incoming_)
                        for (int d = 0; d < dim; ++d)
                          *share++ = f[d];
                      if (owned == nullptr || owned[i])
                        {
                          sum_power += power;
                          sum_hg_power += hg_power;
                        }
                    }
                }
              f_int[i] = fi;
              if (pa != 0.0)
                {
                  const Vector<dim> a =
                    tl ? Vector<dim>(p_.F[i].determinant() * p_.F[i].inverse().transpose() *
                                     area0_[i]) :
                         area0_[i];
                  p_.f_pressure[i] = -pa * a;
                }
              else
                p_.f_pressure[i].setZero();
            }
          partial[2 * chunk]     = sum_power;
          partial[2 * chunk + 1] = sum_hg_power;
        }
#pragma omp barrier
      // (every chunk's shares are written) the shares of the pairs from earlier chunks,
      // subtracted from their j in ascending pair order
      for (int chunk; (chunk = gather_queue.next(t)) >= 0;)
        for (std::int32_t k = incoming_begin_[chunk]; k < incoming_begin_[chunk + 1]; ++k)
          {
            const std::int32_t m  = incoming_[k];
            Vector<dim>       &fj = f_int[incoming_j_[k]];
            for (int d = 0; d < dim; ++d)
              fj[d] -= force_share_[dim * static_cast<std::size_t>(m) + d];
          }
    }
    viscous_power_   = 0;
    hourglass_power_ = 0;
    for (long chunk = 0; chunk < n_chunks; ++chunk)
      {
        viscous_power_ += partial[2 * chunk];
        hourglass_power_ += partial[2 * chunk + 1];
      }
    if (!face_columns_.empty())
      loaded_face_forces();
  }

  template <int dim>
  void Body<dim>::pack_records(const std::int32_t begin, const std::int32_t end)
  {
    if constexpr (dim == 3)
      {
        namespace f          = pair_kernel::field;
        const bool    tl     = total_lagrangian();
        const double *volume = (tl ? p_.volume0 : p_.volume).data();
        if (mixed_)
          {
            namespace m = pair_kernel::mixed::field;
            for (std::int32_t i = begin; i < end; ++i)
              {
                if (!read_.empty() && !read_[i])
                  continue;
                float *r = &frecord_[pair_kernel::mixed::float_size * static_cast<std::size_t>(i)];
                for (int k = 0; k < 9; ++k)
                  {
                    r[m::q + k] = static_cast<float>(Q_[i].data()[k]);
                    // H = F - I and u = x - X formed in double: the floats keep their digits
                    r[m::h_grad + k] =
                      static_cast<float>(p_.F[i].data()[k] - (k % 4 == 0 ? 1.0 : 0.0));
                  }
                for (int c = 0; c < 3; ++c)
                  {
                    r[m::v + c]  = static_cast<float>(p_.v[i][c]);
                    r[m::u + c]  = static_cast<float>(p_.x[i][c] - p_.x0[i][c]);
                    r[m::x0 + c] = static_cast<float>(p_.x0[i][c] - centre0_[c]);
                  }
                r[m::h]       = static_cast<float>(p_.h[i]);
                r[m::density] = static_cast<float>(p_.density[i]);
                r[m::mass]    = static_cast<float>(p_.mass[i]);
                r[m::volume]  = static_cast<float>(volume[i]);
              }
            return;
          }
        for (std::int32_t i = begin; i < end; ++i)
          {
            if (!read_.empty() && !read_[i])
              continue;
            double *r = &record_[pair_kernel::record_size * static_cast<std::size_t>(i)];
            // element loops, not std::copy: a memmove call per 72 bytes costs more than the copy
            const double *q = Q_[i].data(), *F = p_.F[i].data();
            for (int k = 0; k < 9; ++k)
              {
                r[f::q + k] = q[k];
                r[f::f + k] = F[k];
              }
            for (int d = 0; d < 3; ++d)
              {
                r[f::x + d]  = p_.x[i][d];
                r[f::v + d]  = p_.v[i][d];
                r[f::x0 + d] = p_.x0[i][d];
              }
            r[f::h]       = p_.h[i];
            r[f::density] = p_.density[i];
            r[f::mass]    = p_.mass[i];
            r[f::volume]  = volume[i];
          }
      }
  }

  template <int dim>
  void Body<dim>::compute_forces(const Domain *domain)
  {
    if (total_lagrangian())
      update_stress_total_lagrangian();
    else
      update_stress_updated_lagrangian();
    const bool fade = !hg_faded_.empty();
    if (fade)
      {
        cracked_now_.resize(p_.size());
        for (std::size_t i = 0; i < p_.size(); ++i)
          cracked_now_[i] = p_.history[i].cracked ? 1.0 : 0.0;
      }
    if (domain) // what the pair forces read of the ghosts, from their owners
      {
        require(!read_.empty(), "compute_forces: restrict_to_owned(domain) first");
        static_assert(sizeof(Tensor<dim>) == dim * dim * sizeof(double) &&
                      sizeof(Tensor3) == 9 * sizeof(double));
        std::vector<std::pair<double *, int>> fields = {{Q_.front().data(), dim * dim},
                                                        {p_.F.front().data(), dim * dim},
                                                        {p_.stress.front().data(), 9},
                                                        {p_.density.data(), 1}};
        if (fade)
          fields.push_back({cracked_now_.data(), 1});
        domain->exchange(fields);
      }
    if (fade)
      fade_hourglass();
    pair_forces();
  }

  template <int dim>
  void Body<dim>::integrate(const double dt)
  {
    const std::size_t n = p_.size();
    const std::uint8_t *owned = owned_.empty() ? nullptr : owned_.data();
    const bool          only_owned = !read_.empty(); // the ghosts come from their owners
    external_ += deterministic_sum(n, n_threads_, [&](const std::size_t i) {
      if (only_owned && !owned[i])
        return 0.0;
      const Vector<dim> f = p_.f_int[i] + p_.f_pressure[i] + p_.f_ext[i];
      Vector<dim>       v = p_.v[i] + (dt / p_.mass[i]) * f;
      Vector<dim>       r = Vector<dim>::Zero();
      if (constrained_[i])
        for (int d = 0; d < dim; ++d)
          if ((constrained_[i] >> d) & 1u)
            {
              r[d] = p_.mass[i] * (prescribed_[i][d] - p_.v[i][d]) / dt - f[d];
              v[d] = prescribed_[i][d];
            }
      reaction_[i] = r;
      p_.v[i]      = v;
      p_.x[i] += dt * v;
      const double work = (p_.f_ext[i] + p_.f_pressure[i] + r).dot(v) * dt;
      p_.f_ext[i].setZero();
      return (owned == nullptr || owned[i]) ? work : 0.0;
    });
    viscous_ -= dt * viscous_power_;
    hourglass_ -= dt * hourglass_power_;
    dt_last_ = dt;
  }

  template <int dim>
  void Body<dim>::exchange_ghosts(const Domain &domain)
  {
    static_assert(sizeof(Vector<dim>) == dim * sizeof(double));
    domain.exchange({{p_.x.front().data(), dim}, {p_.v.front().data(), dim}});
  }

  template <int dim>
  Energies Body<dim>::energies() const
  {
    Energies e;
    const std::size_t   n     = p_.size();
    const std::uint8_t *owned = owned_.empty() ? nullptr : owned_.data();
    e.kinetic = deterministic_sum(n, n_threads_, [&](const std::size_t i) {
      return (owned == nullptr || owned[i]) ? 0.5 * p_.mass[i] * p_.v[i].squaredNorm() : 0.0;
    });
    e.internal = deterministic_sum(n, n_threads_, [&](const std::size_t i) {
      return (owned == nullptr || owned[i]) ?
               p_.volume[i] * rock::elastic_energy_density(p_.stress[i], rock_) :
               0.0;
    });
    const double work = deterministic_sum(n, n_threads_, [&](const std::size_t i) {
      return (owned == nullptr || owned[i]) ? stress_work_[i] : 0.0;
    });
    e.plastic   = work - e.internal;
    e.viscous   = viscous_;
    e.hourglass = hourglass_;
    e.external  = external_;
    return e;
  }

  template <int dim>
  Vector<dim> Body<dim>::momentum() const
  {
    Vector<dim> m = Vector<dim>::Zero();
    for (std::size_t i = 0; i < p_.size(); ++i)
      m += p_.mass[i] * p_.v[i];
    return m;
  }

  template class Body<2>;
  template class Body<3>;
} // namespace sph
