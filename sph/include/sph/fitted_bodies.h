#pragma once
/// @file
/// Body-fitted particle sets: the cylinder and the disc built of concentric rings, so that the
/// outer particles lie half a spacing inside the true round surface everywhere (a lattice cut out
/// of a cube grid has a staircase there, and a platen then touches a flat where the specimen is
/// round). Each set is a stack of equal layers along the body's axis; a layer is one centre
/// particle and rings k = 1..n at radius k dr, with dr = R / (n + 1/2), each ring holding an
/// even number of particles close to 2 pi k, placed symmetrically about both in-plane axes.
/// Volumes are the annuli's shares, ring k's annulus reaching from (k - 1/2) dr to (k + 1/2) dr
/// (the outer one to R exactly), so they sum to the true volume; spacing is near-uniform (dr
/// radially, 2 pi r / n_k around; every nearest-neighbour distance within 15 % of dx for D >=
/// 10 dx). The outer ring sits half a ring spacing inside the surface rather than on it, as a
/// lattice's outer cells do: a contact radius of dr/2 (cell_size / 2) then puts the particles'
/// contact surface on the true one, and every particle stands for a full annulus share. Returned
/// as a Lattice, so every user of a lattice takes them unchanged; cell_size holds (dr, dr, layer)
/// for the cylinder and (dr, layer, dr) for the disc.

#include <sph/lattice.h>

namespace sph
{
  /// Cylinder of diameter D and length L [m], axis z, base at z = 0, centred at x = y = 0 (the
  /// frame of make_cylinder). Layers along z spaced L / round(L / dx).
  Lattice<3> make_fitted_cylinder(double diameter, double length, double spacing);

  /// Brazilian disc of diameter D and thickness t [m], axis along y, |y| <= t/2, centre at
  /// (0, 0, D/2) (the frame of make_disc). Rings in the x-z plane, one particle of every ring
  /// on the loaded diameter x = 0 at the top and at the bottom; layers along y spaced
  /// t / round(t / dx). `flat_angle` > 0 [rad, at most max_flat_angle] makes it a flattened
  /// Brazilian disc: flats normal to z at z = D/2 -+ R cos(flat_angle / 2), the rings pulled in
  /// along their radii onto them (the outer ring's flat part then lies cos(flat_angle / 2) dr / 2
  /// inside each flat, cell_size[2] = cos(flat_angle / 2) dr), each volume its ring sector's image.
  Lattice<3> make_fitted_disc(double diameter, double thickness, double spacing,
                              double flat_angle = 0);
} // namespace sph
