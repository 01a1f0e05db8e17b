#pragma once
/// @file
/// An independent reference for the Brazilian disc's three-dimensional elastic field: a linear
/// elastic finite element solution (deal.II, 3-D, quadratic hexahedra on an eighth of the disc
/// with three symmetry planes, CG with SSOR) of a disc of diameter D and thickness t loaded
/// across a diameter by a uniform radial pressure over two rim arcs of half-angle alpha
/// (Hondros's load, on the whole thickness). It
/// tells how the tension across the loaded diameter varies through the thickness, which a plane
/// solution (Hondros) cannot. No deal.II types here.

#include <array>
#include <vector>

namespace coupling
{
  /// The disc reference's stress across the loaded diameter [Pa, tension +].
  struct DiscReferenceProfile
  {
    std::vector<double> rho; ///< distance from the centre along the loaded diameter / R [-]
    /// The stress on the mid-plane and on a face (face_depth inside it) at each rho: xx (across
    /// the load, in the disc's plane: the splitting tension), yy (along it), zz (through the
    /// thickness), xy, yz, xz [Pa, tension +]
    std::vector<std::array<double, 6>> mid_stress, face_stress;
    /// The resultant of each arc's pressure as applied [N]: the quadrature cuts the arc's ends
    /// (0.94 / 1.03 P at 2 / 3 refinements); normalise by it
    double load = 0;
  };

  /// The elastic disc under the load P = pressure x the arc's chord x thickness, sampled at `rho`
  /// (0 to below 1). `refinements`: global refinements of the eighth's mesh (three cells of a
  /// quarter disc, one layer through the half thickness; 3: 1,536 cells, 8 layers, 41,667
  /// dofs).
  DiscReferenceProfile elastic_disc_reference(double diameter, double thickness, double alpha,
                                              double youngs_modulus, double poissons_ratio,
                                              double load, const std::vector<double> &rho,
                                              unsigned int refinements, double face_depth = 0);
} // namespace coupling
