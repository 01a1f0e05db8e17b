/// @file
/// The only deal.II translation unit of the fem library: mesh generation, lumped mass, assembled
/// stiffness, power iteration and the explicit central-difference step of fem::SteelBody.
///
/// Unknowns are numbered node-major, dof = 3 * vertex + component, with vertices compacted to
/// the snapshot order, so plain arrays cross the public interface without a permutation.

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q1.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/manifold_lib.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/vector.h>

#include <fem/steel_body.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>

namespace fem
{
  namespace
  {
    using namespace dealii;

    /// deal.II's lexicographic hexahedron vertex order to VTK_HEXAHEDRON order.
    constexpr unsigned int vtk_from_dealii[8] = {0, 1, 3, 2, 4, 5, 7, 6};

    void check_positive(const double value, const char *name)
    {
      if (!(value > 0.0) || !std::isfinite(value))
      {
        std::ostringstream msg;
        msg << "fem::SteelBody: " << name << " must be a positive finite number, got " << value;
        throw std::invalid_argument(msg.str());
      }
    }

    /// Height [m] of the contact face above the tip at lateral distance `r` [m] from the tip
    /// (wedge: |x|; cone: the radius; disc cutter, jaw: |x|): the profile the flat face is bent to.
    double tip_rise(const BodyGeometry &g, const double r)
    {
      switch (g.shape)
      {
        case BodyShape::wedge:
        case BodyShape::cone:
        {
          // a circular tip of radius rho up to r_t = rho cos(alpha), where it meets the flank
          // tangentially (slope cot(alpha) on both sides)
          const double rho = g.tip_radius, a = g.tip_half_angle, x = std::abs(r);
          const double r_t = rho * std::cos(a);
          if (x <= r_t)
            return rho - std::sqrt(rho * rho - x * x);
          return rho - rho * std::sin(a) + (x - r_t) / std::tan(a);
        }
        case BodyShape::disc_cutter:
          return g.cutter_radius - std::sqrt(g.cutter_radius * g.cutter_radius - r * r);
        case BodyShape::jaw:
          return g.jaw_radius - std::sqrt(g.jaw_radius * g.jaw_radius - r * r);
        default:
          return 0.0;
      }
    }

    void validate(const BodyGeometry &g, const Parameters &p)
    {
      if (g.shape == BodyShape::cylinder || g.shape == BodyShape::cone)
        check_positive(g.diameter, "BodyGeometry::diameter [m]");
      else
      {
        check_positive(g.size_x, "BodyGeometry::size_x [m]");
        check_positive(g.size_y, "BodyGeometry::size_y [m]");
        if (g.shape == BodyShape::jaw && !(g.jaw_radius > 0.5 * g.size_x))
          throw std::invalid_argument(
            "fem::SteelBody: BodyGeometry::jaw_radius [m] must exceed size_x / 2 = " +
            std::to_string(0.5 * g.size_x) + ", got " + std::to_string(g.jaw_radius));
      }
      check_positive(g.thickness, "BodyGeometry::thickness [m]");
      // the tip profile must leave the body at least a third of its thickness at the rim, or the
      // bent cells invert
      const double rim_rise = tip_rise(g, g.shape == BodyShape::cone ? 0.5 * g.diameter
                                                                          : 0.5 * g.size_x);
      if (g.shape == BodyShape::wedge || g.shape == BodyShape::cone)
        if (!(g.tip_half_angle > 0.05 && g.tip_half_angle < 1.53))
          throw std::invalid_argument("fem::SteelBody: BodyGeometry::tip_half_angle must lie in "
                                      "(0.05, 1.53) rad, got " +
                                      std::to_string(g.tip_half_angle));
      if (g.shape == BodyShape::disc_cutter && !(g.cutter_radius > 0.5 * g.size_x))
        throw std::invalid_argument(
          "fem::SteelBody: BodyGeometry::cutter_radius [m] must exceed size_x / 2 = " +
          std::to_string(0.5 * g.size_x) + ", got " + std::to_string(g.cutter_radius));
      if (!(rim_rise < 2.0 / 3.0 * g.thickness))
        throw std::invalid_argument(
          "fem::SteelBody: BodyGeometry::thickness [m] must exceed 1.5 x the rise of the tip "
          "profile at the rim (" +
          std::to_string(rim_rise) + " m); got " + std::to_string(g.thickness) +
          "; make the body thicker or narrower");
      check_positive(p.element_size, "Parameters::element_size [m]");
      check_positive(p.density, "Parameters::density [kg/m^3]");
      check_positive(p.time_step_safety, "Parameters::time_step_safety [-]");
      if (p.free_body && p.model != SteelModel::elastic)
        throw std::invalid_argument("fem::SteelBody: Parameters::free_body needs the elastic model (a "
                                    "rigid platen is defined by its prescribed motion)");
      if (p.model == SteelModel::elastic)
      {
        check_positive(p.youngs_modulus, "Parameters::youngs_modulus [Pa]");
        if (!(p.poissons_ratio > -1.0 && p.poissons_ratio < 0.5))
          throw std::invalid_argument(
            "fem::SteelBody: Parameters::poissons_ratio must lie in (-1, 0.5), got " +
            std::to_string(p.poissons_ratio));
        if (!(p.stiffness_damping >= 0.0))
          throw std::invalid_argument(
            "fem::SteelBody: Parameters::stiffness_damping [s] must be >= 0, got " +
            std::to_string(p.stiffness_damping));
      }
    }

    unsigned int n_cells_for(const double length, const double h)
    {
      return std::max(1u, static_cast<unsigned int>(std::lround(length / h)));
    }

    /// Cylinder of the geometry's diameter and thickness, axis along z, z in [0, thickness],
    /// centred on the z axis. End faces keep ids 1 and 2, the hull id 0.
    void make_cylinder(Triangulation<3> &tria, const BodyGeometry &g, const double h,
                       const unsigned int min_refine = 0)
    {
      const double radius = 0.5 * g.diameter;
      // The coarse cross-section (a square and four shells) has edges of about radius/sqrt(2)
      // (the shells are thicker at the rim); refine until the in-plane edge is <= 1.2 h.
      unsigned int n_refine = 0;
      while ((0.75 * radius / std::pow(2.0, n_refine) > 1.2 * h || n_refine < min_refine) &&
             n_refine < 8)
        ++n_refine;
      const double axial_after_refine = g.thickness / std::pow(2.0, n_refine);
      const unsigned int x_sub        = n_cells_for(axial_after_refine, h);

      GridGenerator::subdivided_cylinder(tria, x_sub, radius, 0.5 * g.thickness);
      // The generator's axis is x; rotate it onto z. Rotation moves vertices only: the
      // manifolds still describe an x-axis cylinder and must be attached again.
      Tensor<1, 3> y_axis;
      y_axis[1] = 1.0;
      GridTools::rotate(y_axis, -0.5 * numbers::PI, tria);
      Tensor<1, 3> z_axis;
      z_axis[2] = 1.0;

      tria.set_all_manifold_ids(1);
      for (const auto &cell : tria.active_cell_iterators())
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary() && face->boundary_id() == 0)
            face->set_all_manifold_ids(0);
      tria.set_manifold(0, CylindricalManifold<3>(z_axis, Point<3>()));
      TransfiniteInterpolationManifold<3> interior;
      interior.initialize(tria);
      tria.set_manifold(1, interior);
      tria.refine_global(n_refine);
      tria.reset_all_manifolds();
      tria.set_all_manifold_ids(numbers::flat_manifold_id);

      // whichever way the rotation turned the axis: put the body at z in [0, thickness]
      double z_min = std::numeric_limits<double>::max();
      for (const auto &v : tria.get_vertices())
        z_min = std::min(z_min, v[2]);
      Tensor<1, 3> shift;
      shift[2] = -z_min;
      GridTools::shift(shift, tria);
    }

    /// Box centred on the z axis, z in [0, thickness]. Colorized ids 0..5 (x-, x+, y-, y+, z-, z+).
    void make_box(Triangulation<3> &tria, const BodyGeometry &g, const double h)
    {
      unsigned int n_x = n_cells_for(g.size_x, h);
      // wedge, disc cutter: an even count puts a vertex line on the tip (x = 0)
      if ((g.shape == BodyShape::wedge || g.shape == BodyShape::disc_cutter) && n_x % 2 == 1)
        ++n_x;
      const std::vector<unsigned int> reps = {n_x, n_cells_for(g.size_y, h),
                                              n_cells_for(g.thickness, h)};
      GridGenerator::subdivided_hyper_rectangle(
        tria, reps, Point<3>(-0.5 * g.size_x, -0.5 * g.size_y, 0.0),
        Point<3>(0.5 * g.size_x, 0.5 * g.size_y, g.thickness), true);
    }
  } // namespace

  class SteelBody::Impl
  {
  public:
    Impl(const BodyGeometry &geometry, const Parameters &parameters);

    void step(double t, double dt);
    double lambda_max() const;
    void vertex_field_to_vector(const std::vector<double> &field, Vector<double> &out) const;

    BodyGeometry geometry;
    Parameters prm;

    Triangulation<3> tria;
    FE_Q<3> fe{1};
    std::vector<unsigned int> vertex_of_tria_vertex; ///< tria vertex -> compact vertex
    std::vector<unsigned int> cell_vertices;         ///< 8 compact vertices per cell, deal.II order
    std::size_t n_vertices = 0;

    std::vector<double> x0;     ///< reference positions [m], 3 per vertex
    std::vector<double> m_node; ///< lumped mass per vertex [kg]
    double volume = 0.0;        ///< [m^3]
    double mass   = 0.0;        ///< [kg]

    SparsityPattern sparsity;
    SparseMatrix<double> K;

    std::vector<unsigned int> contact_nodes; ///< compact vertices on the contact face
    std::vector<unsigned int> contact_faces; ///< 4 contact-node indices per quad
    std::vector<double> contact_area;        ///< [m^2]
    std::vector<unsigned int> loaded_nodes;  ///< compact vertices on the loaded face
    std::vector<bool> prescribed;            ///< per dof

    Vector<double> u, v, Ku, Kv, f_ext, du_prev;

    std::function<double(double)> velocity_z;
    std::function<double(double)> velocity_x;
    double time_             = 0.0;
    double dt_prev           = 0.0;
    double rigid_vz          = 0.0; ///< rigid body z velocity at the last half step [m/s]
    double rigid_vx          = 0.0; ///< rigid body x velocity at the last half step [m/s]
    double reaction          = 0.0;
    double reaction_xyz[3]   = {0, 0, 0}; ///< frame force on the loaded face [N]
    double work              = 0.0;
    double dissipated        = 0.0;
    double strain_energy_mid = 0.0; ///< [J], see step()

    mutable double lambda_cache = -1.0;
  };

  SteelBody::Impl::Impl(const BodyGeometry &g, const Parameters &p)
      : geometry(g)
      , prm(p)
  {
    validate(g, p);
    if (g.shape == BodyShape::cylinder)
      make_cylinder(tria, g, p.element_size);
    else if (g.shape == BodyShape::cone)
      make_cylinder(tria, g, p.element_size, 1); // one refinement puts a vertex on the axis
    else
      make_box(tria, g, p.element_size);

    // Place the body on its side of the contact plane and mark the faces. Before the shift the
    // body occupies z in [0, thickness].
    const bool above        = (g.side == BodySide::above);
    const double contact_z0 = above ? 0.0 : g.thickness; // contact plane before the shift
    const double tol        = 1e-6 * g.thickness;
    for (const auto &cell : tria.active_cell_iterators())
      for (const auto &face : cell->face_iterators())
        if (face->at_boundary())
        {
          const double zc = face->center()[2];
          bool flat_end   = true;
          for (unsigned int k = 0; k < 4; ++k)
            flat_end = flat_end && std::abs(face->vertex(k)[2] - zc) < tol;
          if (flat_end && std::abs(zc - contact_z0) < tol)
            face->set_boundary_id(boundary_id::contact);
          else if (flat_end && std::abs(zc - (g.thickness - contact_z0)) < tol)
            face->set_boundary_id(boundary_id::loaded);
          else
            face->set_boundary_id(boundary_id::free_faces);
        }
    if (g.shape != BodyShape::cylinder && g.shape != BodyShape::box)
    {
      // bend the contact face into the tip profile z_c + rise(x) (disc cutter: the arc
      // R - sqrt(R^2 - x^2); wedge: |x| / tan(alpha); cone: r / tan(alpha)), away from the rock:
      // a cutter is convex towards the rock. The ISRM jaw is concave: it cradles the disc, so its
      // face bends by the same arc towards the rock (a jaw radius above the disc radius keeps it
      // clear of the disc but at the apex). The bend fades linearly to zero at the loaded face,
      // which stays flat; boundary ids were set on the flat body and are kept
      const double towards_rock = g.shape == BodyShape::jaw ? -1.0 : 1.0;
      GridTools::transform(
        [&](const Point<3> &q) {
          const double r     = g.shape == BodyShape::cone ? std::hypot(q[0], q[1]) : q[0];
          const double rise  = tip_rise(g, r);
          const double share = above ? 1.0 - q[2] / g.thickness : q[2] / g.thickness;
          Point<3> out       = q;
          out[2] += towards_rock * (above ? 1.0 : -1.0) * rise * share;
          return out;
        },
        tria);
    }
    Tensor<1, 3> shift;
    shift[0] = g.center_x;
    shift[1] = g.center_y;
    shift[2] = g.contact_z - contact_z0;
    GridTools::shift(shift, tria);

    // compact vertex numbering
    const auto &used = tria.get_used_vertices();
    vertex_of_tria_vertex.assign(tria.n_vertices(), numbers::invalid_unsigned_int);
    for (unsigned int i = 0; i < tria.n_vertices(); ++i)
      if (used[i])
      {
        vertex_of_tria_vertex[i] = n_vertices++;
        for (unsigned int d = 0; d < 3; ++d)
          x0.push_back(tria.get_vertices()[i][d]);
      }
    for (const auto &cell : tria.active_cell_iterators())
      for (unsigned int k = 0; k < 8; ++k)
        cell_vertices.push_back(vertex_of_tria_vertex[cell->vertex_index(k)]);

    const std::size_t n_dofs   = 3 * n_vertices;
    const unsigned int n_cells = tria.n_active_cells();

    // Lumped mass: row sums of the consistent mass (Gauss 2x2x2 is exact for the trilinear
    // Jacobian), so the sum of the nodal masses is exactly rho times the mesh volume.
    m_node.assign(n_vertices, 0.0);
    {
      QGauss<3> quadrature(2);
      FEValues<3> fe_values(fe, quadrature, update_values | update_JxW_values);
      unsigned int c = 0;
      for (const auto &cell : tria.active_cell_iterators())
      {
        fe_values.reinit(cell);
        for (unsigned int q = 0; q < quadrature.size(); ++q)
        {
          volume += fe_values.JxW(q);
          for (unsigned int i = 0; i < 8; ++i)
            m_node[cell_vertices[8 * c + i]] +=
              p.density * fe_values.shape_value(i, q) * fe_values.JxW(q);
        }
        ++c;
      }
      for (const double m : m_node)
        mass += m;
    }

    // Stiffness (elastic only), node-major dofs.
    if (p.model == SteelModel::elastic)
    {
      DynamicSparsityPattern dsp(n_dofs, n_dofs);
      for (unsigned int c = 0; c < n_cells; ++c)
        for (unsigned int i = 0; i < 8; ++i)
          for (unsigned int j = 0; j < 8; ++j)
            for (unsigned int a = 0; a < 3; ++a)
              for (unsigned int b = 0; b < 3; ++b)
                dsp.add(3 * cell_vertices[8 * c + i] + a, 3 * cell_vertices[8 * c + j] + b);
      sparsity.copy_from(dsp);
      K.reinit(sparsity);

      const double E      = p.youngs_modulus;
      const double nu     = p.poissons_ratio;
      const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
      const double mu     = E / (2 * (1 + nu));

      QGauss<3> quadrature(2);
      FEValues<3> fe_values(fe, quadrature, update_gradients | update_JxW_values);
      FullMatrix<double> ke(24, 24);
      std::vector<types::global_dof_index> dofs(24);
      unsigned int c = 0;
      for (const auto &cell : tria.active_cell_iterators())
      {
        fe_values.reinit(cell);
        ke = 0;
        for (unsigned int q = 0; q < quadrature.size(); ++q)
          for (unsigned int i = 0; i < 8; ++i)
          {
            const Tensor<1, 3> gi = fe_values.shape_grad(i, q);
            for (unsigned int j = 0; j < 8; ++j)
            {
              const Tensor<1, 3> gj = fe_values.shape_grad(j, q);
              const double dot      = gi * gj;
              for (unsigned int a = 0; a < 3; ++a)
                for (unsigned int b = 0; b < 3; ++b)
                  ke(3 * i + a, 3 * j + b) +=
                    (lambda * gi[a] * gj[b] + mu * gi[b] * gj[a] + (a == b ? mu * dot : 0.0)) *
                    fe_values.JxW(q);
            }
          }
        for (unsigned int i = 0; i < 8; ++i)
          for (unsigned int a = 0; a < 3; ++a)
            dofs[3 * i + a] = 3 * cell_vertices[8 * c + i] + a;
        K.add(dofs, ke);
        ++c;
      }
    }

    // Contact face, loaded face, prescribed dofs.
    std::vector<unsigned int> contact_index(n_vertices, numbers::invalid_unsigned_int);
    std::vector<bool> on_loaded(n_vertices, false);
    const double n_out = above ? -1.0 : 1.0;
    QGauss<2> face_quadrature(2);
    FEFaceValues<3> fe_face(fe, face_quadrature, update_values | update_JxW_values);
    for (const auto &cell : tria.active_cell_iterators())
      for (const unsigned int f : cell->face_indices())
      {
        const auto face = cell->face(f);
        if (!face->at_boundary())
          continue;
        if (face->boundary_id() == boundary_id::loaded)
          for (unsigned int k = 0; k < 4; ++k)
            on_loaded[vertex_of_tria_vertex[face->vertex_index(k)]] = true;
        if (face->boundary_id() != boundary_id::contact)
          continue;
        unsigned int quad[4];
        const unsigned int cyclic[4] = {0, 1, 3, 2}; // lexicographic face vertices -> cyclic
        for (unsigned int k = 0; k < 4; ++k)
        {
          const unsigned int vtx = vertex_of_tria_vertex[face->vertex_index(cyclic[k])];
          if (contact_index[vtx] == numbers::invalid_unsigned_int)
          {
            contact_index[vtx] = contact_nodes.size();
            contact_nodes.push_back(vtx);
            contact_area.push_back(0.0);
          }
          quad[k] = contact_index[vtx];
        }
        const Point<3> p0 = face->vertex(cyclic[0]), p1 = face->vertex(cyclic[1]),
                       p3         = face->vertex(cyclic[3]);
        const Tensor<1, 3> normal = cross_product_3d(p1 - p0, p3 - p0);
        if (normal[2] * n_out < 0)
          std::swap(quad[1], quad[3]);
        contact_faces.insert(contact_faces.end(), quad, quad + 4);

        fe_face.reinit(cell, f);
        for (unsigned int q = 0; q < face_quadrature.size(); ++q)
          for (unsigned int i = 0; i < 8; ++i)
          {
            const double w = fe_face.shape_value(i, q) * fe_face.JxW(q);
            if (w != 0.0)
              contact_area[contact_index[vertex_of_tria_vertex[cell->vertex_index(i)]]] += w;
          }
      }
    prescribed.assign(n_dofs, false);
    for (unsigned int n = 0; n < n_vertices; ++n)
      if (on_loaded[n])
      {
        loaded_nodes.push_back(n);
        if (p.free_body)
          continue;
        prescribed[3 * n + 2] = true;
        if (p.loaded_face_lateral == LoadedFaceLateral::fixed)
          prescribed[3 * n] = prescribed[3 * n + 1] = true;
      }
    if (contact_nodes.empty() || loaded_nodes.empty())
      throw std::logic_error("fem::SteelBody: the mesh has no contact or no loaded face");

    u.reinit(n_dofs);
    v.reinit(n_dofs);
    Ku.reinit(n_dofs);
    Kv.reinit(n_dofs);
    f_ext.reinit(n_dofs);
    du_prev.reinit(n_dofs);
  }

  void SteelBody::Impl::vertex_field_to_vector(const std::vector<double> &field,
                                            Vector<double> &out) const
  {
    if (field.size() != 3 * n_vertices)
      throw std::invalid_argument(
        "fem::SteelBody: a vertex field needs 3 * n_nodes() = " + std::to_string(3 * n_vertices) +
        " values, got " + std::to_string(field.size()));
    out.reinit(field.size());
    std::copy(field.begin(), field.end(), out.begin());
  }

  double SteelBody::Impl::lambda_max() const
  {
    if (prm.model == SteelModel::rigid)
      return 0.0;
    if (lambda_cache >= 0.0)
      return lambda_cache;
    // Power iteration on the symmetric A = M^-1/2 K M^-1/2 (same spectrum as M^-1 K), all dofs
    // free: the constrained problem's lambda_max is not larger (interlacing), so this is safe.
    const std::size_t n = K.m();
    Vector<double> inv_sqrt_m(n), y(n), z(n), w(n);
    for (std::size_t i = 0; i < n; ++i)
      inv_sqrt_m[i] = 1.0 / std::sqrt(m_node[i / 3]);
    std::mt19937 rng(12345);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    for (auto &yi : y)
      yi = uniform(rng);
    y /= y.l2_norm();

    // Gershgorin: a rigorous upper bound on lambda_max of A.
    double gershgorin = 0.0;
    for (std::size_t i = 0; i < n; ++i)
    {
      double row = 0.0;
      for (auto it = K.begin(i); it != K.end(i); ++it)
        row += std::abs(it->value()) * inv_sqrt_m[it->column()];
      gershgorin = std::max(gershgorin, row * inv_sqrt_m[i]);
    }

    double rayleigh = 0.0, residual = 0.0;
    for (unsigned int it = 0; it < prm.power_iteration_max; ++it)
    {
      w = y;
      w.scale(inv_sqrt_m);
      K.vmult(z, w);
      z.scale(inv_sqrt_m);
      rayleigh = y * z;
      w        = z;
      w.add(-rayleigh, y);
      residual = w.l2_norm();
      if (residual < prm.power_iteration_tolerance * rayleigh)
        break;
      y = z;
      y /= y.l2_norm();
    }
    // The Rayleigh quotient approaches lambda_max from below; adding the residual norm makes
    // the estimate an upper bound for the converged eigenpair and a cautious one otherwise.
    lambda_cache = std::min(rayleigh + residual, gershgorin);
    return lambda_cache;
  }

  void SteelBody::Impl::step(const double t, const double dt)
  {
    if (!(dt > 0.0))
      throw std::invalid_argument("fem::SteelBody::step: dt must be > 0, got " + std::to_string(dt));
    const double dt_mid      = 0.5 * (dt_prev + dt); // v lives at half steps
    const double t_half      = t + 0.5 * dt;
    const double vz_new      = velocity_z ? velocity_z(t_half) : 0.0;
    const double vx_new      = velocity_x ? velocity_x(t_half) : 0.0;
    const std::size_t n_dofs = u.size();
    // prescribed velocity of a loaded-face dof by component (y is held)
    const double v_prescribed[3] = {vx_new, 0.0, vz_new};

    if (prm.model == SteelModel::rigid)
    {
      const double a_x    = (vx_new - rigid_vx) / dt_mid;
      const double a_z    = (vz_new - rigid_vz) / dt_mid;
      double f_contact[3] = {0, 0, 0};
      for (std::size_t i = 0; i < n_dofs; ++i)
        f_contact[i % 3] += f_ext[i];
      // frame force: M a = F_contact + R
      reaction_xyz[0]       = mass * a_x - f_contact[0];
      reaction_xyz[1]       = -f_contact[1];
      reaction_xyz[2]       = mass * a_z - f_contact[2];
      reaction              = reaction_xyz[2];
      const double dux_new  = dt * vx_new;
      const double duz_new  = dt * vz_new;
      const double dux_prev = du_prev[0]; // the body moves as one: every x (z) dof alike
      const double duz_prev = du_prev[2];
      double dw             = 0.0;
      for (std::size_t i = 0; i < n_dofs; ++i)
      {
        const double du_new = (i % 3 == 2) ? duz_new : (i % 3 == 0) ? dux_new : 0.0;
        dw += f_ext[i] * 0.5 * (du_prev[i] + du_new);
        u[i] += du_new;
        v[i]       = v_prescribed[i % 3];
        du_prev[i] = du_new;
      }
      // the frame's x and z forces work on the centred increments; it holds y (no work)
      work += dw + reaction_xyz[0] * 0.5 * (dux_prev + dux_new) +
              reaction_xyz[2] * 0.5 * (duz_prev + duz_new);
      rigid_vz = vz_new;
      rigid_vx = vx_new;
    }
    else
    {
      const double beta = prm.stiffness_damping;
      if (beta > 0.0)
        K.vmult(Kv, v);
      double dw = 0.0, dd = 0.0, r[3] = {0, 0, 0};
      for (std::size_t i = 0; i < n_dofs; ++i)
      {
        const double f = f_ext[i] - Ku[i] - (beta > 0.0 ? beta * Kv[i] : 0.0);
        const double m = m_node[i / 3];
        double v_new, f_frame = 0.0;
        if (!prescribed[i])
          v_new = v[i] + dt_mid * f / m;
        else
        {
          v_new   = v_prescribed[i % 3];
          f_frame = m * (v_new - v[i]) / dt_mid - f; // m a = f + f_frame
          r[i % 3] += f_frame;
        }
        const double du_new = dt * v_new;
        const double du_mid = 0.5 * (du_prev[i] + du_new);
        dw += (f_ext[i] + f_frame) * du_mid;
        if (beta > 0.0)
          dd += beta * Kv[i] * du_mid;
        u[i] += du_new;
        v[i]       = v_new;
        du_prev[i] = du_new;
      }
      reaction = r[2];
      std::copy(r, r + 3, reaction_xyz);
      work += dw;
      dissipated += dd;
      // strain energy at t + dt/2, where the kinetic energy lives: 1/2 u(t+dt) . K u(t); with
      // it, kinetic + strain + dissipated - work is what central differences conserve
      strain_energy_mid = 0.5 * (u * Ku);
      K.vmult(Ku, u);
    }
    f_ext   = 0.0;
    dt_prev = dt;
    time_   = t + dt;
  }

  // ---------------------------------------------------------------------------------------------
  // SteelBody: thin forwarding layer

  SteelBody::SteelBody(const BodyGeometry &geometry, const Parameters &parameters)
      : impl_(std::make_unique<Impl>(geometry, parameters))
  {}

  SteelBody::~SteelBody()                             = default;
  SteelBody::SteelBody(SteelBody &&) noexcept            = default;
  SteelBody &SteelBody::operator=(SteelBody &&) noexcept = default;

  void SteelBody::set_loaded_face_velocity(std::function<double(double)> velocity_z)
  {
    if (impl_->prm.free_body)
      throw std::logic_error("fem::SteelBody::set_loaded_face_velocity: a free body (Parameters::"
                             "free_body) has no prescribed motion");
    impl_->velocity_z = std::move(velocity_z);
  }

  void SteelBody::set_loaded_face_velocity_x(std::function<double(double)> velocity_x)
  {
    impl_->velocity_x = std::move(velocity_x);
  }

  bool SteelBody::is_rigid() const
  {
    return impl_->prm.model == SteelModel::rigid;
  }
  std::size_t SteelBody::n_nodes() const
  {
    return impl_->n_vertices;
  }
  std::size_t SteelBody::n_cells() const
  {
    return impl_->cell_vertices.size() / 8;
  }
  double SteelBody::total_mass() const
  {
    return impl_->mass;
  }
  double SteelBody::mesh_volume() const
  {
    return impl_->volume;
  }
  double SteelBody::contact_normal_z() const
  {
    return impl_->geometry.side == BodySide::above ? -1.0 : 1.0;
  }
  double SteelBody::max_eigenvalue() const
  {
    return impl_->lambda_max();
  }

  std::size_t SteelBody::n_contact_nodes() const
  {
    return impl_->contact_nodes.size();
  }

  std::vector<double> SteelBody::contact_positions() const
  {
    std::vector<double> out;
    out.reserve(3 * impl_->contact_nodes.size());
    for (const unsigned int n : impl_->contact_nodes)
      for (unsigned int d = 0; d < 3; ++d)
        out.push_back(impl_->x0[3 * n + d] + impl_->u[3 * n + d]);
    return out;
  }

  std::vector<double> SteelBody::contact_velocities() const
  {
    std::vector<double> out;
    out.reserve(3 * impl_->contact_nodes.size());
    for (const unsigned int n : impl_->contact_nodes)
      for (unsigned int d = 0; d < 3; ++d)
        out.push_back(impl_->v[3 * n + d]);
    return out;
  }

  std::vector<double> SteelBody::contact_free_accelerations() const
  {
    const Impl &im = *impl_;
    std::vector<double> out(3 * im.contact_nodes.size(), 0.0);
    if (is_rigid())
      return out;
    const double beta = im.prm.stiffness_damping;
    Vector<double> kv;
    if (beta > 0.0)
    {
      kv.reinit(im.v.size());
      im.K.vmult(kv, im.v);
    }
    for (std::size_t k = 0; k < im.contact_nodes.size(); ++k)
      for (unsigned int d = 0; d < 3; ++d)
      {
        const std::size_t i = 3 * im.contact_nodes[k] + d;
        if (!im.prescribed[i])
          out[3 * k + d] = -(im.Ku[i] + (beta > 0.0 ? beta * kv[i] : 0.0)) / im.m_node[i / 3];
      }
    return out;
  }

  std::vector<double> SteelBody::contact_masses() const
  {
    std::vector<double> out;
    out.reserve(impl_->contact_nodes.size());
    for (const unsigned int n : impl_->contact_nodes)
      out.push_back(impl_->m_node[n]);
    return out;
  }

  std::vector<double> SteelBody::contact_areas() const
  {
    return impl_->contact_area;
  }

  const std::vector<unsigned int> &SteelBody::contact_faces() const
  {
    return impl_->contact_faces;
  }

  void SteelBody::add_contact_forces(const std::vector<double> &forces)
  {
    const auto &nodes = impl_->contact_nodes;
    if (forces.size() != 3 * nodes.size())
      throw std::invalid_argument(
        "fem::SteelBody::add_contact_forces: expected 3 * n_contact_nodes() = " +
        std::to_string(3 * nodes.size()) + " values, got " + std::to_string(forces.size()));
    for (std::size_t k = 0; k < nodes.size(); ++k)
      for (unsigned int d = 0; d < 3; ++d)
        impl_->f_ext[3 * nodes[k] + d] += forces[3 * k + d];
  }

  double SteelBody::stable_time_step() const
  {
    if (is_rigid())
      return std::numeric_limits<double>::infinity();
    const double omega = std::sqrt(impl_->lambda_max());
    const double xi    = 0.5 * impl_->prm.stiffness_damping * omega;
    return impl_->prm.time_step_safety * 2.0 / omega * (std::sqrt(1.0 + xi * xi) - xi);
  }

  void SteelBody::step(const double t, const double dt)
  {
    impl_->step(t, dt);
  }
  double SteelBody::time() const
  {
    return impl_->time_;
  }

  double SteelBody::reaction_force() const
  {
    return impl_->reaction;
  }
  std::array<double, 3> SteelBody::reaction_force_vector() const
  {
    return {{impl_->reaction_xyz[0], impl_->reaction_xyz[1], impl_->reaction_xyz[2]}};
  }
  double SteelBody::compressive_force() const
  {
    return contact_normal_z() * impl_->reaction;
  }

  double SteelBody::loaded_face_displacement() const
  {
    double sum = 0.0;
    for (const unsigned int n : impl_->loaded_nodes)
      sum += impl_->u[3 * n + 2];
    return sum / impl_->loaded_nodes.size();
  }

  double SteelBody::contact_face_displacement() const
  {
    double sum = 0.0;
    for (const unsigned int n : impl_->contact_nodes)
      sum += impl_->u[3 * n + 2];
    return sum / impl_->contact_nodes.size();
  }

  double SteelBody::kinetic_energy() const
  {
    double e = 0.0;
    for (std::size_t i = 0; i < impl_->v.size(); ++i)
      e += impl_->m_node[i / 3] * impl_->v[i] * impl_->v[i];
    return 0.5 * e;
  }

  double SteelBody::strain_energy() const
  {
    return is_rigid() ? 0.0 : impl_->strain_energy_mid;
  }

  double SteelBody::external_work() const
  {
    return impl_->work;
  }
  double SteelBody::damping_dissipation() const
  {
    return impl_->dissipated;
  }

  MeshSnapshot SteelBody::mesh_snapshot() const
  {
    const Impl &im = *impl_;
    MeshSnapshot s;
    s.position.resize(im.x0.size());
    s.displacement.assign(im.u.begin(), im.u.end());
    s.velocity.assign(im.v.begin(), im.v.end());
    for (std::size_t i = 0; i < im.x0.size(); ++i)
      s.position[i] = im.x0[i] + im.u[i];
    const std::size_t n_cells = im.cell_vertices.size() / 8;
    s.hexahedra.resize(im.cell_vertices.size());
    for (std::size_t c = 0; c < n_cells; ++c)
      for (unsigned int k = 0; k < 8; ++k)
        s.hexahedra[8 * c + k] = im.cell_vertices[8 * c + vtk_from_dealii[k]];

    s.von_mises.assign(n_cells, 0.0);
    if (is_rigid())
      return s;
    const double E      = im.prm.youngs_modulus;
    const double nu     = im.prm.poissons_ratio;
    const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
    const double mu     = E / (2 * (1 + nu));
    QGauss<3> centre(1);
    FEValues<3> fe_values(im.fe, centre, update_gradients);
    std::size_t c = 0;
    for (const auto &cell : im.tria.active_cell_iterators())
    {
      fe_values.reinit(cell);
      double grad[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
      for (unsigned int i = 0; i < 8; ++i)
      {
        const Tensor<1, 3> g = fe_values.shape_grad(i, 0);
        const unsigned int n = im.cell_vertices[8 * c + i];
        for (unsigned int a = 0; a < 3; ++a)
          for (unsigned int b = 0; b < 3; ++b)
            grad[a][b] += im.u[3 * n + a] * g[b];
      }
      double sigma[3][3];
      const double tr = grad[0][0] + grad[1][1] + grad[2][2];
      for (unsigned int a = 0; a < 3; ++a)
        for (unsigned int b = 0; b < 3; ++b)
          sigma[a][b] = mu * (grad[a][b] + grad[b][a]) + (a == b ? lambda * tr : 0.0);
      const double sxx = sigma[0][0], syy = sigma[1][1], szz = sigma[2][2];
      s.von_mises[c] = std::sqrt(
        0.5 * ((sxx - syy) * (sxx - syy) + (syy - szz) * (syy - szz) + (szz - sxx) * (szz - sxx)) +
        3.0 * (sigma[0][1] * sigma[0][1] + sigma[1][2] * sigma[1][2] + sigma[0][2] * sigma[0][2]));
      ++c;
    }
    return s;
  }

  void SteelBody::write_vtu(const std::string &filename) const
  {
    fem::write_vtu(mesh_snapshot(), filename);
  }

  std::vector<double> SteelBody::reference_positions() const
  {
    return impl_->x0;
  }
  std::vector<double> SteelBody::nodal_masses() const
  {
    return impl_->m_node;
  }

  std::vector<double> SteelBody::internal_force(const std::vector<double> &displacement) const
  {
    Vector<double> uu;
    impl_->vertex_field_to_vector(displacement, uu);
    if (is_rigid())
      return std::vector<double>(displacement.size(), 0.0);
    Vector<double> f(uu.size());
    impl_->K.vmult(f, uu);
    return std::vector<double>(f.begin(), f.end());
  }

  void SteelBody::set_state(const std::vector<double> &displacement,
                         const std::vector<double> &velocity)
  {
    Impl &im = *impl_;
    im.vertex_field_to_vector(displacement, im.u);
    im.vertex_field_to_vector(velocity, im.v);
    if (!is_rigid())
    {
      im.K.vmult(im.Ku, im.u);
      im.strain_energy_mid = 0.5 * (im.u * im.Ku);
    }
    else
    {
      im.rigid_vz = velocity.empty() ? 0.0 : velocity[2];
      im.rigid_vx = velocity.empty() ? 0.0 : velocity[0];
    }
    im.du_prev = 0.0;
    im.dt_prev = 0.0;
  }

  // ---- checkpoints: every member of Impl that step() changes -------------------------------
  void SteelBody::save_state(std::map<std::string, std::vector<double>> &out,
                          const std::string &prefix) const
  {
    const Impl &im = *impl_;
    auto put       = [&](const char *name, const Vector<double> &x) {
      out[prefix + name] = std::vector<double>(x.begin(), x.end());
    };
    put("u", im.u);
    put("v", im.v);
    put("Ku", im.Ku);
    put("Kv", im.Kv);
    put("f_ext", im.f_ext);
    put("du_prev", im.du_prev);
    // the x motion and the frame force vector came with the disc cutter (a rigid body moved along
    // x): scalars 7-10
    out[prefix + "scalars"] = {im.time_,           im.dt_prev,         im.rigid_vz,
                               im.reaction,        im.work,            im.dissipated,
                               im.strain_energy_mid, im.rigid_vx,      im.reaction_xyz[0],
                               im.reaction_xyz[1], im.reaction_xyz[2]};
  }

  void SteelBody::load_state(const std::map<std::string, std::vector<double>> &in,
                          const std::string &prefix)
  {
    Impl &im  = *impl_;
    auto find = [&](const char *name, std::size_t size) -> const std::vector<double> & {
      const auto it = in.find(prefix + name);
      if (it == in.end() || it->second.size() != size)
        throw std::invalid_argument("platen state: array '" + prefix + name +
                                    (it == in.end() ? "' missing" : "' has the wrong size") +
                                    " (a checkpoint of another case?)");
      return it->second;
    };
    auto get = [&](const char *name, Vector<double> &x) {
      const auto &a = find(name, x.size());
      std::copy(a.begin(), a.end(), x.begin());
    };
    get("u", im.u);
    get("v", im.v);
    get("Ku", im.Ku);
    get("Kv", im.Kv);
    get("f_ext", im.f_ext);
    get("du_prev", im.du_prev);
    const auto &s        = find("scalars", 11);
    im.time_             = s[0];
    im.dt_prev           = s[1];
    im.rigid_vz          = s[2];
    im.reaction          = s[3];
    im.work              = s[4];
    im.dissipated        = s[5];
    im.strain_energy_mid = s[6];
    im.rigid_vx          = s[7];
    std::copy(s.begin() + 8, s.begin() + 11, im.reaction_xyz);
  }
} // namespace fem
