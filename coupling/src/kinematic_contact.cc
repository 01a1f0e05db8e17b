/// @file
/// PenaltyContact::apply for ContactMethod::kinematic: a predictor-corrector constraint, as the
/// constraint contacts of explicit codes do it. The step the rock would take without contact,
/// x + dt (v + dt f / m) (the body's symplectic Euler update), is predicted; for each particle
/// that would end the step inside a face (predicted gap g* < 0) the normal force that brings it
/// exactly onto the face is
///   f_n = -m_eff g* / dt^2,   1 / m_eff = 1 / m_particle + sum_a w_a^2 / m_a,share,
/// the face's node masses shared among the particles that touch them in proportion to their
/// shape-function weights w_a (on a deformable face, with ContactParameters::patch_points > 1,
/// the mean weights over the particle's patch, and the gap the patch's mean: share_among_nodes;
/// on an elastic cylinder platen the patch's points first moved by map_contact_point) (m_a,share = m_a w_a / sum over the node's contacts of w), so that
/// several particles on one node do not each move it as if alone; on a deformable face the
/// contacts are then corrected together (projected Jacobi sweeps, see step 3) until each ends
/// the step on the moved face. A rigid master has no mass: m_eff is the particle's, and one pass
/// is exact. A particle is held at r (n . F n) from the face, its half cell straining with it
/// (ContactParticles::deformation), taken at the step's end: n . F n moves with the particle's
/// own normal move (ContactParticles::self_gradient), which the end gap and the normal effective
/// mass, 1 / (sum_a w_a^2 / m_a,share + (1 - Contact::stretch_slope) / m_particle), include.
/// The tangential force that would stop the relative sliding over the step,
/// f_t* = -m_eff v_t* / dt, is applied while |f_t*| <= mu_s f_n (stick), else mu_d f_n along it
/// (slip); sliding continues while |f_t*| > mu_d f_n. A bonded interface ties a
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
  } // namespace

  void PenaltyContact::share_among_nodes(const double *x, Contact &c, const ContactSurface &s,
                                         const bool deformable) const
  {
    const auto add = [&c](const unsigned int node, const double w) {
      for (int a = 0; a < c.n_nodes; ++a)
        if (c.node[a] == node)
        {
          c.weight[a] += w;
          return;
        }
      c.node[c.n_nodes]   = node;
      c.weight[c.n_nodes] = w;
      ++c.n_nodes;
    };
    c.n_nodes = 0;
    const unsigned int points = deformable ? std::max(1u, prm_.patch_points) : 1u;
    if (points == 1)
    {
      for (int a = 0; a < 4; ++a)
        add(s.faces[c.hit.face][a], c.hit.weight[a]);
      return;
    }
    // two tangents of the face at the hit, the first along the lattice's x (or y) axis
    const V3 &nrm = c.hit.normal;
    V3 t1         = std::abs(nrm[0]) < 0.9 ? V3{1, 0, 0} : V3{0, 1, 0};
    const double along = dot(t1, nrm);
    for (int d = 0; d < 3; ++d)
      t1[d] -= along * nrm[d];
    const double norm = std::sqrt(dot(t1, t1));
    for (double &v : t1)
      v /= norm;
    const V3 t2{nrm[1] * t1[2] - nrm[2] * t1[1], nrm[2] * t1[0] - nrm[0] * t1[2], nrm[0] * t1[1] - nrm[1] * t1[0]};
    const double w   = 1.0 / (points * points);
    const Hit centre = c.hit;
    double gap       = 0;
    // the hit's nodes first (weight 0 until a sample lands on them): a sample whose face's nodes
    // would not fit in the list falls back onto them without growing it
    for (int k = 0; k < 4; ++k)
      add(s.faces[centre.face][k], 0.0);
    for (unsigned int i = 0; i < points; ++i)
      for (unsigned int j = 0; j < points; ++j)
      {
        const double a = ((i + 0.5) / points - 0.5) * 2.0 * prm_.radius;
        const double b = ((j + 0.5) / points - 0.5) * 2.0 * prm_.radius;
        double q[3] = {x[0] + a * t1[0] + b * t2[0], x[1] + a * t1[1] + b * t2[1], x[2] + a * t1[2] + b * t2[2]};
        map_contact_point(prm_, q[0], q[1]);
        // a sample point past every face (beyond the platen's rim) loads the hit's face
        Hit h = inside_face(q, s, centre.face);
        if (h.face < 0)
          h = find_face(q, s);
        const Hit &on     = (h.face >= 0 && c.n_nodes + 4 <= max_patch_nodes) ? h : centre;
        for (int k = 0; k < 4; ++k)
          add(s.faces[on.face][k], w * on.weight[k]);
        gap += w * on.gap;
      }
    // the gap is the patch's mean, as the patch's mean motion (the weights above) closes it
    c.hit.gap = gap;
  }

  std::size_t PenaltyContact::apply_kinematic(const ContactParticles &pt, const ContactSurface &s, double dt,
                                              std::vector<double> &force_on_particles,
                                              std::vector<double> &force_on_nodes)
  {
    build_face_grid(s);
    // a deformable face: the same on every process (the face is whole on each)
    const bool deformable = std::any_of(s.mass.begin(), s.mass.end(), [](double m) { return m > 0; });
    const double mu_s = prm_.friction_static, mu_d = prm_.friction_dynamic;
    const long n      = static_cast<long>(pt.n);

    // 1. prediction and detection, per particle (no shared writes; contiguous chunks per thread)
    const std::size_t max_threads = static_cast<std::size_t>(omp_get_max_threads());
    if (contacts_.size() < max_threads)
      contacts_.resize(max_threads);
    for (auto &list : contacts_)
      list.clear();
    // per contact: v* of the particle minus the contact point's [m/s]
    std::vector<std::vector<V3>> predicted(contacts_.size());
#pragma omp parallel
    {
      const long t = omp_get_thread_num(), nt = omp_get_num_threads();
      std::vector<Contact> &mine     = contacts_[t];
      std::vector<V3> &motion = predicted[t];
      for (long i = n * t / nt; i < n * (t + 1) / nt; ++i)
      {
        FrictionState &fr = friction_[i];
        if (surely_clear(pt.position + 3 * i))
        {
          fr = FrictionState{};
          continue;
        }
        // on a deformable cylinder platen, the point where a uniform stress would put the
        // particle's load (map_contact_point: the ends' discrete areas, the rim polygon)
        double at[3] = {pt.position[3 * i], pt.position[3 * i + 1], pt.position[3 * i + 2]};
        if (deformable)
          map_contact_point(prm_, at[0], at[1]);
        Hit hit = find_face(at, s);
        if (hit.face < 0)
        {
          fr = FrictionState{};
          continue;
        }
        Contact c{static_cast<std::int32_t>(i), hit, {0, 0, 0}};
        share_among_nodes(pt.position + 3 * i, c, s, deformable);
        if (pt.deformation) // the particle's half cell strains with it: held at r (n . F n)
        {
          const double *F = pt.deformation + 9 * i;
          const auto &nn  = c.hit.normal;
          double stretch  = 0;
          for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b)
              stretch += nn[a] * F[3 * a + b] * nn[b];
          c.hit.gap += prm_.radius * (1.0 - stretch);
          // the stretch at the step's end: its change with the particle's own normal move,
          // d(n . F n) = -(n . dx)(n . g); a particle whose stretch would fall as it nears the face
          // (none at a face: g points into the body) is held at the lagged distance
          if (pt.self_gradient)
          {
            const double *g = pt.self_gradient + 3 * i;
            c.stretch_slope = std::min(0.0, -prm_.radius * dot(nn, V3{g[0], g[1], g[2]}));
          }
        }
        // the contact point's velocity: the patch's mean, with the weights the force is shared by
        V3 vm{0, 0, 0};
        for (int a = 0; a < c.n_nodes; ++a)
          for (int d = 0; d < 3; ++d)
            vm[d] += c.weight[a] * s.velocity[3 * c.node[a] + d];
        V3 vr, vp;
        for (int d = 0; d < 3; ++d)
        {
          const double f = pt.force ? pt.force[3 * i + d] : 0.0;
          vp[d]          = pt.velocity[3 * i + d] + dt * f / pt.mass[i];
          vr[d]          = vp[d] - vm[d];
        }
        c.own_speed    = dot(vp, c.hit.normal);
        const double g = c.hit.gap + dt * dot(vr, c.hit.normal) - c.stretch_slope * dt * c.own_speed;
        // a bond forms where the particle touches the face (at the start: the end layers at gap 0)
        const bool touches = g < 0 || (prm_.bonded && (fr.tied || c.hit.gap <= 0));
        if (!touches)
        {
          fr.sliding = false;
          continue;
        }
        mine.push_back(c);
        motion.push_back(vr);
      }
    }

    // 2. the node masses shared among the contacts on each node (in particle order)
    node_weight_.assign(s.n_nodes(), 0.0);
    for (const auto &list : contacts_)
      for (const Contact &c : list)
        for (int a = 0; a < c.n_nodes; ++a)
          node_weight_[c.node[a]] += c.weight[a];
    if (deformable && reduce_sum_) // the other processes' contacts on the same nodes
      reduce_sum_(node_weight_.data(), static_cast<int>(node_weight_.size()));

    // 3. the forces. Contact k moves relative to its face over the step by
    //      D_k = dt v*_k + dt^2 f_k / m_k - sum_a w_ka dt^2 F_a / M_a,   F_a = -sum_j w_ja f_j,
    //    F_a being the force on face node a. The constraint wants the end gap g_k + n_k . D_k = 0
    //    (>= 0 with no force where it would have to pull, unless bonded) and, where the contact
    //    sticks, no tangential D_k. On a rigid face (M = infinity) one pass with the particle's
    //    mass is exact. On a deformable face the contacts are coupled through the nodes they
    //    share: projected Jacobi sweeps, each contact corrected with its effective mass m_eff
    //    (the node masses shared by weight: a diagonal no smaller than the coupling's row sums,
    //    so the sweeps converge; a uniform push converges in one), until every end gap and stuck
    //    slip is below ContactParameters::tolerance (1e-6) of the contact radius.
    std::vector<Contact *> all;
    std::vector<const V3 *> motion;
    for (std::size_t t = 0; t < contacts_.size(); ++t)
      for (std::size_t k = 0; k < contacts_[t].size(); ++k)
      {
        all.push_back(&contacts_[t][k]);
        motion.push_back(&predicted[t][k]);
      }
    const std::size_t n_all = all.size();
    // m_eff: tangential; m_eff_normal: the particle's share (1 - stretch_slope) / m, its own move
    // also moving the distance it is held at
    std::vector<double> m_eff(n_all), m_eff_normal(n_all);
    for (std::size_t k = 0; k < n_all; ++k)
    {
      const Contact &c    = *all[k];
      double inverse_mass = 1.0 / pt.mass[c.particle];
      for (int a = 0; a < c.n_nodes; ++a)
      {
        const unsigned int node = c.node[a];
        const double m          = s.mass[node];
        if (m > 0 && c.weight[a] > 0)
          inverse_mass += c.weight[a] * node_weight_[node] / m; // w^2 / (m w / sum w)
      }
      m_eff[k]        = 1.0 / inverse_mass;
      m_eff_normal[k] = 1.0 / (inverse_mass - c.stretch_slope / pt.mass[c.particle]);
    }
    // the force that the correction `trial` asks for, within the interface's law: no pull unless
    // bonded, the tangential part within mu f_n (the static limit unless the particle slid in
    // the last step); `slid` says whether the limit cut it
    auto project = [&](const std::size_t k, const V3 &trial, bool &slid) {
      const auto &nrm = all[k]->hit.normal;
      double fn       = dot(trial, nrm);
      V3 ft{trial[0] - fn * nrm[0], trial[1] - fn * nrm[1], trial[2] - fn * nrm[2]};
      slid = false;
      if (!prm_.bonded)
      {
        fn = std::max(fn, 0.0);
        if (mu_s > 0 || mu_d > 0)
        {
          const double needed = std::sqrt(dot(ft, ft));
          const double limit  = (friction_[all[k]->particle].sliding ? mu_d : mu_s) * fn;
          slid                = needed > limit && needed > 0;
          if (slid)
            for (int d = 0; d < 3; ++d)
              ft[d] *= mu_d * fn / needed;
        }
        else
          ft = {0, 0, 0}; // free slip
      }
      return V3{fn * nrm[0] + ft[0], fn * nrm[1] + ft[1], fn * nrm[2] + ft[2]};
    };
    std::vector<char> slid(n_all, 0);
    std::vector<V3> moved(n_all); // D_k
    std::vector<double> moved_own(n_all); // n_k . the particle's own move over the step
    // the end gap of contact k for the relative motion d and the particle's own normal move
    auto end_gap = [&](const std::size_t k, const double dn, const double own_n) {
      return all[k]->hit.gap + dn - all[k]->stretch_slope * own_n;
    };
    // the correction of contact k for the relative motion `d` it would make: close the end gap
    // and, unless it slides, stop the tangential motion
    auto correct = [&](const std::size_t k, const V3 &force, const V3 &d) {
      const Hit &hit  = all[k]->hit;
      const auto &nrm = hit.normal;
      const double dn  = dot(d, nrm);
      const double c   = m_eff[k] / (dt * dt);
      const double cn  = m_eff_normal[k] / (dt * dt);
      const double end = end_gap(k, dn, moved_own[k]);
      V3 trial;
      for (int d_ = 0; d_ < 3; ++d_)
        trial[d_] = force[d_] - cn * end * nrm[d_] - c * (d[d_] - dn * nrm[d_]);
      bool s_ = false;
      const V3 f = project(k, trial, s_);
      slid[k]    = s_;
      return f;
    };
    // the first pass: each contact alone against its share of the nodes
    for (std::size_t k = 0; k < n_all; ++k)
    {
      const V3 &vr = *motion[k];
      moved[k]     = {dt * vr[0], dt * vr[1], dt * vr[2]};
      moved_own[k] = dt * all[k]->own_speed;
      all[k]->force = correct(k, {0, 0, 0}, moved[k]);
    }
    // D_k for the current forces
    std::vector<double> node_shift(deformable ? 3 * s.n_nodes() : 0);
    auto relative_motion = [&]() {
      if (deformable)
      {
        std::fill(node_shift.begin(), node_shift.end(), 0.0);
        for (std::size_t k = 0; k < n_all; ++k)
          for (int a = 0; a < all[k]->n_nodes; ++a)
          {
            const unsigned int node = all[k]->node[a];
            if (s.mass[node] > 0)
              for (int d = 0; d < 3; ++d)
                node_shift[3 * node + d] -= dt * dt * all[k]->weight[a] * all[k]->force[d] / s.mass[node];
          }
        if (reduce_sum_) // the nodes also move under the other processes' contacts
          reduce_sum_(node_shift.data(), static_cast<int>(node_shift.size()));
      }
      for (std::size_t k = 0; k < n_all; ++k)
      {
        const V3 &vr    = *motion[k];
        const double mp = pt.mass[all[k]->particle];
        for (int d = 0; d < 3; ++d)
          moved[k][d] = dt * vr[d] + dt * dt * all[k]->force[d] / mp;
        moved_own[k] = dt * all[k]->own_speed + dt * dt * dot(all[k]->force, all[k]->hit.normal) / mp;
        if (deformable)
          for (int a = 0; a < all[k]->n_nodes; ++a)
          {
            const unsigned int node = all[k]->node[a];
            for (int d = 0; d < 3; ++d)
              moved[k][d] -= all[k]->weight[a] * node_shift[3 * node + d];
          }
      }
    };
    relative_motion();
    if (deformable)
    {
      const double tolerance = prm_.tolerance * prm_.radius;
      const int max_sweeps   = 200;
      std::vector<V3> next(n_all);
      for (int sweep = 0; sweep < max_sweeps; ++sweep)
      {
        double worst = 0;
        for (std::size_t k = 0; k < n_all; ++k)
        {
          const Hit &hit   = all[k]->hit;
          const double dn  = dot(moved[k], hit.normal);
          const double end = end_gap(k, dn, moved_own[k]);
          const double fn  = dot(all[k]->force, hit.normal);
          // the end gap where there is a force (or the particle would end inside)
          if (fn != 0 || end < 0)
            worst = std::max(worst, std::abs(end));
          if (!slid[k] && (prm_.bonded || mu_s > 0 || mu_d > 0) && fn != 0)
          {
            V3 t{moved[k][0] - dn * hit.normal[0], moved[k][1] - dn * hit.normal[1], moved[k][2] - dn * hit.normal[2]};
            worst = std::max(worst, std::sqrt(dot(t, t)));
          }
        }
        if (reduce_max_) // every process sweeps as long as any needs it
          worst = reduce_max_(worst);
        if (worst < tolerance)
          break;

        for (std::size_t k = 0; k < n_all; ++k)
          next[k] = correct(k, all[k]->force, moved[k]);
        for (std::size_t k = 0; k < n_all; ++k)
          all[k]->force = next[k];
        relative_motion();
      }
    }

    double fn_sum = 0, dissipated = 0;
    std::size_t n_contact = 0, n_slide = 0;
    for (std::size_t k = 0; k < n_all; ++k)
    {
      Contact &c        = *all[k];
      FrictionState &fr = friction_[c.particle];
      const double fn   = dot(c.force, c.hit.normal);
      if (prm_.bonded)
        fr.tied = true;
      else
      {
        fr.sliding = slid[k] != 0;
        n_slide += fr.sliding ? 1 : 0;
      }
      fr.tangential_force = {c.force[0] - fn * c.hit.normal[0], c.force[1] - fn * c.hit.normal[1],
                             c.force[2] - fn * c.hit.normal[2]};
      // the interface's work over the step on the relative motion (<= 0: what the constraint
      // and the friction take out)
      c.hit.normal_force = fn;
      c.hit.energy       = 0;
      c.hit.dissipated   = -dot(c.force, moved[k]);
      ++n_contact;
    }
    for (const auto &list : contacts_)
      for (const Contact &c : list)
      {
        fn_sum += c.hit.normal_force;
        dissipated += c.hit.dissipated;
        for (int d = 0; d < 3; ++d)
          force_on_particles[3 * c.particle + d] += c.force[d];
        for (int a = 0; a < c.n_nodes; ++a)
          for (int d = 0; d < 3; ++d)
            force_on_nodes[3 * c.node[a] + d] -= c.weight[a] * c.force[d];
      }
    normal_force_   = fn_sum;
    penalty_energy_ = 0;
    friction_dissipation_ += dissipated;
    n_sliding_ = n_slide;
    return n_contact;
  }
} // namespace coupling
