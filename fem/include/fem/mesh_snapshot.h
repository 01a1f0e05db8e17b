#pragma once
/// @file
/// A steel body's mesh at one instant (platen or cutter), as plain arrays: what fem::SteelBody
/// gives, what the coupled drivers hand to RunObserver::snapshot and what the output writers
/// read. No deal.II here.

#include <cstddef>
#include <string>
#include <vector>

namespace fem
{
  /// Hexahedra with their 8 vertices in VTK hexahedron order (the writers do not re-map). Vertex
  /// arrays are flat 3-vectors x0,y0,z0,x1,...
  struct MeshSnapshot
  {
    std::string name;                    ///< the body in the output, e.g. "platen_top"; "" unnamed
    std::vector<double> position;        ///< deformed vertex positions x0 + u [m]
    std::vector<double> displacement;    ///< u [m]
    std::vector<double> velocity;        ///< v at the last half step [m/s]
    std::vector<unsigned int> hexahedra; ///< 8 vertex indices per cell, VTK_HEXAHEDRON order
    std::vector<double> von_mises;       ///< von Mises stress at each cell centre [Pa]
    std::size_t n_vertices() const { return position.size() / 3; }
    std::size_t n_cells() const { return hexahedra.size() / 8; }
  };

  /// Write a snapshot as a VTK XML unstructured grid (ASCII), readable by ParaView.
  /// Throws std::runtime_error naming the file if it cannot be written.
  void write_vtu(const MeshSnapshot &snapshot, const std::string &filename);
} // namespace fem
