#include "io/pvtu_writer.hpp"

#include <iterator>

#include <fmt/format.h>

#include "io/atomic_file.hpp"

namespace fdem {

std::string piece_file_name(const std::string& base, int rank) { return fmt::format("{}_rank{:04d}.vtu", base, rank); }

std::string particles_pvtu(ParticleArrays arrays, std::span<const std::string> piece_files) {
  fmt::memory_buffer out;
  // The pieces' own header (vtu_writer.cpp): little-endian, UInt64 headers.
  fmt::format_to(std::back_inserter(out),
                 "<?xml version=\"1.0\"?>\n"
                 "<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
                 "header_type=\"UInt64\">\n"
                 "<PUnstructuredGrid GhostLevel=\"0\">\n"
                 "<PPointData Scalars=\"diameter\" Vectors=\"velocity\">\n");
  for (const VtuArraySpec& a : particle_point_arrays(arrays))
    fmt::format_to(std::back_inserter(out), "<PDataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\"/>\n", a.type,
                   a.name, a.components);
  fmt::format_to(std::back_inserter(out),
                 "</PPointData>\n<PPoints>\n<PDataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\"/>\n"
                 "</PPoints>\n");
  for (const std::string& piece : piece_files) fmt::format_to(std::back_inserter(out), "<Piece Source=\"{}\"/>\n", piece);
  fmt::format_to(std::back_inserter(out), "</PUnstructuredGrid>\n</VTKFile>\n");
  return fmt::to_string(out);
}

void write_particles_pvtu(const std::string& path, ParticleArrays arrays, std::span<const std::string> piece_files) {
  write_file_atomically(path, particles_pvtu(arrays, piece_files));
}

}  // namespace fdem
