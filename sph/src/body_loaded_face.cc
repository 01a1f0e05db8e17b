// Loaded faces of an SPH body: the boundary term of the symmetric force moved to the outer layer
// (see Body::add_loaded_face).
#include <sph/body.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <utility>

namespace sph
{
  template <int dim>
  unsigned int Body<dim>::add_loaded_face(const Vector<dim> &normal)
  {
    return add_loaded_face(normal, std::numeric_limits<double>::quiet_NaN());
  }

  template <int dim>
  unsigned int Body<dim>::add_loaded_face(const Vector<dim> &normal, const double face_height)
  {
    const double length = normal.norm();
    if (!(length > 0) || !std::isfinite(length))
      throw std::invalid_argument("sph::Body::add_loaded_face: the normal must be a non-zero "
                                  "finite vector");
    const Vector<dim> n = normal / length;
    double            h_max = 0, top = -std::numeric_limits<double>::max();
    for (unsigned int i = 0; i < n_particles(); ++i)
      {
        h_max = std::max(h_max, p_.h[i]);
        top   = std::max(top, n.dot(p_.x0[i]));
      }
    if (!std::isnan(face_height))
      top = face_height;
    // the boundary term reaches two kernel supports deep: particles within 2h of the surface
    // have truncated supports (L != I), and their L enters the sums of their neighbours
    const double depth = 4.0 * h_max + 0.01 * prm_.spacing;
    // columns: particles with the same lateral position, outer particle first. The generators
    // repeat a layer's lateral positions exactly in every layer (lattice cells and body-fitted
    // rings alike); a key of a thousandth of the spacing tells apart particles of one layer,
    // which lie at least 0.85 spacings apart, but a key of a whole spacing would not for rings
    // (two ring particles can round to the same lattice cell)
    const double quantum = 1e-3 * prm_.spacing;
    std::map<std::array<long, dim>, std::vector<std::pair<double, unsigned int>>> columns;
    for (unsigned int i = 0; i < n_particles(); ++i)
      {
        const double height = n.dot(p_.x0[i]);
        if (height < top - depth)
          continue;
        const Vector<dim>     lateral = p_.x0[i] - height * n;
        std::array<long, dim> key;
        for (int d = 0; d < dim; ++d)
          key[d] = std::lround(lateral[d] / quantum);
        columns[key].emplace_back(-height, i);
      }
    face_area_.resize(n_particles(), 0.0);
    std::vector<bool> taken(n_particles(), false);
    for (const FaceColumn &column : face_columns_)
      for (const unsigned int k : column.members)
        taken[k] = true;
    for (const auto &entry : columns)
      for (const auto &m : entry.second)
        if (taken[m.second])
          throw std::invalid_argument(
            "sph::Body::add_loaded_face: the body is too thin for two loaded faces (each takes "
            "the particles within two kernel supports of it)");
    unsigned int count = 0;
    for (auto &entry : columns)
      {
        auto &c = entry.second;
        std::sort(c.begin(), c.end());
        // a column whose outer particle lies below the face is not loaded by the platen
        if (-c.front().first < top - 0.5 * prm_.spacing)
          continue;
        FaceColumn column;
        column.normal = n;
        for (const auto &m : c)
          column.members.push_back(m.second);
        count += static_cast<unsigned int>(c.size());
        double area = 0;
        for (const unsigned int k : column.members)
          area -= n.dot(loaded_face_s(k)); // f = P s: s points into the body
        if (total_lagrangian())
          for (const unsigned int k : column.members)
            column.ds.push_back(-n.dot(loaded_face_s(k)) * n);
        face_area_[column.members.front()] = area;
        face_columns_.push_back(std::move(column));
      }
    compute_area_vectors(); // the surface-pressure vectors of the face, lumped like the force
    return count;
  }

  template <int dim>
  Vector<dim> Body<dim>::loaded_face_s(const unsigned int i) const
  {
    // s_i = sum_j V_i V_j (L_i + L_j) grad_i W_ij: f_i = P s_i for a uniform stress P
    const bool                 cor = corrected();
    const std::vector<double> &V   = total_lagrangian() ? p_.volume0 : p_.volume;
    const Tensor<dim>          I   = Tensor<dim>::Identity();
    Vector<dim>                sum = Vector<dim>::Zero();
    for (std::int32_t k = pairs_.offsets[i]; k < pairs_.offsets[i + 1]; ++k)
      {
        const std::int32_t p = pairs_.incidence[k];
        const std::int32_t j = pairs_.other(p, i);
        const Vector<dim>  g = (pairs_.first[p] == static_cast<std::int32_t>(i)) ?
                                 grad_w_[p] :
                                 Vector<dim>(-grad_w_[p]);
        sum += V[i] * V[j] * ((cor ? p_.L[i] : I) + (cor ? p_.L[j] : I)) * g;
      }
    return sum;
  }

  template <int dim>
  void Body<dim>::lump_loaded_faces(std::vector<Vector<dim>> &v) const
  {
    for (const FaceColumn &column : face_columns_)
      {
        const Vector<dim> &n     = column.normal;
        const unsigned int o     = column.members.front();
        for (std::size_t m = 1; m < column.members.size(); ++m)
          {
            const unsigned int k      = column.members[m];
            const Vector<dim>  normal = n.dot(v[k]) * n;
            v[k] -= normal;
            v[o] += normal;
          }
      }
  }

  template <int dim>
  void Body<dim>::loaded_face_forces()
  {
    // Each member k != o of a column gets -(n.s_k) n with its own stress P_k, which removes the
    // normal part of its own boundary term P_k s_k in any state, not only a uniform one; the
    // column's outer particle o takes the sum, so the corrections of a column cancel (momentum
    // exact). With o's stress for every member instead, k's force followed o's strain, a
    // coupling with no counterpart in k's force on o: under a kinematic (exact) constraint on
    // the outer layer that one-sided stiffness fed an oscillation that the artificial viscosity
    // took out (an elastic UCS dissipated 105 J of 265 J of work).
    const bool tl = total_lagrangian();
    auto piola = [&](const int i) {
      const Tensor<dim> sigma = p_.stress[i].template topLeftCorner<dim, dim>();
      return tl ? Tensor<dim>(p_.F[i].determinant() * sigma * p_.F[i].inverse().transpose()) : sigma;
    };
#pragma omp parallel for num_threads(n_threads_) schedule(static)
    for (long c = 0; c < static_cast<long>(face_columns_.size()); ++c)
      {
        const FaceColumn &column = face_columns_[c];
        const int         o      = static_cast<int>(column.members.front());
        Vector<dim>       moved  = Vector<dim>::Zero();
        for (std::size_t m = 1; m < column.members.size(); ++m)
          {
            const int         k  = static_cast<int>(column.members[m]);
            const Vector<dim> ds = column.ds.empty() ?
                                     Vector<dim>(-column.normal.dot(loaded_face_s(k)) * column.normal) :
                                     column.ds[m];
            const Vector<dim> f = piola(k) * ds;
            p_.f_pressure[k] += f;
            moved -= f;
          }
        p_.f_pressure[o] += moved;
      }
  }

  template unsigned int Body<2>::add_loaded_face(const Vector<2> &);
  template unsigned int Body<3>::add_loaded_face(const Vector<3> &);
  template unsigned int Body<2>::add_loaded_face(const Vector<2> &, double);
  template unsigned int Body<3>::add_loaded_face(const Vector<3> &, double);
  template void         Body<2>::loaded_face_forces();
  template void Body<2>::lump_loaded_faces(std::vector<Vector<2>> &) const;
  template void Body<3>::lump_loaded_faces(std::vector<Vector<3>> &) const;
  template Vector<2>    Body<2>::loaded_face_s(unsigned int) const;
  template Vector<3>    Body<3>::loaded_face_s(unsigned int) const;
  template void         Body<3>::loaded_face_forces();
} // namespace sph
