#include "io/vtu_writer.hpp"

#include <iterator>

#include <fmt/format.h>

#include "core/error.hpp"
#include "io/atomic_file.hpp"

namespace fdem {

namespace {

using Buffer = fmt::memory_buffer;

void begin(Buffer& out, std::size_t points, std::size_t cells, double time_s) {
  fmt::format_to(std::back_inserter(out),
                 "<?xml version=\"1.0\"?>\n"
                 "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
                 "header_type=\"UInt64\">\n"
                 "<UnstructuredGrid>\n"
                 "<FieldData>\n"
                 "<DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"ascii\">{}</DataArray>\n"
                 "</FieldData>\n"
                 "<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n",
                 time_s, points, cells);
}

void end(Buffer& out) { fmt::format_to(std::back_inserter(out), "</Piece>\n</UnstructuredGrid>\n</VTKFile>\n"); }

template <class Value>
void data_array(Buffer& out, const char* type, const std::string& name, int components, std::size_t entries,
                Value&& value) {
  fmt::format_to(std::back_inserter(out), "<DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\" format=\"ascii\">\n",
                 type, name, components);
  for (std::size_t i = 0; i < entries; ++i) {
    for (int c = 0; c < components; ++c) {
      if (c > 0) out.push_back(' ');
      fmt::format_to(std::back_inserter(out), "{}", value(i, c));
    }
    out.push_back('\n');
  }
  fmt::format_to(std::back_inserter(out), "</DataArray>\n");
}

void field(Buffer& out, const Field& f, std::size_t entries, const char* where) {
  if (f.entries() != entries) {
    throw SolverError(fmt::format("output field '{}' has {} entries, the mesh {} {}", f.name, f.entries(), entries, where));
  }
  data_array(out, "Float64", f.name, f.components, entries, [&](std::size_t i, int c) { return f.at(i, c); });
}

std::span<const double> or_empty(const std::vector<double>& v, std::size_t n) {
  return v.size() == n ? std::span<const double>(v) : std::span<const double>();
}

}  // namespace

Field Field::scalar(std::string name, std::span<const double> values) {
  Field f;
  f.name = std::move(name);
  f.components = 1;
  f.interleaved = values;
  return f;
}
Field Field::vector_interleaved(std::string name, std::span<const double> xyz) {
  Field f;
  f.name = std::move(name);
  f.components = 3;
  f.interleaved = xyz;
  return f;
}
Field Field::vector_separate(std::string name, std::span<const double> x, std::span<const double> y,
                             std::span<const double> z) {
  Field f;
  f.name = std::move(name);
  f.components = 3;
  f.separate = {x, y, z};
  f.is_separate = true;
  if (x.size() != y.size() || x.size() != z.size()) {
    throw SolverError(fmt::format("output field '{}': components of unequal length", f.name));
  }
  return f;
}
std::size_t Field::entries() const {
  return is_separate ? separate[0].size() : interleaved.size() / static_cast<std::size_t>(components);
}

std::string particles_vtu(const Particles& p, double time_s) {
  const std::size_t n = p.size();
  Buffer out;
  begin(out, n, n, time_s);
  out.append(std::string_view("<PointData Scalars=\"diameter\" Vectors=\"velocity\">\n"));
  data_array(out, "Float64", "diameter", 1, n, [&](std::size_t i, int) { return p.diameter[i]; });
  data_array(out, "Float64", "mass", 1, n, [&](std::size_t i, int) { return p.mass[i]; });
  data_array(out, "Float64", "velocity", 3, n, [&](std::size_t i, int c) { return c == 0 ? p.vx[i] : c == 1 ? p.vy[i] : p.vz[i]; });
  const auto fx = or_empty(p.fx, n), fy = or_empty(p.fy, n), fz = or_empty(p.fz, n);
  const bool has_force = !fx.empty() && !fy.empty() && !fz.empty();
  data_array(out, "Float64", "force", 3, n, [&](std::size_t i, int c) {
    return has_force ? (c == 0 ? fx[i] : c == 1 ? fy[i] : fz[i]) : 0.0;
  });
  if (p.wx.size() == n && p.wy.size() == n && p.wz.size() == n && n > 0) {
    data_array(out, "Float64", "angular_velocity", 3, n,
               [&](std::size_t i, int c) { return c == 0 ? p.wx[i] : c == 1 ? p.wy[i] : p.wz[i]; });
  }
  out.append(std::string_view("</PointData>\n<Points>\n"));
  data_array(out, "Float64", "Points", 3, n, [&](std::size_t i, int c) { return c == 0 ? p.x[i] : c == 1 ? p.y[i] : p.z[i]; });
  out.append(std::string_view("</Points>\n<Cells>\n"));
  data_array(out, "Int64", "connectivity", 1, n, [](std::size_t i, int) { return i; });
  data_array(out, "Int64", "offsets", 1, n, [](std::size_t i, int) { return i + 1; });
  data_array(out, "UInt8", "types", 1, n, [](std::size_t, int) { return 1; });  // VTK_VERTEX
  out.append(std::string_view("</Cells>\n"));
  end(out);
  return fmt::to_string(out);
}

void write_particles_vtu(const std::string& path, const Particles& particles, double time_s) {
  write_file_atomically(path, particles_vtu(particles, time_s));
}

std::string mesh_vtu(const BoxMesh& mesh, std::span<const Field> point_data, std::span<const Field> cell_data,
                     double time_s) {
  const auto nodes = static_cast<std::size_t>(mesh.num_nodes());
  const auto elements = static_cast<std::size_t>(mesh.num_elements());
  Buffer out;
  begin(out, nodes, elements, time_s);
  out.append(std::string_view("<PointData>\n"));
  for (const Field& f : point_data) field(out, f, nodes, "nodes");
  out.append(std::string_view("</PointData>\n<CellData>\n"));
  for (const Field& f : cell_data) field(out, f, elements, "elements");
  out.append(std::string_view("</CellData>\n<Points>\n"));
  data_array(out, "Float64", "Points", 3, nodes,
             [&](std::size_t i, int c) { return mesh.node(static_cast<Index>(i))[c]; });
  out.append(std::string_view("</Points>\n<Cells>\n"));
  data_array(out, "Int64", "connectivity", 4, elements, [&](std::size_t e, int c) {
    return mesh.element_nodes(static_cast<Index>(e))[static_cast<std::size_t>(c)];
  });
  data_array(out, "Int64", "offsets", 1, elements, [](std::size_t e, int) { return 4 * (e + 1); });
  data_array(out, "UInt8", "types", 1, elements, [](std::size_t, int) { return 10; });  // VTK_TETRA
  out.append(std::string_view("</Cells>\n"));
  end(out);
  return fmt::to_string(out);
}

void write_mesh_vtu(const std::string& path, const BoxMesh& mesh, std::span<const Field> point_data,
                    std::span<const Field> cell_data, double time_s) {
  write_file_atomically(path, mesh_vtu(mesh, point_data, cell_data, time_s));
}

}  // namespace fdem
