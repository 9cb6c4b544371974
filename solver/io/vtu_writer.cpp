#include "io/vtu_writer.hpp"

#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <string_view>

#include <fmt/format.h>

#include "core/error.hpp"
#include "io/atomic_file.hpp"

namespace fdem {

namespace {

// The binary layout below is VTK's for byte_order="LittleEndian": values are
// copied from memory as they are.
static_assert(std::endian::native == std::endian::little, "the VTU writer assumes a little-endian host");

// VTK's block size for compressed arrays (vtkXMLWriter's default, 32 KiB of
// uncompressed bytes per block).
constexpr std::size_t kBlockBytes = 32768;

// Appends one array's bytes to the appended-data section in VTK's compressed
// layout (header_type UInt64, vtkZLibDataCompressor): the header
// [blocks, block size, size of the last partial block (0: none), compressed
// size of each block], then the compressed blocks one after another.
void append_compressed(std::string& appended, std::string_view bytes) {
  const std::size_t blocks = (bytes.size() + kBlockBytes - 1) / kBlockBytes;
  std::vector<std::uint64_t> header{blocks, kBlockBytes, bytes.size() % kBlockBytes};
  std::string compressed;
  std::vector<Bytef> block(compressBound(kBlockBytes));
  for (std::size_t b = 0; b < blocks; ++b) {
    const std::size_t begin = b * kBlockBytes;
    const std::size_t size = std::min(kBlockBytes, bytes.size() - begin);
    uLongf out_size = static_cast<uLongf>(block.size());
    // Level 1 (fastest): on a 1e5-grain snapshot within 1 % of the default
    // level's size (random mantissa bits do not compress at any level) in
    // about 2/3 of its time.
    const int status = compress2(block.data(), &out_size, reinterpret_cast<const Bytef*>(bytes.data() + begin),
                                 static_cast<uLong>(size), Z_BEST_SPEED);
    if (status != Z_OK) throw SolverError(fmt::format("zlib compress2 failed with status {}", status));
    header.push_back(out_size);
    compressed.append(reinterpret_cast<const char*>(block.data()), out_size);
  }
  appended.append(reinterpret_cast<const char*>(header.data()), header.size() * sizeof(std::uint64_t));
  appended += compressed;
}

// One VTU document being built: the XML text and, for the binary encoding,
// the appended-data section that follows it.
class VtuDocument {
 public:
  VtuDocument(VtuEncoding encoding, std::size_t points, std::size_t cells, double time_s) : encoding_(encoding) {
    fmt::format_to(std::back_inserter(xml_),
                   "<?xml version=\"1.0\"?>\n"
                   "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
                   "header_type=\"UInt64\"{}>\n"
                   "<UnstructuredGrid>\n"
                   "<FieldData>\n"
                   "<DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"ascii\">{}</DataArray>\n"
                   "</FieldData>\n"
                   "<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n",
                   encoding_ == VtuEncoding::binary ? " compressor=\"vtkZLibDataCompressor\"" : "", time_s, points,
                   cells);
  }

  void text(std::string_view s) { xml_.append(s); }

  // One DataArray of `entries` tuples of `components` values, value(i, c)
  // converted to Stored (double for Float64, std::int64_t for Int64,
  // std::uint8_t for UInt8).
  template <class Stored, class Value>
  void data_array(const char* type, const std::string& name, int components, std::size_t entries, Value&& value) {
    if (encoding_ == VtuEncoding::ascii) {
      fmt::format_to(std::back_inserter(xml_),
                     "<DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\" format=\"ascii\">\n", type, name,
                     components);
      for (std::size_t i = 0; i < entries; ++i) {
        for (int c = 0; c < components; ++c) {
          if (c > 0) xml_.push_back(' ');
          // Shortest round-trip decimals: the values read back bit for bit.
          fmt::format_to(std::back_inserter(xml_), "{}", static_cast<Stored>(value(i, c)));
        }
        xml_.push_back('\n');
      }
      xml_.append(std::string_view("</DataArray>\n"));
      return;
    }
    fmt::format_to(std::back_inserter(xml_),
                   "<DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\" format=\"appended\" offset=\"{}\"/>\n",
                   type, name, components, appended_.size());
    values_.resize(entries * static_cast<std::size_t>(components) * sizeof(Stored));
    char* out = values_.data();
    for (std::size_t i = 0; i < entries; ++i) {
      for (int c = 0; c < components; ++c) {
        const auto v = static_cast<Stored>(value(i, c));
        std::memcpy(out, &v, sizeof v);
        out += sizeof v;
      }
    }
    append_compressed(appended_, values_);
  }

  std::string finish() {
    xml_.append(std::string_view("</Piece>\n</UnstructuredGrid>\n"));
    if (encoding_ == VtuEncoding::binary) {
      // Raw bytes after the underscore; offsets count from the byte after it.
      xml_.append(std::string_view("<AppendedData encoding=\"raw\">\n_"));
      xml_.append(appended_);
      xml_.append(std::string_view("\n</AppendedData>\n"));
    }
    xml_.append(std::string_view("</VTKFile>\n"));
    return fmt::to_string(xml_);
  }

 private:
  VtuEncoding encoding_;
  fmt::memory_buffer xml_;
  std::string appended_;
  std::string values_;  // one array's uncompressed bytes, reused
};

void field(VtuDocument& out, const Field& f, std::size_t entries, const char* where) {
  if (f.entries() != entries) {
    throw SolverError(fmt::format("output field '{}' has {} entries, the mesh {} {}", f.name, f.entries(), entries, where));
  }
  out.data_array<double>("Float64", f.name, f.components, entries, [&](std::size_t i, int c) { return f.at(i, c); });
}

std::span<const double> or_empty(std::span<const double> v, std::size_t n) {
  return v.size() == n ? v : std::span<const double>();
}

// A field whose components lie interleaved in one span.
Field interleaved_field(std::string name, int components, std::span<const double> values) {
  Field f;
  f.name = std::move(name);
  f.components = components;
  f.interleaved = values;
  return f;
}

}  // namespace

Field Field::scalar(std::string name, std::span<const double> values) {
  return interleaved_field(std::move(name), 1, values);
}
Field Field::vector_interleaved(std::string name, std::span<const double> xyz) {
  return interleaved_field(std::move(name), 3, xyz);
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

ParticleArrays particle_arrays_of(const Particles& p) {
  const std::size_t n = p.size();
  ParticleArrays a;
  a.angular_velocity = n > 0 && p.wx.size() == n && p.wy.size() == n && p.wz.size() == n;
  a.id = n > 0 && p.id.size() == n;
  return a;
}

std::vector<VtuArraySpec> particle_point_arrays(ParticleArrays arrays) {
  std::vector<VtuArraySpec> specs{
      {"diameter", "Float64", 1}, {"mass", "Float64", 1}, {"velocity", "Float64", 3}, {"force", "Float64", 3}};
  if (arrays.angular_velocity) specs.push_back({"angular_velocity", "Float64", 3});
  if (arrays.id) specs.push_back({"id", "Int64", 1});
  return specs;
}

std::string particles_vtu(const Particles& p, double time_s, VtuEncoding encoding) {
  return particles_vtu(p, time_s, encoding, particle_arrays_of(p));
}

std::string particles_vtu(const Particles& p, double time_s, VtuEncoding encoding, ParticleArrays arrays) {
  const std::size_t n = p.size();
  VtuDocument out(encoding, n, n, time_s);
  out.text("<PointData Scalars=\"diameter\" Vectors=\"velocity\">\n");
  // Written in particle_point_arrays' order (a .pvtu declares them so).
  out.data_array<double>("Float64", "diameter", 1, n, [&](std::size_t i, int) { return p.diameter[i]; });
  out.data_array<double>("Float64", "mass", 1, n, [&](std::size_t i, int) { return p.mass[i]; });
  out.data_array<double>("Float64", "velocity", 3, n,
                         [&](std::size_t i, int c) { return c == 0 ? p.vx[i] : c == 1 ? p.vy[i] : p.vz[i]; });
  const auto fx = or_empty(p.fx, n), fy = or_empty(p.fy, n), fz = or_empty(p.fz, n);
  const bool has_force = !fx.empty() && !fy.empty() && !fz.empty();
  out.data_array<double>("Float64", "force", 3, n, [&](std::size_t i, int c) {
    return has_force ? (c == 0 ? fx[i] : c == 1 ? fy[i] : fz[i]) : 0.0;
  });
  if (arrays.angular_velocity) {
    const auto wx = or_empty(p.wx, n), wy = or_empty(p.wy, n), wz = or_empty(p.wz, n);
    const bool has_rotation = !wx.empty() && !wy.empty() && !wz.empty();
    out.data_array<double>("Float64", "angular_velocity", 3, n, [&](std::size_t i, int c) {
      return has_rotation ? (c == 0 ? wx[i] : c == 1 ? wy[i] : wz[i]) : 0.0;
    });
  }
  if (arrays.id) {
    const bool has_id = p.id.size() == n;
    out.data_array<std::int64_t>("Int64", "id", 1, n,
                                 [&](std::size_t i, int) { return has_id ? std::int64_t{p.id[i]} : std::int64_t{-1}; });
  }
  out.text("</PointData>\n<Points>\n");
  out.data_array<double>("Float64", "Points", 3, n,
                         [&](std::size_t i, int c) { return c == 0 ? p.x[i] : c == 1 ? p.y[i] : p.z[i]; });
  out.text("</Points>\n<Cells>\n");
  out.data_array<std::int64_t>("Int64", "connectivity", 1, n, [](std::size_t i, int) { return i; });
  out.data_array<std::int64_t>("Int64", "offsets", 1, n, [](std::size_t i, int) { return i + 1; });
  out.data_array<std::uint8_t>("UInt8", "types", 1, n, [](std::size_t, int) { return 1; });  // VTK_VERTEX
  out.text("</Cells>\n");
  return out.finish();
}

void write_particles_vtu(const std::string& path, const Particles& particles, double time_s, VtuEncoding encoding) {
  write_file_atomically(path, particles_vtu(particles, time_s, encoding));
}

void write_particles_vtu(const std::string& path, const Particles& particles, double time_s, VtuEncoding encoding,
                         ParticleArrays arrays) {
  write_file_atomically(path, particles_vtu(particles, time_s, encoding, arrays));
}

std::string mesh_vtu(const BoxMesh& mesh, std::span<const Field> point_data, std::span<const Field> cell_data,
                     double time_s, VtuEncoding encoding) {
  const auto nodes = static_cast<std::size_t>(mesh.num_nodes());
  const auto elements = static_cast<std::size_t>(mesh.num_elements());
  VtuDocument out(encoding, nodes, elements, time_s);
  out.text("<PointData>\n");
  for (const Field& f : point_data) field(out, f, nodes, "nodes");
  out.text("</PointData>\n<CellData>\n");
  for (const Field& f : cell_data) field(out, f, elements, "elements");
  out.text("</CellData>\n<Points>\n");
  out.data_array<double>("Float64", "Points", 3, nodes,
                         [&](std::size_t i, int c) { return mesh.node(static_cast<Index>(i))[c]; });
  out.text("</Points>\n<Cells>\n");
  out.data_array<std::int64_t>("Int64", "connectivity", 4, elements, [&](std::size_t e, int c) {
    return mesh.element_nodes(static_cast<Index>(e))[static_cast<std::size_t>(c)];
  });
  out.data_array<std::int64_t>("Int64", "offsets", 1, elements, [](std::size_t e, int) { return 4 * (e + 1); });
  out.data_array<std::uint8_t>("UInt8", "types", 1, elements, [](std::size_t, int) { return 10; });  // VTK_TETRA
  out.text("</Cells>\n");
  return out.finish();
}

void write_mesh_vtu(const std::string& path, const BoxMesh& mesh, std::span<const Field> point_data,
                    std::span<const Field> cell_data, double time_s, VtuEncoding encoding) {
  write_file_atomically(path, mesh_vtu(mesh, point_data, cell_data, time_s, encoding));
}

}  // namespace fdem
