#pragma once
// VTK XML unstructured grids (.vtu) that ParaView opens: particles as points,
// the fluid mesh as linear tetrahedra (VTK cell type 10). Writers take plain
// data (Particles, BoxMesh, spans), not solver classes, and write atomically
// (io/atomic_file.hpp).
//
// Binary (the default): every array in one appended section, raw
// little-endian values in zlib-compressed blocks of 32 KiB (VTK's
// vtkZLibDataCompressor layout, header_type UInt64): 64-88 bytes a grain
// (11 doubles hardly compress; the index arrays shrink ~100x) against
// 190-250 in ASCII. ASCII: shortest round-trip decimals inline, for reading
// by eye. Both read back bit for bit.
#include <array>
#include <span>
#include <string>
#include <vector>

#include "core/particles.hpp"
#include "mesh/box_mesh.hpp"

namespace fdem {

enum class VtuEncoding { binary, ascii };

/// A named field over the points or the cells of a grid.
struct Field {
  std::string name;
  int components = 1;
  std::span<const double> interleaved;                 // components values per entry: v0x v0y v0z v1x ...
  std::array<std::span<const double>, 3> separate{};   // or one span per component (structure of arrays)
  bool is_separate = false;

  static Field scalar(std::string name, std::span<const double> values);
  static Field vector_interleaved(std::string name, std::span<const double> xyz);
  static Field vector_separate(std::string name, std::span<const double> x, std::span<const double> y,
                               std::span<const double> z);
  std::size_t entries() const;  // number of points or cells the field covers
  double at(std::size_t entry, int component) const {
    return is_separate ? separate[static_cast<std::size_t>(component)][entry]
                       : interleaved[entry * static_cast<std::size_t>(components) + static_cast<std::size_t>(component)];
  }
};

/// The optional point arrays of a particles .vtu. The pieces of one snapshot
/// written by several MPI ranks must hold the same arrays (their .pvtu
/// declares them once), an empty piece too, so the ranks agree on these.
struct ParticleArrays {
  bool angular_velocity = false;  // rotation on: the wx, wy, wz arrays filled
  bool id = false;                // Particles::id filled (the DEM engine numbers the grains)
};
/// The optional arrays `particles` holds (none for an empty set).
ParticleArrays particle_arrays_of(const Particles& particles);

/// One point array of a particles .vtu: its name, VTK type, components.
struct VtuArraySpec {
  const char* name;
  const char* type;
  int components;
};
/// The point arrays of a particles .vtu in file order, with `arrays`.
std::vector<VtuArraySpec> particle_point_arrays(ParticleArrays arrays);

/// Particles as VTK vertices with point data diameter [m], mass [kg],
/// velocity [m/s], force [N] (zeros when the force arrays are empty) and,
/// when rotation is on, angular_velocity [rad/s], and the grains' id (their
/// index at the start, kept when others leave the domain). `time_s` goes to
/// TimeValue. `arrays`: the optional arrays to write (a piece of a
/// snapshot: the snapshot's; zeros where this set lacks them).
std::string particles_vtu(const Particles& particles, double time_s, VtuEncoding encoding = VtuEncoding::binary);
std::string particles_vtu(const Particles& particles, double time_s, VtuEncoding encoding, ParticleArrays arrays);
void write_particles_vtu(const std::string& path, const Particles& particles, double time_s,
                         VtuEncoding encoding = VtuEncoding::binary);
void write_particles_vtu(const std::string& path, const Particles& particles, double time_s, VtuEncoding encoding,
                         ParticleArrays arrays);

/// The tetrahedral mesh with nodal fields (velocity, pressure, source_term,
/// ...) and element fields (porosity, ...). Field sizes are checked against
/// num_nodes / num_elements (SolverError naming the field on mismatch).
std::string mesh_vtu(const BoxMesh& mesh, std::span<const Field> point_data, std::span<const Field> cell_data,
                     double time_s, VtuEncoding encoding = VtuEncoding::binary);
void write_mesh_vtu(const std::string& path, const BoxMesh& mesh, std::span<const Field> point_data,
                    std::span<const Field> cell_data, double time_s, VtuEncoding encoding = VtuEncoding::binary);

}  // namespace fdem
