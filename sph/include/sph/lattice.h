#pragma once
/// @file
/// Particle lattices for the laboratory specimens. Particles sit at the cell centres of a lattice
/// of spacing dx; their volumes are scaled so that they sum to the true body volume. Particles
/// are emitted in the Morton (Z-order) curve order of their cells, which the solver keeps:
/// neighbours in space are close in memory at every body size (linear scaling in N). The loading axis is the last coordinate (z in 3-D,
/// y in 2-D, where "z" below means the last coordinate).

#include <sph/types.h>

#include <vector>

namespace sph
{
  /// Positions and volumes of a particle body, with the cross-section areas the tests report.
  template <int dim>
  struct Lattice
  {
    std::vector<Vector<dim>> positions; ///< cell centres [m]
    std::vector<double>      volumes;   ///< particle volumes [m^dim], sum = true body volume
    double spacing = 0;                 ///< lattice spacing dx [m]
    /// Edge lengths of a lattice cell along each axis [m]: dx, except along an axis whose side
    /// dx does not divide (the cylinder's axis, the disc's thickness, a block's sides), where the
    /// side is split into round(side/dx) equal cells. A particle reaches half a cell out.
    Vector<dim> cell_size = Vector<dim>::Zero();
    /// Cross-section normal to the loading axis (UCS / CTCS) or, for a disc, the diametral plane
    /// x = 0 that splits (BTS): number of particles in one lattice layer times dx^(dim-1)
    /// [m^(dim-1)].
    double lattice_section_area = 0;
    /// The same section of the true (smooth) body [m^(dim-1)]: pi D^2/4 for a cylinder, D t for
    /// a disc, the block's face for a block. Divide loads by this one ("real section area").
    double true_section_area = 0;
    double true_volume       = 0; ///< volume of the true body [m^dim]
  };

  /// Cylinder of diameter D and length L [m]: axis z, base at z = 0, centred at x = y = 0.
  /// In 2-D: its axial section, the rectangle |x| <= D/2, 0 <= y <= L (plane strain).
  /// Layers along the axis are spaced exactly L/round(L/dx) (= dx when L/dx is an integer).
  template <int dim>
  Lattice<dim> make_cylinder(double diameter, double length, double spacing);

  /// Largest loading angle 2 alpha of a flattened disc [rad] (60 degrees; the flattened
  /// Brazilian test uses about 20).
  constexpr double max_flat_angle = 1.0471975511965976;

  /// Brazilian disc of diameter D and thickness t [m]: its axis along y, |y| <= t/2, centre at
  /// (0, 0, D/2) so that its lowest point is at z = 0 and the load acts along z.
  /// In 2-D: the circle of diameter D centred at (0, D/2) (plane strain).
  /// `flat_angle` > 0 [rad] makes it a flattened Brazilian disc: two flats normal to z, each
  /// 2 R sin(flat_angle / 2) wide, at z = D/2 -+ R cos(flat_angle / 2); the rows along z are then
  /// H / round(H / dx) apart, H = D cos(flat_angle / 2), so that the outer rows reach the flats
  /// (cell_size[z] holds that row distance). 0: the round disc, rows dx apart. At most
  /// max_flat_angle.
  template <int dim>
  Lattice<dim> make_disc(double diameter, double thickness, double spacing, double flat_angle = 0);

  /// Box [lower, upper] [m]; each side is split into round(side/dx) cells (at least one).
  template <int dim>
  Lattice<dim> make_block(const Vector<dim> &lower, const Vector<dim> &upper, double spacing);
} // namespace sph
