// The implicit axisymmetric FE reference of the rock cylinder between platens
// (coupling/reference_cylinder.h). One triangulation holds the rock and, with elastic platens, the
// two platens as separate regions whose interface vertices are duplicated (the regions share no
// vertex); AffineConstraints tie the interface nodes (u_z, and u_r when bonded).
#include <coupling/errors.h>
#include <coupling/reference_cylinder.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q1.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparse_direct.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/vector.h>
#include <deal.II/numerics/vector_tools.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <string>

namespace coupling
{
  namespace
  {
    using namespace dealii;

    constexpr types::material_id rock_region = 0, bottom_platen_region = 1, top_platen_region = 2;

    /// Tensor3 (r -> 0, z -> 1, theta -> 2) of a Voigt strain (engineering shear).
    sph::Tensor3 strain_tensor(const Voigt4 &e)
    {
      sph::Tensor3 t = sph::Tensor3::Zero();
      t(0, 0)        = e[0];
      t(1, 1)        = e[1];
      t(2, 2)        = e[2];
      t(0, 1) = t(1, 0) = 0.5 * e[3];
      return t;
    }

    sph::Tensor3 stress_tensor(const Voigt4 &s)
    {
      sph::Tensor3 t = sph::Tensor3::Zero();
      t(0, 0)        = s[0];
      t(1, 1)        = s[1];
      t(2, 2)        = s[2];
      t(0, 1) = t(1, 0) = s[3];
      return t;
    }

    Voigt4 stress_voigt(const sph::Tensor3 &t)
    {
      return {{t(0, 0), t(1, 1), t(2, 2), 0.5 * (t(0, 1) + t(1, 0))}};
    }

    /// Isotropic elasticity in the Voigt order (rr, zz, tt, rz) with engineering shear [Pa].
    Tangent4 isotropic_tangent(const double K, const double G)
    {
      const double lambda = K - 2.0 / 3.0 * G;
      Tangent4 C{};
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          C[i][j] = lambda + (i == j ? 2.0 * G : 0.0);
      C[3][3] = G;
      return C;
    }

    /// A structured block of cells [r_0..r_n] x [z_0..z_m] with its own vertices.
    void add_block(const std::vector<double> &rs, const std::vector<double> &zs,
                   const types::material_id region, std::vector<Point<2>> &vertices,
                   std::vector<CellData<2>> &cells)
    {
      const unsigned int base = vertices.size(), nr = rs.size();
      for (const double z : zs)
        for (const double r : rs)
          vertices.emplace_back(r, z);
      for (unsigned int j = 0; j + 1 < zs.size(); ++j)
        for (unsigned int i = 0; i + 1 < nr; ++i)
        {
          CellData<2> c;
          c.vertices    = {base + j * nr + i, base + j * nr + i + 1, base + (j + 1) * nr + i,
                           base + (j + 1) * nr + i + 1};
          c.material_id = region;
          cells.push_back(c);
        }
    }

    /// n + 1 equally spaced coordinates from a to b.
    std::vector<double> lines(const double a, const double b, const unsigned int n)
    {
      std::vector<double> x(n + 1);
      for (unsigned int i = 0; i <= n; ++i)
        x[i] = a + (b - a) * i / n;
      x[n] = b;
      return x;
    }

    /// One Gauss point's converged and current state (rock only).
    struct PointState
    {
      Voigt4 stress{};              ///< converged stress [Pa]
      sph::MaterialState state;     ///< converged history
      Voigt4 stress_new{};          ///< stress of the current iterate [Pa]
      sph::MaterialState state_new; ///< history of the current iterate
    };

    /// Where a stress profile is sampled: (active cell index, quadrature index), sorted.
    struct SamplePoint
    {
      unsigned int cell, q;
      double r, z;
    };

    class ReferenceModel
    {
    public:
      ReferenceModel(const CaseParameters &prm, const ReferenceOptions &options);
      ReferenceResult run();

    private:
      void make_mesh();
      void make_constraints();
      /// Assembles the tangent and residual at `u` (converged state `u_old`); returns the
      /// residual norm of the free dofs and sets the axial force and the reaction norm.
      /// `elastic_tangent`: the rock's elastic stiffness in place of its tangent. `constraints`:
      /// those of the Newton update (constraints_, or with the increment's prescribed values).
      double assemble(const Vector<double> &u, const Vector<double> &u_old, bool elastic_tangent,
                      const AffineConstraints<double> &constraints);
      /// Newton from the predictor `u`; `predicted`: u extrapolates the last increments (else
      /// only its prescribed values are new, and the first iteration uses the elastic stiffness).
      bool solve_increment(Vector<double> &u, const Vector<double> &u_old, double displacement,
                           bool predicted, unsigned int &iterations);
      void set_prescribed(Vector<double> &u, double displacement) const;
      double end_face_mean_uz(const Vector<double> &u, double z) const;
      std::vector<ReferenceStressSample> samples(const std::vector<SamplePoint> &where) const;

      const CaseParameters &prm_;
      const ReferenceOptions options_;
      sph::MaterialParameters rock_;
      sph::rock::ModelConstants constants_;
      sph::rock::Model model_;
      Tangent4 rock_elastic_, steel_elastic_;
      double R_ = 0, L_ = 0, Rp_ = 0, t_ = 0;
      bool elastic_platens_ = false, bonded_ = false;

      Triangulation<2> tria_;
      FESystem<2> fe_;
      DoFHandler<2> dof_;
      QGauss<2> quadrature_;
      AffineConstraints<double> constraints_; ///< homogeneous: Dirichlet dofs and interface ties
      /// Dirichlet dofs and the factor of the platen displacement they take (0 or -1)
      std::vector<std::pair<types::global_dof_index, double>> prescribed_;
      std::vector<types::global_dof_index> loaded_dofs_; ///< u_z of the moving loaded face
      SparsityPattern pattern_;
      SparseMatrix<double> matrix_;
      Vector<double> rhs_, internal_force_;
      std::vector<PointState> points_;
      std::vector<SamplePoint> end_face_points_, axis_points_;
      double force_ = 0, reaction_norm_ = 0;
    };

    ReferenceModel::ReferenceModel(const CaseParameters &prm, const ReferenceOptions &options)
        : prm_(prm)
        , options_(options)
        , rock_(reference_rock(prm))
        , constants_(sph::rock::make_model_constants(rock_))
        , model_(sph::rock::make_model(rock_.model))
        , fe_(FE_Q<2>(options.degree), 2)
        , dof_(tria_)
        , quadrature_(options.degree + 1)
    {
      R_               = 0.5 * prm.diameter;
      L_               = prm.length;
      elastic_platens_ = options.platens == ReferencePlatens::elastic;
      bonded_          = options.interface == ReferenceInterface::bonded;
      Rp_              = 0.5 * reference_platen_diameter(prm);
      t_               = prm.platens.thickness;
      rock_elastic_    = isotropic_tangent(constants_.K, constants_.G);
      const double Es = prm.platens.steel.youngs_modulus, nus = prm.platens.steel.poissons_ratio;
      steel_elastic_ = isotropic_tangent(Es / (3.0 * (1.0 - 2.0 * nus)), Es / (2.0 * (1.0 + nus)));
    }

    void ReferenceModel::make_mesh()
    {
      const unsigned int n = options_.n_radial;
      const double h       = R_ / n;
      const auto nz        = [h](const double length) {
        return std::max(1u, static_cast<unsigned int>(std::lround(length / h)));
      };
      std::vector<Point<2>> vertices;
      std::vector<CellData<2>> cells;
      const std::vector<double> rock_r = lines(0, R_, n);
      add_block(rock_r, lines(0, L_, nz(L_)), rock_region, vertices, cells);
      if (elastic_platens_)
      {
        // the platen's radial lines are the rock's, continued to the platen's rim
        std::vector<double> platen_r = rock_r;
        if (Rp_ > R_ * (1 + 1e-12))
        {
          const std::vector<double> outer = lines(R_, Rp_, nz(Rp_ - R_));
          platen_r.insert(platen_r.end(), outer.begin() + 1, outer.end());
        }
        add_block(platen_r, lines(-t_, 0, nz(t_)), bottom_platen_region, vertices, cells);
        add_block(platen_r, lines(L_, L_ + t_, nz(t_)), top_platen_region, vertices, cells);
      }
      tria_.create_triangulation(vertices, cells, SubCellData());
    }

    void ReferenceModel::make_constraints()
    {
      dof_.distribute_dofs(fe_);
      std::vector<Point<2>> support(dof_.n_dofs());
      DoFTools::map_dofs_to_support_points(MappingQ1<2>(), dof_, support);
      const double tol = 1e-9 * std::max(L_, R_);

      // classify the boundary dofs by the face they lie on
      std::vector<types::global_dof_index> face_dofs(fe_.n_dofs_per_face());
      std::map<types::global_dof_index, unsigned int> axis, rock_bottom, rock_top, platen_bottom,
        platen_top, loaded_bottom, loaded_top; // dof -> component
      for (const auto &cell : dof_.active_cell_iterators())
        for (const unsigned int f : cell->face_indices())
        {
          const Point<2> c                                     = cell->face(f)->center();
          const auto region                                    = cell->material_id();
          std::map<types::global_dof_index, unsigned int> *set = nullptr;
          if (std::abs(c[0]) < tol)
            set = &axis;
          else if (region == rock_region && std::abs(c[1]) < tol)
            set = &rock_bottom;
          else if (region == rock_region && std::abs(c[1] - L_) < tol)
            set = &rock_top;
          else if (region == bottom_platen_region && std::abs(c[1]) < tol)
            set = &platen_bottom;
          else if (region == top_platen_region && std::abs(c[1] - L_) < tol)
            set = &platen_top;
          else if (region == bottom_platen_region && std::abs(c[1] + t_) < tol)
            set = &loaded_bottom;
          else if (region == top_platen_region && std::abs(c[1] - L_ - t_) < tol)
            set = &loaded_top;
          if (set == nullptr)
            continue;
          cell->face(f)->get_dof_indices(face_dofs);
          for (unsigned int i = 0; i < face_dofs.size(); ++i)
            (*set)[face_dofs[i]] = fe_.face_system_to_component_index(i).first;
        }

      constraints_.clear();
      prescribed_.clear();
      loaded_dofs_.clear();
      const auto prescribe = [&](const types::global_dof_index d, const double factor) {
        if (constraints_.is_constrained(d))
          return;
        constraints_.add_line(d);
        prescribed_.emplace_back(d, factor);
      };
      // the axis: u_r = 0
      for (const auto &[d, c] : axis)
        if (c == 0)
          prescribe(d, 0.0);
      // the fixed (bottom) and moving (top) loaded faces: u_z given; u_r held where the platen is
      // bonded (rigid) or its loaded face is clamped laterally (elastic)
      const bool hold_r =
        elastic_platens_ ? prm_.platens.steel.loaded_face_lateral == fem::LoadedFaceLateral::fixed
                         : bonded_;
      const auto &bottom = elastic_platens_ ? loaded_bottom : rock_bottom;
      const auto &top    = elastic_platens_ ? loaded_top : rock_top;
      for (const auto &[d, c] : bottom)
        if (c == 1 || hold_r)
          prescribe(d, 0.0);
      for (const auto &[d, c] : top)
      {
        if (c == 1)
        {
          prescribe(d, -1.0);
          loaded_dofs_.push_back(d);
        }
        else if (hold_r)
          prescribe(d, 0.0);
      }
      // interface ties: each rock node takes the coincident platen node's displacement
      if (elastic_platens_)
      {
        const auto key = [&](const types::global_dof_index d, const unsigned int c) {
          return std::make_pair(std::lround(support[d][0] / tol), c);
        };
        for (const auto &[rock_face, platen_face] :
             {std::make_pair(&rock_bottom, &platen_bottom), std::make_pair(&rock_top, &platen_top)})
        {
          std::map<std::pair<long, unsigned int>, types::global_dof_index> platen_nodes;
          for (const auto &[d, c] : *platen_face)
            platen_nodes[key(d, c)] = d;
          for (const auto &[d, c] : *rock_face)
          {
            if (c == 0 && !bonded_)
              continue; // free slip: u_r of the rock is its own
            if (constraints_.is_constrained(d))
              continue; // on the axis: u_r = 0 on both sides
            const auto it = platen_nodes.find(key(d, c));
            if (it == platen_nodes.end())
              throw std::logic_error(
                "reference_cylinder: the platen mesh does not conform to the rock's");
            constraints_.add_line(d);
            constraints_.add_entry(d, it->second, 1.0);
          }
        }
      }
      constraints_.close();

      DynamicSparsityPattern dsp(dof_.n_dofs());
      DoFTools::make_sparsity_pattern(dof_, dsp, constraints_, false);
      pattern_.copy_from(dsp);
      matrix_.reinit(pattern_);
      rhs_.reinit(dof_.n_dofs());
      internal_force_.reinit(dof_.n_dofs());

      // Gauss-point storage and the profile sample points
      const unsigned int nq = quadrature_.size();
      points_.assign(tria_.n_active_cells() * nq, PointState{});
      FEValues<2> fev(fe_, quadrature_, update_quadrature_points);
      const double h = R_ / options_.n_radial;
      for (const auto &cell : dof_.active_cell_iterators())
      {
        if (cell->material_id() != rock_region)
          continue;
        fev.reinit(cell);
        const auto &x     = fev.get_quadrature_points();
        const double zmax = cell->center()[1] + 0.5 * cell->extent_in_direction(1);
        const double rmin = cell->center()[0] - 0.5 * cell->extent_in_direction(0);
        double top_z = -1e300, low_r = 1e300;
        for (unsigned int q = 0; q < nq; ++q)
          top_z = std::max(top_z, x[q][1]), low_r = std::min(low_r, x[q][0]);
        for (unsigned int q = 0; q < nq; ++q)
        {
          const SamplePoint s{cell->active_cell_index(), q, x[q][0], x[q][1]};
          if (std::abs(zmax - L_) < 1e-6 * h && std::abs(x[q][1] - top_z) < 1e-9 * h)
            end_face_points_.push_back(s);
          if (std::abs(rmin) < 1e-6 * h && std::abs(x[q][0] - low_r) < 1e-9 * h)
            axis_points_.push_back(s);
        }
      }
      std::sort(end_face_points_.begin(), end_face_points_.end(),
                [](const SamplePoint &a, const SamplePoint &b) { return a.r < b.r; });
      std::sort(axis_points_.begin(), axis_points_.end(),
                [](const SamplePoint &a, const SamplePoint &b) { return a.z < b.z; });
    }

    void ReferenceModel::set_prescribed(Vector<double> &u, const double displacement) const
    {
      for (const auto &[d, factor] : prescribed_)
        u[d] = factor * displacement;
      // the ties copy the platens' interface values onto the rock; distribute() zeroes the
      // Dirichlet lines, so their values are set again
      constraints_.distribute(u);
      for (const auto &[d, factor] : prescribed_)
        u[d] = factor * displacement;
    }

    double ReferenceModel::assemble(const Vector<double> &u, const Vector<double> &u_old,
                                    const bool elastic_tangent,
                                    const AffineConstraints<double> &constraints)
    {
      matrix_         = 0;
      rhs_            = 0;
      internal_force_ = 0;
      FEValues<2> fev(fe_, quadrature_,
                      update_values | update_gradients | update_quadrature_points |
                        update_JxW_values);
      const unsigned int n = fe_.n_dofs_per_cell(), nq = quadrature_.size();
      FullMatrix<double> cell_matrix(n, n);
      Vector<double> cell_rhs(n), cell_force(n);
      std::vector<types::global_dof_index> dofs(n);
      std::vector<std::array<double, 4>> B(n);
      std::vector<double> u_cell(n), u_old_cell(n);
      for (const auto &cell : dof_.active_cell_iterators())
      {
        fev.reinit(cell);
        cell->get_dof_indices(dofs);
        for (unsigned int i = 0; i < n; ++i)
          u_cell[i] = u[dofs[i]], u_old_cell[i] = u_old[dofs[i]];
        cell_matrix     = 0;
        cell_force      = 0;
        const bool rock = cell->material_id() == rock_region;
        for (unsigned int q = 0; q < nq; ++q)
        {
          const double r = fev.quadrature_point(q)[0];
          const double w = fev.JxW(q) * 2.0 * M_PI * r;
          Voigt4 eps{}, eps_old{};
          for (unsigned int i = 0; i < n; ++i)
          {
            const unsigned int c = fe_.system_to_component_index(i).first;
            const auto g         = fev.shape_grad_component(i, q, c);
            if (c == 0)
              B[i] = {{g[0], 0.0, fev.shape_value_component(i, q, 0) / r, g[1]}};
            else
              B[i] = {{0.0, g[1], 0.0, g[0]}};
            for (int k = 0; k < 4; ++k)
              eps[k] += B[i][k] * u_cell[i], eps_old[k] += B[i][k] * u_old_cell[i];
          }
          Voigt4 sigma{};
          const Tangent4 *C = &steel_elastic_;
          Tangent4 tangent;
          if (rock)
          {
            PointState &p = points_[cell->active_cell_index() * nq + q];
            Voigt4 de;
            for (int k = 0; k < 4; ++k)
              de[k] = eps[k] - eps_old[k];
            const ReferencePointUpdate up =
              reference_point_update(model_, constants_, p.stress, p.state, de);
            p.stress_new = up.stress;
            p.state_new  = up.state;
            sigma        = up.stress;
            tangent      = up.tangent;
            C            = elastic_tangent ? &rock_elastic_ : &tangent;
          }
          else
            for (int a = 0; a < 4; ++a)
              for (int b = 0; b < 4; ++b)
                sigma[a] += steel_elastic_[a][b] * eps[b];
          for (unsigned int i = 0; i < n; ++i)
          {
            double bs = 0;
            std::array<double, 4> BC{};
            for (int a = 0; a < 4; ++a)
            {
              bs += B[i][a] * sigma[a];
              for (int b = 0; b < 4; ++b)
                BC[b] += B[i][a] * (*C)[a][b];
            }
            cell_force[i] += bs * w;
            for (unsigned int j = 0; j < n; ++j)
              cell_matrix(i, j) +=
                (BC[0] * B[j][0] + BC[1] * B[j][1] + BC[2] * B[j][2] + BC[3] * B[j][3]) * w;
          }
        }
        for (unsigned int i = 0; i < n; ++i)
          cell_rhs[i] = -cell_force[i];
        constraints.distribute_local_to_global(cell_matrix, cell_rhs, dofs, matrix_, rhs_);
        internal_force_.add(dofs, cell_force);
      }
      force_ = 0;
      for (const auto d : loaded_dofs_)
        force_ -= internal_force_[d];
      reaction_norm_ = 0;
      for (const auto &pd : prescribed_)
        reaction_norm_ += internal_force_[pd.first] * internal_force_[pd.first];
      reaction_norm_ = std::sqrt(reaction_norm_);
      return rhs_.l2_norm();
    }

    bool ReferenceModel::solve_increment(Vector<double> &u, const Vector<double> &u_old,
                                         const double displacement, const bool predicted,
                                         unsigned int &iterations)
    {
      // a force scale for the residual: 1e-6 of the rock's elastic stiffness times its area
      const double floor = 1e-6 * rock_.youngs_modulus * M_PI * R_ * R_;
      Vector<double> du(u.size());
      const auto solve = [&]() {
        SparseDirectUMFPACK solver;
        try
        {
          solver.initialize(matrix_);
          du = rhs_;
          solver.solve(du);
        }
        catch (const std::exception &)
        {
          return false; // a singular tangent: the increment is halved
        }
        return true;
      };
      iterations = 0;
      if (predicted)
        set_prescribed(u, displacement);
      else
      {
        // elastic step from the converged state with the increment of the prescribed values: for
        // an elastic increment, the solution
        AffineConstraints<double> step;
        step.copy_from(constraints_);
        for (const auto &[d, factor] : prescribed_)
          step.set_inhomogeneity(d, factor * displacement - u_old[d]);
        assemble(u_old, u_old, true, step);
        if (!solve())
          return false;
        step.distribute(du);
        u = u_old;
        u += du;
        set_prescribed(u, displacement); // the exact values, free of round-off
        ++iterations;
      }
      // Newton with a backtracking line search on the residual norm: the return mapping switches
      // between the plane, edge and apex returns, and a full step can cycle between them
      double res = assemble(u, u_old, false, constraints_);
      for (; iterations < 25; ++iterations)
      {
        if (!std::isfinite(res))
          return false;
        // 1e-7: sph's update decides elastic or plastic from closed-form eigenvalues (accurate
        // to ~1e-8 of the stress where two are close) and calls a return of under 1e-9 of the
        // stress elastic; points on the surface thus carry stress noise of ~1e-8, which summed
        // over ~1e3 plastic points sets a floor of the residual near 1e-8 of the reaction
        if (res <= 1e-7 * std::max(reaction_norm_, floor))
          return true;
        if (!solve())
          return false;
        constraints_.distribute(du);
        double alpha = 1.0;
        u += du;
        double trial = assemble(u, u_old, false, constraints_);
        for (int cut = 0; cut < 8 && !(trial < res); ++cut)
        {
          u.add(-0.5 * alpha, du);
          alpha *= 0.5;
          trial = assemble(u, u_old, false, constraints_);
        }
        res = trial;
      }
      return false;
    }

    double ReferenceModel::end_face_mean_uz(const Vector<double> &u, const double z) const
    {
      const QGauss<1> face_quadrature(options_.degree + 1);
      FEFaceValues<2> fv(fe_, face_quadrature,
                         update_values | update_quadrature_points | update_JxW_values);
      std::vector<Vector<double>> values(face_quadrature.size(), Vector<double>(2));
      double integral = 0, area = 0;
      for (const auto &cell : dof_.active_cell_iterators())
      {
        if (cell->material_id() != rock_region)
          continue;
        for (const unsigned int f : cell->face_indices())
          if (std::abs(cell->face(f)->center()[1] - z) < 1e-9 * L_)
          {
            fv.reinit(cell, f);
            fv.get_function_values(u, values);
            for (unsigned int q = 0; q < face_quadrature.size(); ++q)
            {
              const double w = fv.JxW(q) * 2.0 * M_PI * fv.quadrature_point(q)[0];
              integral += values[q][1] * w;
              area += w;
            }
          }
      }
      return integral / area;
    }

    std::vector<ReferenceStressSample>
    ReferenceModel::samples(const std::vector<SamplePoint> &where) const
    {
      const unsigned int nq = quadrature_.size();
      std::vector<ReferenceStressSample> out;
      for (const auto &s : where)
      {
        const Voigt4 &sigma = points_[s.cell * nq + s.q].stress;
        out.push_back({s.r, s.z, -sigma[1], -sigma[0]});
      }
      return out;
    }

    ReferenceResult ReferenceModel::run()
    {
      const auto start = std::chrono::steady_clock::now();
      make_mesh();
      make_constraints();
      ReferenceResult result;
      result.n_cells         = tria_.n_active_cells();
      result.n_dofs          = dof_.n_dofs();
      result.platen_diameter = elastic_platens_ ? 2.0 * Rp_ : 0.0;
      const double area      = M_PI * R_ * R_;

      Vector<double> u(dof_.n_dofs()), u_old(dof_.n_dofs()), u_older(dof_.n_dofs());
      std::vector<std::vector<ReferenceStressSample>> face_history, axis_history;
      result.curve.push_back({});
      face_history.push_back(samples(end_face_points_));
      axis_history.push_back(samples(axis_points_));

      const double final_displacement = options_.end_strain * L_;
      const double step               = final_displacement / options_.n_increments;
      double done = 0, last_step = 0, dstep = step;
      unsigned int halvings = 0;
      while (done < final_displacement * (1 - 1e-12))
      {
        const double target = std::min(done + dstep, final_displacement);
        // predictor: the last increment's displacement field, scaled
        u = u_old;
        if (last_step > 0)
          u.add((target - done) / last_step, u_old), u.add(-(target - done) / last_step, u_older);
        unsigned int iterations = 0;
        if (!solve_increment(u, u_old, target, last_step > 0, iterations))
        {
          if (++halvings > 4)
          {
            // the curve ends here; where the rock's flow is strongly non-associated this happens
            // near the peak, where the tangent loses definiteness and the solution its uniqueness
            result.end_reason = "Newton did not converge at platen displacement " +
                                std::to_string(target * 1e3) + " mm (4 halvings of the increment)";
            result.n_newton_iterations += iterations;
            break;
          }
          ++result.n_cutbacks;
          dstep *= 0.5;
          result.n_newton_iterations += iterations;
          continue;
        }
        result.n_newton_iterations += iterations;
        for (auto &p : points_)
          p.stress = p.stress_new, p.state = p.state_new;
        u_older   = u_old;
        u_old     = u;
        last_step = target - done;
        done      = target;
        dstep     = std::min(step, 2 * dstep);
        halvings  = 0;

        ReferenceCurveRow row;
        row.platen_displacement = done;
        row.strain              = (end_face_mean_uz(u, 0.0) - end_face_mean_uz(u, L_)) / L_;
        Vector<double> mid(2);
        VectorTools::point_value(dof_, u, Point<2>(R_, 0.5 * L_), mid);
        row.radial_strain = mid[0] / R_;
        row.force         = force_;
        row.stress        = force_ / area;
        row.iterations    = iterations;
        result.curve.push_back(row);
        face_history.push_back(samples(end_face_points_));
        axis_history.push_back(samples(axis_points_));
        // perfect plasticity: the load stays at the limit load once the body flows
        const std::size_t n = result.curve.size();
        if (n > 4)
        {
          bool flat = true;
          for (std::size_t i = n - 3; i < n; ++i)
            flat = flat && std::abs(result.curve[i].force - result.curve[i - 1].force) <=
                             1e-7 * result.curve[i].force;
          if (flat)
          {
            result.end_reason = "limit load: the force stayed within 1e-7 over three increments";
            break;
          }
        }
      }
      if (result.end_reason.empty())
        result.end_reason = "end strain";

      // the peak: the first increment within 1e-7 of the largest force (on a plateau, where
      // the limit load is first reached)
      double largest = 0;
      for (const auto &row : result.curve)
        largest = std::max(largest, row.force);
      std::size_t peak = 0;
      while (result.curve[peak].force < largest * (1 - 1e-7))
        ++peak;
      result.peak_force           = result.curve[peak].force;
      result.peak_stress          = result.curve[peak].stress;
      result.strain_at_peak       = result.curve[peak].strain;
      result.displacement_at_peak = result.curve[peak].platen_displacement;
      // the profiles at half the peak, on the way up: linear in the force between two increments
      result.half_peak_force = 0.5 * result.peak_force;
      std::size_t k          = 1;
      while (k < peak && result.curve[k].force < result.half_peak_force)
        ++k;
      const double f0 = result.curve[k - 1].force, f1 = result.curve[k].force;
      const double a =
        f1 > f0 ? std::clamp((result.half_peak_force - f0) / (f1 - f0), 0.0, 1.0) : 1.0;
      const auto blend = [a](const std::vector<ReferenceStressSample> &s0,
                             const std::vector<ReferenceStressSample> &s1) {
        std::vector<ReferenceStressSample> out = s1;
        for (std::size_t i = 0; i < out.size(); ++i)
        {
          out[i].axial_stress  = (1 - a) * s0[i].axial_stress + a * s1[i].axial_stress;
          out[i].radial_stress = (1 - a) * s0[i].radial_stress + a * s1[i].radial_stress;
        }
        return out;
      };
      result.end_face = blend(face_history[k - 1], face_history[k]);
      result.axis     = blend(axis_history[k - 1], axis_history[k]);
      result.wall_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      return result;
    }
  } // namespace

  sph::MaterialParameters reference_rock(const CaseParameters &prm)
  {
    sph::MaterialParameters m = prm.rock;
    m.softening_strain        = 0.0;
    m.residual_fraction       = 1.0;
    m.residual_friction_angle = -1.0;
    return m;
  }

  double reference_platen_diameter(const CaseParameters &prm)
  {
    // as the coupled driver builds its platens (specimen_driver.cc, build_platens)
    return cylinder_platen_diameter(prm);
  }

  ReferencePointUpdate reference_point_update(const sph::rock::Model &model,
                                              const sph::rock::ModelConstants &constants,
                                              const Voigt4 &stress_old,
                                              const sph::MaterialState &state_old,
                                              const Voigt4 &strain_increment)
  {
    const sph::Tensor3 s_old = stress_tensor(stress_old);
    const auto update        = [&](const Voigt4 &de) {
      return std::visit(
        [&](const auto &m) { return m(s_old, strain_tensor(de), state_old, constants); }, model);
    };
    const sph::rock::StressUpdate base = update(strain_increment);
    ReferencePointUpdate out;
    out.stress = stress_voigt(base.stress);
    out.state  = base.state;
    // elastic where the return changed nothing
    const sph::Tensor3 trial =
      sph::rock::elastic_trial(s_old, strain_tensor(strain_increment), constants);
    const double scale = 1e-12 * (trial.cwiseAbs().maxCoeff() + constants.cohesion);
    out.plastic        = (base.stress - trial).cwiseAbs().maxCoeff() > scale;
    if (!out.plastic)
    {
      out.tangent = isotropic_tangent(constants.K, constants.G);
      return out;
    }
    constexpr double h = 1e-9; // central differences; the strains are ~1e-4..1e-2
    for (int k = 0; k < 4; ++k)
    {
      Voigt4 dp = strain_increment, dm = strain_increment;
      dp[k] += h;
      dm[k] -= h;
      const Voigt4 sp = stress_voigt(update(dp).stress), sm = stress_voigt(update(dm).stress);
      for (int i = 0; i < 4; ++i)
        out.tangent[i][k] = (sp[i] - sm[i]) / (2 * h);
    }
    return out;
  }

  ReferenceResult run_reference_cylinder(const CaseParameters &prm, const ReferenceOptions &options)
  {
    if (prm.test != "UCS")
      throw InputError("reference: Test/Type = " + prm.test +
                       ": the reference models the UCS cylinder only");
    if (options.degree < 1 || options.degree > 2)
      throw InputError("reference: degree " + std::to_string(options.degree) + ": accepted 1 or 2");
    if (options.n_radial < 1 || options.n_radial > 256)
      throw InputError("reference: mesh " + std::to_string(options.n_radial) +
                       ": elements across the radius must be in [1, 256]");
    if (options.n_increments < 1 || options.n_increments > 100000)
      throw InputError("reference: increments " + std::to_string(options.n_increments) +
                       ": must be in [1, 100000]");
    if (!(options.end_strain > 0 && options.end_strain < 0.2))
      throw InputError("reference: end strain " + std::to_string(options.end_strain) +
                       ": must be in (0, 0.2)");
    ReferenceModel model(prm, options);
    return model.run();
  }
} // namespace coupling
