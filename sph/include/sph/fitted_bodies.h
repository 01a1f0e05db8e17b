#pragma once
/// @file
/// Body-fitted particle sets: the cylinder and the disc built of concentric rings, so that the
/// outer particles lie half a spacing inside the true round surface everywhere (a lattice cut out
/// of a cube grid has a staircase there, and a platen then touches a flat where the specimen is
/// round). Each set is a stack of equal layers along the body's axis; a layer is one centre
/// particle and rings k = 1..n at radius k dr, with dr = R / (n + 1/2), each ring holding an
/// even number of particles close to 2 pi k, placed symmetrically about both in-plane axes.
/// Volumes are the annuli's shares, ring k's annulus reaching from (k - 1/2) dr to (k + 1/2) dr
/// (the outer one to R exactly), so they sum to the true volume (given the kernel, SummedWith,
/// the centre's and the first three rings' are then made consistent with it); spacing is
/// near-uniform (dr radially, 2 pi r / n_k around; every nearest-neighbour distance within 15 %
/// of dx for D >= 10 dx). The outer ring sits half a ring spacing inside the surface rather than on it, as a
/// lattice's outer cells do: a contact radius of dr/2 (cell_size / 2) then puts the particles'
/// contact surface on the true one, and every particle stands for a full annulus share. Returned
/// as a Lattice, so every user of a lattice takes them unchanged; cell_size holds (dr, dr, layer)
/// for the cylinder and (dr, layer, dr) for the disc.

#include <sph/kernels.h>
#include <sph/lattice.h>
#include <sph/parameters.h>

#include <optional>

namespace sph
{
  /// The kernel a body-fitted set will be summed with. Given it, the volumes of the centre
  /// particle and the first three rings of each layer are made consistent with it: each one's
  /// sum_j V_j W(x_i - x_j, h) equal to the mean of the next three rings' (the layers taken as
  /// continuing past the body's faces). The annuli's shares are not: the centre particle (pi/4
  /// dr^2) among ring 1's six of 1.05 dr^2 each (2 round(pi k) particles on ring k, 4.5 % short
  /// of 2 pi k for k <= 3) sums to 1.06, ring 1 to 1.03, where every particle from the fourth
  /// ring out sums to 0.998-1.0003 (1.25 mm, cubic spline, h 1.2 dx), and a non-uniform field
  /// sees a hard spot there: an elastic flattened disc's centre 22 % low in tension against the
  /// 3-D FE solution (now 6 %), a cylinder's axis particle in lateral tension under an uneven
  /// end load. The centre's volume becomes 0.684 dr^2 times the layer step (cubic spline; 0.70
  /// Wendland). Then the volumes are scaled to the true volume. A kernel too wide for these
  /// conditions to have a positive solution (from h = 1.9 dx on the 25 mm disc at 2.5 mm) makes
  /// the makers below throw std::domain_error.
  struct SummedWith
  {
    KernelType kernel = KernelType::cubic_spline;
    double     h      = 0; ///< smoothing length [m]
  };

  /// The kernel a Body with numerics `p` sums with (its h = CSLH dx, as Body sets it).
  inline SummedWith summed_with(const Parameters &p) { return {p.kernel, p.cslh * p.spacing}; }

  /// Cylinder of diameter D and length L [m], axis z, base at z = 0, centred at x = y = 0 (the
  /// frame of make_cylinder). Layers along z spaced L / round(L / dx).
  Lattice<3> make_fitted_cylinder(double diameter, double length, double spacing,
                                  const std::optional<SummedWith> &summed_with = std::nullopt);

  /// Brazilian disc of diameter D and thickness t [m], axis along y, |y| <= t/2, centre at
  /// (0, 0, D/2) (the frame of make_disc). Rings in the x-z plane, one particle of every ring
  /// on the loaded diameter x = 0 at the top and at the bottom; layers along y spaced
  /// t / round(t / dx). `flat_angle` > 0 [rad, at most max_flat_angle] makes it a flattened
  /// Brazilian disc: flats normal to z at z = D/2 -+ R cos(flat_angle / 2), the rings pulled in
  /// along their radii onto them (the outer ring's flat part then lies cos(flat_angle / 2) dr / 2
  /// inside each flat, cell_size[2] = cos(flat_angle / 2) dr), each volume its ring sector's image.
  Lattice<3> make_fitted_disc(double diameter, double thickness, double spacing,
                              double flat_angle = 0,
                              const std::optional<SummedWith> &summed_with = std::nullopt);
} // namespace sph
