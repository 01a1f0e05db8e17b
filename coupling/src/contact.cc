#include <coupling/contact.h>
// The V3 / std::array brace initialisers are intended; deal.II's flags turn -Wmissing-braces on.
#pragma GCC diagnostic ignored "-Wmissing-braces"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace coupling
{
  namespace
  {
    using V3 = std::array<double, 3>;

    inline V3 sub(const V3 &a, const V3 &b)
    {
      return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
    }
    inline double dot(const V3 &a, const V3 &b)
    {
      return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    }
    inline V3 cross(const V3 &a, const V3 &b)
    {
      return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    }
    inline V3 node(const ContactSurface &s, unsigned int k)
    {
      return {s.position[3 * k], s.position[3 * k + 1], s.position[3 * k + 2]};
    }

    /// Bilinear shape functions of a quad with nodes counter-clockwise at
    /// (-1,-1),(1,-1),(1,1),(-1,1).
    inline std::array<double, 4> shape(double xi, double eta)
    {
      return {0.25 * (1 - xi) * (1 - eta), 0.25 * (1 + xi) * (1 - eta), 0.25 * (1 + xi) * (1 + eta),
              0.25 * (1 - xi) * (1 + eta)};
    }

    /// The bilinear face through p0..p3 at (xi, eta): its point xs and tangents dxi, deta.
    inline void bilinear_frame(const V3 &p0, const V3 &p1, const V3 &p2, const V3 &p3, double xi, double eta,
                               V3 &xs, V3 &dxi, V3 &deta)
    {
      const auto N = shape(xi, eta);
      for (int d = 0; d < 3; ++d)
      {
        xs[d]   = N[0] * p0[d] + N[1] * p1[d] + N[2] * p2[d] + N[3] * p3[d];
        dxi[d]  = 0.25 * ((1 - eta) * (p1[d] - p0[d]) + (1 + eta) * (p2[d] - p3[d]));
        deta[d] = 0.25 * ((1 - xi) * (p3[d] - p0[d]) + (1 + xi) * (p2[d] - p1[d]));
      }
    }

    /// How far outside the reference square a projection may fall and still count: particles on a
    /// shared edge must find one of the two faces despite round-off.
    constexpr double edge_tolerance = 1e-9;
  } // namespace

  void map_onto_rim_polygon(const ContactParameters &p, double &x, double &y)
  {
    const std::vector<double> &angle = p.rim_angles;
    if (angle.size() < 3)
      return;
    const double r = std::hypot(x, y);
    if (!(r > 0))
      return;
    const double theta = std::atan2(y, x);
    // the sector [angle[k], angle[k + 1]) holding theta; the last one wraps through pi
    const std::size_t k = static_cast<std::size_t>(std::upper_bound(angle.begin(), angle.end(), theta) - angle.begin());
    const double lo = k == 0 ? angle.back() - 2 * M_PI : angle[k - 1];
    const double hi = k == angle.size() ? angle.front() + 2 * M_PI : angle[k];
    const double a = 0.5 * (hi - lo), middle = lo + a;
    double u       = theta - middle;
    u -= 2 * M_PI * std::round(u / (2 * M_PI));
    const double phi = std::atan(std::tan(a) * u / a);
    const double rho = r * std::cos(a) / std::cos(phi);
    x                = rho * std::cos(middle + phi);
    y                = rho * std::sin(middle + phi);
  }

  void map_contact_point(const ContactParameters &p, double &x, double &y)
  {
    const std::vector<double> &to = p.face_radius_mapped;
    const double r                = std::hypot(x, y);
    const double at               = p.face_remap_step > 0 ? r / p.face_remap_step : 0.0;
    if (to.size() >= 2 && r > 0 && at < to.size() - 1)
    {
      const std::size_t k = static_cast<std::size_t>(at);
      const double t      = at - k;
      const double scale  = ((1 - t) * to[k] + t * to[k + 1]) / r;
      x *= scale;
      y *= scale;
    }
    map_onto_rim_polygon(p, x, y);
  }

  double stable_contact_stiffness(double slave_mass, double master_mass, double dt)
  {
    const double m_eff =
      master_mass > 0 ? slave_mass * master_mass / (slave_mass + master_mass) : slave_mass;
    return 4.0 * m_eff / (dt * dt);
  }

  double coupled_time_step(double dt_alone, double stiffness_scale)
  {
    return dt_alone / std::sqrt(1.0 + stiffness_scale);
  }

  PenaltyContact::PenaltyContact(const ContactParameters &parameters, std::size_t n_particles)
      : prm_(parameters)
      , friction_(n_particles)
  {}

  void PenaltyContact::find_interior_edges(const ContactSurface &s)
  {
    if (s.faces == edge_faces_)
      return;
    edge_faces_ = s.faces;
    // (smaller node, larger node, face, edge), sorted: an edge listed twice is shared
    std::vector<std::array<unsigned int, 4>> e;
    e.reserve(4 * s.faces.size());
    for (std::size_t f = 0; f < s.faces.size(); ++f)
      for (unsigned int k = 0; k < 4; ++k)
      {
        const unsigned int a = s.faces[f][k], b = s.faces[f][(k + 1) % 4];
        e.push_back({std::min(a, b), std::max(a, b), unsigned(f), k});
      }
    std::sort(e.begin(), e.end());
    interior_edge_.assign(s.faces.size(), {{false, false, false, false}});
    for (std::size_t i = 0; i + 1 < e.size(); ++i)
      if (e[i][0] == e[i + 1][0] && e[i][1] == e[i + 1][1])
      {
        interior_edge_[e[i][2]][e[i][3]]         = true;
        interior_edge_[e[i + 1][2]][e[i + 1][3]] = true;
      }
  }

  void PenaltyContact::build_face_grid(const ContactSurface &s)
  {
    find_interior_edges(s);
    const double inflate = 2.0 * prm_.radius;
    V3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    double largest = 0;
    std::vector<std::array<double, 6>> box(s.faces.size());
    for (std::size_t f = 0; f < s.faces.size(); ++f)
    {
      std::array<double, 6> b{1e300, 1e300, 1e300, -1e300, -1e300, -1e300};
      for (unsigned int k : s.faces[f])
        for (int d = 0; d < 3; ++d)
        {
          b[d]     = std::min(b[d], s.position[3 * k + d] - inflate);
          b[3 + d] = std::max(b[3 + d], s.position[3 * k + d] + inflate);
        }
      for (int d = 0; d < 3; ++d)
      {
        lo[d]   = std::min(lo[d], b[d]);
        hi[d]   = std::max(hi[d], b[3 + d]);
        largest = std::max(largest, b[3 + d] - b[d]);
      }
      box[f] = b;
    }
    face_box_    = box;
    grid_origin_ = lo;
    grid_top_    = hi;
    grid_cell_   = std::max(largest, 1e-12);
    for (int d = 0; d < 3; ++d)
      grid_n_[d] = std::max(1, static_cast<int>(std::ceil((hi[d] - lo[d]) / grid_cell_)));
    const std::size_t n_cells = std::size_t(grid_n_[0]) * grid_n_[1] * grid_n_[2];
    cell_start_.assign(n_cells + 1, 0);
    auto cell_range = [&](const std::array<double, 6> &b, std::array<int, 6> &r) {
      for (int d = 0; d < 3; ++d)
      {
        r[d]     = std::clamp(int((b[d] - lo[d]) / grid_cell_), 0, grid_n_[d] - 1);
        r[3 + d] = std::clamp(int((b[3 + d] - lo[d]) / grid_cell_), 0, grid_n_[d] - 1);
      }
    };
    auto for_cells = [&](const std::array<int, 6> &r, auto &&fn) {
      for (int k = r[2]; k <= r[5]; ++k)
        for (int j = r[1]; j <= r[4]; ++j)
          for (int i = r[0]; i <= r[3]; ++i)
            fn((std::size_t(k) * grid_n_[1] + j) * grid_n_[0] + i);
    };
    std::array<int, 6> r;
    for (const auto &b : box)
    {
      cell_range(b, r);
      for_cells(r, [&](std::size_t c) { ++cell_start_[c + 1]; });
    }
    for (std::size_t c = 0; c < n_cells; ++c)
      cell_start_[c + 1] += cell_start_[c];
    cell_faces_.assign(cell_start_.back(), -1);
    std::vector<int> fill(cell_start_.begin(), cell_start_.end() - 1);
    for (std::size_t f = 0; f < box.size(); ++f)
    {
      cell_range(box[f], r);
      for_cells(r, [&](std::size_t c) { cell_faces_[fill[c]++] = int(f); });
    }
  }

  bool PenaltyContact::closest_point(const std::array<double, 3> &p, const ContactSurface &s, const int f,
                                     double &xi, double &eta) const
  {
    const auto &fn = s.faces[f];
    const V3 p0 = node(s, fn[0]), p1 = node(s, fn[1]), p2 = node(s, fn[2]), p3 = node(s, fn[3]);
    // Newton iterations for the closest point x(xi, eta) of the bilinear face.
    V3 xs{}, dxi{}, deta{};
    for (int it = 0; it < 8; ++it)
    {
      bilinear_frame(p0, p1, p2, p3, xi, eta, xs, dxi, deta);
      const V3 r     = sub(p, xs);
      const double a = dot(dxi, dxi), b = dot(dxi, deta), e = dot(deta, deta);
      const double g1 = dot(dxi, r), g2 = dot(deta, r);
      const double det = a * e - b * b;
      if (!(det > 0))
        return false;
      const double dx1 = (e * g1 - b * g2) / det, dx2 = (a * g2 - b * g1) / det;
      xi += dx1;
      eta += dx2;
      if (std::abs(dx1) + std::abs(dx2) < 1e-13)
        return true;
    }
    return false;
  }

  bool PenaltyContact::face_point(const ContactSurface &s, const int f, const double xi, const double eta,
                                  std::array<double, 3> &xs, std::array<double, 3> &n) const
  {
    const auto &fn = s.faces[f];
    const V3 p0 = node(s, fn[0]), p1 = node(s, fn[1]), p2 = node(s, fn[2]), p3 = node(s, fn[3]);
    V3 dxi, deta;
    bilinear_frame(p0, p1, p2, p3, xi, eta, xs, dxi, deta);
    n               = cross(dxi, deta);
    const double nn = std::sqrt(dot(n, n));
    if (!(nn > 0))
      return false;
    for (double &v : n)
      v /= nn;
    return true;
  }

  PenaltyContact::Hit PenaltyContact::inside_face(const double *x, const ContactSurface &s, const int f) const
  {
    // only a flat master (no face of its tiling overlaps another's projection: one face holds a
    // point's projection), inside the face by a margin: there find_face's search ends on this
    // face with these very numbers
    Hit hit;
    if (!prm_.flat_master || f < 0)
      return hit;
    const V3 p{x[0], x[1], x[2]};
    if (outside_face_box(p, f))
      return hit;
    double xi = 0, eta = 0;
    if (!closest_point(p, s, f, xi, eta))
      return hit;
    // Two faces that meet at a crease hold the projections of the points above it (r over the
    // face) within about r times the angle between them of the crease: under load a platen's
    // faces tilt by about 1e-4 against each other, so 1e-4 of the face; 1e-2 keeps far off.
    const double margin = 1e-2;
    if (!(std::abs(xi) < 1 - margin && std::abs(eta) < 1 - margin))
      return hit;
    V3 xs, n;
    if (!face_point(s, f, xi, eta, xs, n))
      return hit;
    const double distance = dot(sub(p, xs), n);
    if (out_of_reach(distance))
      return hit;
    hit.face   = f;
    hit.gap    = distance - prm_.radius;
    hit.weight = shape(xi, eta);
    hit.normal = n;
    return hit;
  }

  PenaltyContact::Hit PenaltyContact::find_face(const double *x, const ContactSurface &s) const
  {
    Hit best;
    // a flat or concave master takes only faces whose inflated box (with the slack below) holds
    // the particle: beyond the boxes' upper corner none does. The grid's last cells reach further
    // (a flat platen's one cell layer is a face wide across its plane), so surely_clear, not the
    // cell index, turns away the particles behind it.
    if (surely_clear(x))
      return best;
    int idx[3];
    for (int d = 0; d < 3; ++d)
    {
      idx[d] = static_cast<int>(std::floor((x[d] - grid_origin_[d]) / grid_cell_));
      if (idx[d] < 0 || idx[d] >= grid_n_[d])
        return best;
    }
    const std::size_t c = (std::size_t(idx[2]) * grid_n_[1] + idx[1]) * grid_n_[0] + idx[0];
    const V3 p{x[0], x[1], x[2]};
    // flat or concave master: the best face reached across an interior edge, used only when no
    // face contains the particle's projection (see below)
    Hit across;
    // kinematic, flat or concave master: the face whose outer edge the particle is past by less
    // than r or ContactParameters::rim_reach (below), used only when neither of the above holds it
    Hit over_rim;
    for (int q = cell_start_[c]; q < cell_start_[c + 1]; ++q)
    {
      const int f    = cell_faces_[q];
      // a flat or concave master (a platen) takes a face only with the particle within 2 r of
      // its plane and over the face, so within the face's box inflated by 2 r: skip the Newton
      // iterations for any other face (1 % margin on the inflation for the closest-point
      // iteration's tolerance). A convex master also uses faces the particle is clear of.
      if (!prm_.convex_master && outside_face_box(p, f))
        continue;
      double xi = 0, eta = 0;
      const bool converged = closest_point(p, s, f, xi, eta);
      // outside the face: skipped, except on a convex master across an edge shared with another
      // face (an apex or ridge line), where the particle takes the face's plane clamped to that
      // edge (below): in the wedge of space between two faces' normals at a convex edge a particle
      // projects onto neither face and would feel no force until the edge had passed its centre,
      // then the full penalty at once (energy created from nothing)
      // A flat or concave master has the same gap wherever two of its faces meet at a crease
      // that is convex towards the rock (a ridge): the closest points of a particle over the
      // crease lie outside both faces, shifted off the crease by about r times the angle between
      // the faces (the particle's centre is r above the surface). A platen face is flat at the
      // start, but under load its quads warp by micrometres, and a particle over a mesh vertex
      // that sank less than its neighbours found no face and felt no force: under an elastic
      // steel platen such UCS particles lost their contact, went into tension and failed at 6 %
      // of the strength. So a flat or concave master keeps the faces reached across an interior
      // edge, clamped to that edge and within r of it along the face, as a fallback taken only
      // when no face contains the particle's projection (where one does, nothing changes).
      const bool out_xi = std::abs(xi) > 1 + edge_tolerance, out_eta = std::abs(eta) > 1 + edge_tolerance;
      // An iteration that stopped unconverged inside the face has not found the particle's
      // projection there: a point far past a face (a patch sample 5 mm from its face, seen from
      // the face's far corner) can stop inside after 8 steps, and it then took the face's
      // nodes 11 mm away, its gap as if over the face, against the face that does hold it.
      // Such a face holds no projection (a flat or concave master; a convex one treats a point
      // that is not the closest below).
      if (!converged && !(out_xi || out_eta) && !prm_.convex_master)
        continue;
      bool past_rim     = false;
      if (out_xi || out_eta)
      {
        // quad edges 0: eta = -1, 1: xi = +1, 2: eta = +1, 3: xi = -1
        const auto &inner = interior_edge_[f];
        const bool ok     = (!out_xi || inner[xi > 0 ? 1 : 3]) && (!out_eta || inner[eta > 0 ? 2 : 0]);
        // Past the master's outer edge: the kinematic contact of a flat or concave master keeps
        // the face within r (or rim_reach) of that edge (the last fallback below). The mesh's outer edge is a
        // polygon inside the platen's circle (a 50 mm platen with 16 rim vertices: 0.48 mm in at
        // the chords' middles), and the rim particles of a specimen as wide as its platen lay
        // over no face: unsupported, they failed at 28 % of the strength.
        if (!ok && (prm_.convex_master || prm_.method != ContactMethod::kinematic))
          continue;
        past_rim = !ok;
      }
      xi  = std::clamp(xi, -1.0, 1.0);
      eta = std::clamp(eta, -1.0, 1.0);
      V3 xs, n;
      if (!face_point(s, f, xi, eta, xs, n))
        continue;
      const auto N          = shape(xi, eta);
      const V3 r_clamped    = sub(p, xs);
      const double distance = dot(r_clamped, n);
      if (out_xi || out_eta)
      {
        // a convex master counts a face reached across an edge within a particle diameter of
        // that edge; a flat or concave one within r of it along the face (tangentially)
        const double t2 = dot(r_clamped, r_clamped) - distance * distance;
        const double reach = past_rim ? std::max(prm_.radius, prm_.rim_reach) : prm_.radius;
        if (prm_.convex_master ? dot(r_clamped, r_clamped) > 4.0 * prm_.radius * prm_.radius : t2 > reach * reach)
          continue;
      }
      else if (prm_.convex_master)
      {
        // inside the face only if the iteration found the closest point (r along the normal):
        // on a warped quad (a cone's flank meshed with bilinear faces) the Gauss-Newton
        // iteration above does not converge for a particle far from the face and may stop at
        // (xi, eta) inside it, with r mostly tangential and a plane distance that says
        // "penetrated" for a particle millimetres away on the far side of the cone: a sharp cone
        // 2 mm into basalt at 1.5 mm spacing gave eight such particles 0.8 mm of penalty
        // penetration at once, 170 J from nothing (cases/indentation/README.md). A face whose
        // point is not the closest counts only within a particle diameter, as across an edge.
        const double r2 = dot(r_clamped, r_clamped);
        const double t2 = r2 - distance * distance;
        if (t2 > 1e-4 * prm_.radius * prm_.radius && r2 > 4.0 * prm_.radius * prm_.radius)
          continue;
      }
      // a particle more than one diameter behind the face is not in contact with it (it belongs to
      // another face or has tunnelled, which the time-step bound prevents)
      // (a convex master keeps the faces the particle is clear of: the largest plane distance
      // decides, and one face plane the particle is more than r in front of separates it from the
      // whole body)
      // The kinematic method also needs the particles in front of the face (gap > 0) that the
      // step may bring into it, and above all the ones it left exactly on the face at the last
      // step (gap 0 to round-off): cut at gap > 0, such a particle was found on one step and
      // missed on the next, flew into the face with a whole step of its internal force and was
      // thrown back: energy from nothing at every platen-mesh vertex line (a 2.5 mm elastic UCS
      // blew up). A step moves a particle far less than r (the CFL bound), so r of reach holds.
      if (out_of_reach(distance))
        continue;
      const double gap = distance - prm_.radius;
      Hit &slot = past_rim ? over_rim : (!prm_.convex_master && (out_xi || out_eta)) ? across : best;
      if (slot.face < 0 || (prm_.convex_master ? gap > slot.gap : gap < slot.gap))
      {
        slot.face   = f;
        slot.gap    = gap;
        slot.weight = N;
        slot.normal = n;
      }
    }
    return best.face >= 0 ? best : across.face >= 0 ? across : over_rim;
  }

  std::size_t PenaltyContact::apply(const ContactParticles &pt, const ContactSurface &s, double dt,
                                    std::vector<double> &force_on_particles,
                                    std::vector<double> &force_on_nodes)
  {
    if (prm_.method == ContactMethod::kinematic)
      return apply_kinematic(pt, s, dt, force_on_particles, force_on_nodes);
    build_face_grid(s);
    const double k0   = prm_.stiffness;
    const double mu_s = prm_.friction_static, mu_d = prm_.friction_dynamic;
    const long n  = static_cast<long>(pt.n);
    double fn_sum = 0, energy = 0, dissipated = 0;
    std::size_t n_contact = 0, n_slide = 0;

    // Gather: each particle finds its face and its force independently (no shared writes);
    // each thread keeps the contacts of its contiguous chunk. The floating-point sums are taken
    // afterwards in particle order: an OpenMP reduction combines the threads' partial sums in
    // arrival order, which is not reproducible bitwise.
    const std::size_t max_threads = static_cast<std::size_t>(omp_get_max_threads());
    if (contacts_.size() < max_threads)
      contacts_.resize(max_threads);
    for (auto &list : contacts_)
      list.clear();
#pragma omp parallel reduction(+ : n_contact, n_slide)
    {
      const long t = omp_get_thread_num(), nt = omp_get_num_threads();
      std::vector<Contact> &mine = contacts_[t];
      for (long i = n * t / nt; i < n * (t + 1) / nt; ++i)
      {
        FrictionState &fr = friction_[i];
        if (surely_clear(pt.position + 3 * i))
        {
          fr = FrictionState{};
          continue;
        }
        Hit hit = find_face(pt.position + 3 * i, s);
        if (hit.face < 0 || hit.gap >= 0)
        {
          fr = FrictionState{};
          continue;
        }
        const double k = stiffness_factor_.empty() ? k0 : k0 * stiffness_factor_[i];
        std::array<double, 3> f{0, 0, 0};
        ++n_contact;
        const double fn  = -k * hit.gap;
        hit.normal_force = fn;
        hit.energy       = 0.5 * k * hit.gap * hit.gap;
        const auto &nrm  = hit.normal;
        // velocity of the contact point on the face
        V3 vm{0, 0, 0};
        for (int a = 0; a < 4; ++a)
          for (int d = 0; d < 3; ++d)
            vm[d] += hit.weight[a] * s.velocity[3 * s.faces[hit.face][a] + d];
        V3 vr{pt.velocity[3 * i] - vm[0], pt.velocity[3 * i + 1] - vm[1],
              pt.velocity[3 * i + 2] - vm[2]};
        const double vn = dot(vr, nrm);
        V3 vt{vr[0] - vn * nrm[0], vr[1] - vn * nrm[1], vr[2] - vn * nrm[2]};
        V3 ft{0, 0, 0};
        if (mu_s > 0 || mu_d > 0)
        {
          // elastic stick spring (regularised stick), rotated into the current tangent plane
          V3 trial        = fr.tangential_force;
          const double tn = dot(trial, nrm);
          for (int d = 0; d < 3; ++d)
            trial[d] += -tn * nrm[d] - k * vt[d] * dt;
          const double t_norm = std::sqrt(dot(trial, trial));
          const double limit  = (fr.sliding ? mu_d : mu_s) * fn;
          if (t_norm > limit && t_norm > 0)
          {
            for (int d = 0; d < 3; ++d)
              ft[d] = trial[d] * (mu_d * fn / t_norm);
            fr.sliding = true;
            ++n_slide;
            // friction dissipation: -f_t . v_t dt (f_t opposes the slip)
            hit.dissipated = std::max(0.0, -dot(ft, vt) * dt);
          }
          else
          {
            ft         = trial;
            fr.sliding = false;
          }
          fr.tangential_force = ft;
          hit.energy += 0.5 * dot(ft, ft) / k; // the stick spring's elastic energy
        }
        for (int d = 0; d < 3; ++d)
          f[d] = fn * nrm[d] + ft[d];
        mine.push_back({static_cast<std::int32_t>(i), hit, f});
      }
    }

    // Scatter in particle order: deterministic, and each force applied once to each side.
    for (const auto &list : contacts_)
      for (const Contact &c : list)
      {
        const Hit &hit = c.hit;
        fn_sum += hit.normal_force;
        energy += hit.energy;
        dissipated += hit.dissipated;
        const auto &f = c.force;
        for (int d = 0; d < 3; ++d)
          force_on_particles[3 * c.particle + d] += f[d];
        for (int a = 0; a < 4; ++a)
        {
          const unsigned int node_id = s.faces[hit.face][a];
          for (int d = 0; d < 3; ++d)
            force_on_nodes[3 * node_id + d] -= hit.weight[a] * f[d];
        }
      }
    normal_force_   = fn_sum;
    penalty_energy_ = energy;
    friction_dissipation_ += dissipated;
    n_sliding_ = n_slide;
    return n_contact;
  }
} // namespace coupling
