/// @file
/// PenaltyContact::apply for ContactMethod::kinematic: a predictor-corrector constraint, as the
/// constraint contacts of explicit codes do it. The step the rock would take without contact,
/// x + dt (v + dt f / m) (the body's symplectic Euler update), is predicted; for each particle
/// that would end the step inside a face (predicted gap g* < 0) the normal force that brings it
/// exactly onto the face is
///   f_n = -m_eff g* / dt^2,   1 / m_eff = 1 / m_particle + sum_a w_a^2 / m_a,share,
/// the face's node masses shared among the particles that touch them in proportion to their
/// shape-function weights w_a (m_a,share = m_a w_a / sum over the node's contacts of w), so that
/// several particles on one node do not each move it as if alone. A rigid master has no mass:
/// m_eff is the particle's. The tangential force that would stop the relative sliding over the
/// step, f_t* = -m_eff v_t* / dt, is applied while |f_t*| <= mu_s f_n (stick), else
/// mu_d f_n along it (slip); sliding continues while |f_t*| > mu_d f_n. A bonded interface ties a
/// particle once it has touched: normal and tangential forces without limit, tension included.
/// Every pair force is applied once, with opposite signs on the particle and the face's nodes
/// (shape-function weights summing to one), so momentum is exchanged exactly. There is no
/// stiffness, hence no stability bound of its own: the coupled step is the bodies' step.

#include <coupling/contact.h>
#pragma GCC diagnostic ignored "-Wmissing-braces"

#include <omp.h>

#include <algorithm>
#include <cmath>

namespace coupling
{
  namespace
  {
    using V3 = std::array<double, 3>;
    inline double dot(const V3 &a, const V3 &b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

    /// A particle that ends the step in contact: its face, and its predicted relative motion.
    struct Candidate
    {
      std::array<double, 3> relative_velocity; ///< v* of the particle minus the contact point's [m/s]
      double predicted_gap;                   ///< g* [m]
    };
  } // namespace

  std::size_t PenaltyContact::apply_kinematic(const ContactParticles &pt, const ContactSurface &s, double dt,
                                              std::vector<double> &force_on_particles,
                                              std::vector<double> &force_on_nodes)
  {
    build_face_grid(s);
    const double mu_s = prm_.friction_static, mu_d = prm_.friction_dynamic;
    const long n      = static_cast<long>(pt.n);

    // 1. prediction and detection, per particle (no shared writes; contiguous chunks per thread)
    const std::size_t max_threads = static_cast<std::size_t>(omp_get_max_threads());
    if (contacts_.size() < max_threads)
      contacts_.resize(max_threads);
    for (auto &list : contacts_)
      list.clear();
    std::vector<std::vector<Candidate>> predicted(contacts_.size());
#pragma omp parallel
    {
      const long t = omp_get_thread_num(), nt = omp_get_num_threads();
      std::vector<Contact> &mine     = contacts_[t];
      std::vector<Candidate> &motion = predicted[t];
      for (long i = n * t / nt; i < n * (t + 1) / nt; ++i)
      {
        FrictionState &fr = friction_[i];
        if (surely_clear(pt.position + 3 * i))
        {
          fr = FrictionState{};
          continue;
        }
        const Hit hit = find_face(pt.position + 3 * i, s);
        if (hit.face < 0)
        {
          fr = FrictionState{};
          continue;
        }
        V3 vm{0, 0, 0};
        for (int a = 0; a < 4; ++a)
          for (int d = 0; d < 3; ++d)
            vm[d] += hit.weight[a] * s.velocity[3 * s.faces[hit.face][a] + d];
        V3 vr;
        for (int d = 0; d < 3; ++d)
        {
          const double f = pt.force ? pt.force[3 * i + d] : 0.0;
          vr[d]          = pt.velocity[3 * i + d] + dt * f / pt.mass[i] - vm[d];
        }
        const double g = hit.gap + dt * dot(vr, hit.normal);
        // a bond forms where the particle touches the face (at the start: the end layers at gap 0)
        const bool touches = g < 0 || (prm_.bonded && (fr.tied || hit.gap <= 0));
        if (!touches)
        {
          fr.sliding = false;
          continue;
        }
        mine.push_back({static_cast<std::int32_t>(i), hit, {0, 0, 0}});
        motion.push_back({vr, g});
      }
    }

    // 2. the node masses shared among the contacts on each node (in particle order)
    node_weight_.assign(s.n_nodes(), 0.0);
    for (const auto &list : contacts_)
      for (const Contact &c : list)
        for (int a = 0; a < 4; ++a)
          node_weight_[s.faces[c.hit.face][a]] += c.hit.weight[a];

    // 3. the forces, in particle order; each applied once to each side
    double fn_sum = 0, dissipated = 0;
    std::size_t n_contact = 0, n_slide = 0;
    for (std::size_t t = 0; t < contacts_.size(); ++t)
      for (std::size_t k = 0; k < contacts_[t].size(); ++k)
      {
        Contact &c               = contacts_[t][k];
        const Candidate &motion  = predicted[t][k];
        Hit &hit                 = c.hit;
        FrictionState &fr        = friction_[c.particle];
        double inverse_mass      = 1.0 / pt.mass[c.particle];
        for (int a = 0; a < 4; ++a)
        {
          const unsigned int node = s.faces[hit.face][a];
          const double m          = s.mass[node];
          if (m > 0 && hit.weight[a] > 0)
            inverse_mass += hit.weight[a] * node_weight_[node] / m; // w^2 / (m w / sum w)
        }
        const double m_eff = 1.0 / inverse_mass;
        const auto &nrm    = hit.normal;
        const V3 &vr       = motion.relative_velocity;
        double fn          = -m_eff * motion.predicted_gap / (dt * dt);
        if (!prm_.bonded)
          fn = std::max(fn, 0.0);
        const double vn = dot(vr, nrm);
        V3 vt{vr[0] - vn * nrm[0], vr[1] - vn * nrm[1], vr[2] - vn * nrm[2]};
        V3 ft{-m_eff * vt[0] / dt, -m_eff * vt[1] / dt, -m_eff * vt[2] / dt}; // stick
        if (prm_.bonded)
          fr.tied = true;
        else if (mu_s > 0 || mu_d > 0)
        {
          const double needed = std::sqrt(dot(ft, ft));
          const double limit  = (fr.sliding ? mu_d : mu_s) * fn;
          fr.sliding          = needed > limit && needed > 0;
          if (fr.sliding)
          {
            for (int d = 0; d < 3; ++d)
              ft[d] *= mu_d * fn / needed;
            ++n_slide;
          }
        }
        else
          ft = {0, 0, 0}; // free slip
        fr.tangential_force = ft;
        for (int d = 0; d < 3; ++d)
          c.force[d] = fn * nrm[d] + ft[d];
        // the interface's work over the step on the corrected relative motion (<= 0: what the
        // constraint and the friction take out)
        double work = 0;
        for (int d = 0; d < 3; ++d)
          work += c.force[d] * (vr[d] + dt * c.force[d] / m_eff) * dt;
        hit.normal_force = fn;
        hit.energy       = 0;
        hit.dissipated   = -work;
        ++n_contact;
      }
    for (const auto &list : contacts_)
      for (const Contact &c : list)
      {
        fn_sum += c.hit.normal_force;
        dissipated += c.hit.dissipated;
        for (int d = 0; d < 3; ++d)
          force_on_particles[3 * c.particle + d] += c.force[d];
        for (int a = 0; a < 4; ++a)
        {
          const unsigned int node_id = s.faces[c.hit.face][a];
          for (int d = 0; d < 3; ++d)
            force_on_nodes[3 * node_id + d] -= c.hit.weight[a] * c.force[d];
        }
      }
    normal_force_   = fn_sum;
    penalty_energy_ = 0;
    friction_dissipation_ += dissipated;
    n_sliding_ = n_slide;
    return n_contact;
  }
} // namespace coupling
