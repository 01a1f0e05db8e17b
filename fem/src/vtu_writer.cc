/// @file
/// VTK XML unstructured-grid writer for fem::MeshSnapshot (no deal.II: plain arrays in).

#include <fem/steel_body.h>

#include <fstream>
#include <iomanip>
#include <stdexcept>

namespace fem
{
  namespace
  {
    void write_vector_array(std::ofstream &out, const char *name, const std::vector<double> &a)
    {
      out << "        <DataArray type=\"Float64\" Name=\"" << name
          << "\" NumberOfComponents=\"3\" format=\"ascii\">\n";
      for (std::size_t i = 0; i < a.size(); i += 3)
        out << "          " << a[i] << ' ' << a[i + 1] << ' ' << a[i + 2] << '\n';
      out << "        </DataArray>\n";
    }
  } // namespace

  void write_vtu(const MeshSnapshot &s, const std::string &filename)
  {
    std::ofstream out(filename);
    if (!out)
      throw std::runtime_error("fem::write_vtu: cannot open '" + filename +
                               "' for writing; does its folder exist and is it writable?");
    out << std::setprecision(10);
    const std::size_t n_points = s.n_vertices();
    const std::size_t n_cells  = s.n_cells();
    out << "<?xml version=\"1.0\"?>\n"
        << "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
        << "  <UnstructuredGrid>\n"
        << "    <Piece NumberOfPoints=\"" << n_points << "\" NumberOfCells=\"" << n_cells << "\">\n"
        << "      <Points>\n";
    write_vector_array(out, "position", s.position);
    out << "      </Points>\n      <Cells>\n"
        << "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
    for (std::size_t c = 0; c < n_cells; ++c)
    {
      out << "         ";
      for (unsigned int k = 0; k < 8; ++k)
        out << ' ' << s.hexahedra[8 * c + k];
      out << '\n';
    }
    out << "        </DataArray>\n"
        << "        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
    for (std::size_t c = 0; c < n_cells; ++c)
      out << "          " << 8 * (c + 1) << '\n';
    out << "        </DataArray>\n"
        << "        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
    for (std::size_t c = 0; c < n_cells; ++c)
      out << "          12\n"; // VTK_HEXAHEDRON
    out << "        </DataArray>\n      </Cells>\n      <PointData Vectors=\"displacement\">\n";
    write_vector_array(out, "displacement", s.displacement);
    if (s.velocity.size() == s.position.size())
      write_vector_array(out, "velocity", s.velocity);
    out << "      </PointData>\n      <CellData Scalars=\"von_mises\">\n"
        << "        <DataArray type=\"Float64\" Name=\"von_mises\" format=\"ascii\">\n";
    for (const double vm : s.von_mises)
      out << "          " << vm << '\n';
    out << "        </DataArray>\n      </CellData>\n    </Piece>\n  </UnstructuredGrid>\n"
        << "</VTKFile>\n";
    if (!out)
      throw std::runtime_error("fem::write_vtu: writing '" + filename + "' failed");
  }
} // namespace fem
