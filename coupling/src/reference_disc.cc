// The Brazilian disc's 3-D elastic reference (reference_disc.h): an eighth of the disc, the
// thickness along z, the load along y; the tension across the loaded diameter is sigma_xx.
#include <coupling/reference_disc.h>

#include <deal.II/base/function.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/component_mask.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/manifold_lib.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/precondition.h>
#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/vector.h>
#include <deal.II/numerics/vector_tools.h>

#include <cmath>
#include <stdexcept>

namespace coupling
{
  using namespace dealii;

  DiscReferenceProfile elastic_disc_reference(const double diameter, const double thickness,
                                              const double alpha, const double E,
                                              const double nu, const double load,
                                              const std::vector<double> &rho,
                                              const unsigned int refinements,
                                              const double face_depth)
  {
    if (!(diameter > 0 && thickness > 0 && alpha > 0 && alpha < 1.5 && E > 0 && nu > -1 &&
          nu < 0.5 && load > 0 && face_depth >= 0 && face_depth < 0.5 * thickness))
      throw std::invalid_argument("elastic_disc_reference: a parameter is out of range");
    for (const double r : rho)
      if (!(r >= 0 && r < 1))
        throw std::invalid_argument("elastic_disc_reference: sample radii must lie in [0, 1)");
    const double R = 0.5 * diameter, half = 0.5 * thickness;
    // an eighth of the disc (x, y >= 0, the mid-plane z = 0 to a face z = t / 2; the load along
    // y), its three cut planes symmetry planes: a quarter disc extruded over the half thickness
    Triangulation<2> quarter;
    GridGenerator::quarter_hyper_ball(quarter, Point<2>(), R);
    Triangulation<3> tria;
    GridGenerator::extrude_triangulation(quarter, 2, half, tria, true);
    const CylindricalManifold<3> rim(Tensor<1, 3>({0.0, 0.0, 1.0}), Point<3>());
    tria.set_manifold(0, rim);
    tria.refine_global(refinements);
    // boundary parts by where their faces lie: 1, 2, 3 the planes x, y, z = 0; 4 the face
    // z = t / 2; 0 the rim
    const double tol = 1e-9 * R;
    for (const auto &cell : tria.active_cell_iterators())
      for (const unsigned int f : cell->face_indices())
        if (cell->face(f)->at_boundary())
        {
          const Point<3> c = cell->face(f)->center();
          const types::boundary_id id = std::abs(c[0]) < tol          ? 1
                                        : std::abs(c[1]) < tol        ? 2
                                        : std::abs(c[2]) < tol        ? 3
                                        : std::abs(c[2] - half) < tol ? 4
                                                                      : 0;
          cell->face(f)->set_boundary_id(id);
        }
    const FESystem<3> fe(FE_Q<3>(2), 3);
    const MappingQ<3> mapping(2);
    DoFHandler<3> dof(tria);
    dof.distribute_dofs(fe);
    AffineConstraints<double> constraints;
    for (unsigned int c = 0; c < 3; ++c)
    {
      ComponentMask mask(3, false);
      mask.set(c, true);
      VectorTools::interpolate_boundary_values(mapping, dof, c + 1, Functions::ZeroFunction<3>(3),
                                               constraints, mask);
    }
    constraints.close();

    DynamicSparsityPattern dsp(dof.n_dofs());
    DoFTools::make_sparsity_pattern(dof, dsp, constraints, false);
    SparsityPattern pattern;
    pattern.copy_from(dsp);
    SparseMatrix<double> K(pattern);
    Vector<double> u(dof.n_dofs()), f(dof.n_dofs());

    const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
    const double pressure = load / (2 * R * std::sin(alpha) * thickness);

    const QGauss<3> quadrature(3);
    const QGauss<2> face_quadrature(8); // many points: the arc's end cuts through faces
    FEValues<3> fv(mapping, fe, quadrature, update_gradients | update_JxW_values);
    FEFaceValues<3> ffv(mapping, fe, face_quadrature,
                        update_values | update_quadrature_points | update_normal_vectors |
                          update_JxW_values);
    const unsigned int n = fe.n_dofs_per_cell();
    double applied       = 0; // the load the masked quadrature applies [N]
    FullMatrix<double> Kc(n, n);
    Vector<double> fc(n);
    std::vector<types::global_dof_index> dofs(n);
    for (const auto &cell : dof.active_cell_iterators())
    {
      fv.reinit(cell);
      Kc = 0;
      fc = 0;
      for (unsigned int q = 0; q < quadrature.size(); ++q)
        for (unsigned int i = 0; i < n; ++i)
        {
          const unsigned int ci = fe.system_to_component_index(i).first;
          const Tensor<1, 3> gi = fv.shape_grad(i, q);
          for (unsigned int j = 0; j < n; ++j)
          {
            const unsigned int cj = fe.system_to_component_index(j).first;
            const Tensor<1, 3> gj = fv.shape_grad(j, q);
            // lambda div u div v + mu (grad u + grad u^T) : grad v, components ci and cj
            double k = lambda * gi[ci] * gj[cj] + mu * gi[cj] * gj[ci];
            if (ci == cj)
              k += mu * (gi * gj);
            Kc(i, j) += k * fv.JxW(q);
          }
        }
      for (const unsigned int face : cell->face_indices())
        if (cell->face(face)->at_boundary() && cell->face(face)->boundary_id() == 0)
        {
          ffv.reinit(cell, face);
          for (unsigned int q = 0; q < face_quadrature.size(); ++q)
          {
            const Point<3> &x = ffv.quadrature_point(q);
            if (std::atan2(x[0], x[1]) > alpha) // within alpha of the loaded diameter (y)
              continue;
            const Tensor<1, 3> traction = -pressure * ffv.normal_vector(q);
            applied -= traction[1] * ffv.JxW(q); // the eighth's share: P / 4 (a quarter rim)
            for (unsigned int i = 0; i < n; ++i)
              fc(i) += traction[fe.system_to_component_index(i).first] * ffv.shape_value(i, q) *
                       ffv.JxW(q);
          }
        }
      cell->get_dof_indices(dofs);
      constraints.distribute_local_to_global(Kc, fc, dofs, K, f);
    }

    SolverControl control(20000, 1e-12 * f.l2_norm());
    SolverCG<Vector<double>> cg(control);
    PreconditionSSOR<SparseMatrix<double>> ssor;
    ssor.initialize(K, 1.2);
    cg.solve(K, u, f, ssor);
    constraints.distribute(u);

    DiscReferenceProfile out;
    out.load = 4 * applied;
    for (const double r : rho)
    {
      out.rho.push_back(r);
      for (const double z : {0.0, half - face_depth})
      {
        std::vector<Tensor<1, 3>> grad(3);
        VectorTools::point_gradient(mapping, dof, u, Point<3>(0, r * R, z), grad);
        const double div = grad[0][0] + grad[1][1] + grad[2][2];
        const std::array<double, 6> sigma{
          {lambda * div + 2 * mu * grad[0][0], lambda * div + 2 * mu * grad[1][1],
           lambda * div + 2 * mu * grad[2][2], mu * (grad[0][1] + grad[1][0]),
           mu * (grad[1][2] + grad[2][1]), mu * (grad[0][2] + grad[2][0])}};
        (z == 0 ? out.mid_stress : out.face_stress).push_back(sigma);
      }
    }
    return out;
  }
} // namespace coupling
