#pragma once
// The checkpoint file of a run (crash safety): exact binary state for
// a restart that reproduces the uninterrupted run bit for bit (same scene,
// same thread count, same MPI rank count).
//
// File layout (version 2; every number in the writer's native byte order,
// which the byte-order mark lets a reader on another order refuse):
//   "FDEMCKPT"                      8 bytes, magic
//   u32 format version              kFormatVersion
//   u32 byte-order mark             0x01020304
//   u32 MPI ranks, u32 this rank    the run that wrote it: on N ranks every
//                                   rank writes its own file (rank_file_path),
//                                   and a run on another count is refused
//                                   (version 1, without them: 1 rank, rank 0)
//   u64 scene hash                  FNV-1a of the fingerprint below
//   u32 entry count, then per entry: u32 name length, name, f64 value
//                                   the scene's key numbers, so a refusal can
//                                   name what differs (e.g. "particles.count")
//   u64 initial-particle hash       FNV-1a over the generated particles
//   u64 payload length [bytes]
//   u64 payload checksum            FNV-1a of the payload
//   payload                         sections written by the engines (below)
//   "FDEMEND."                      8 bytes, trailer: a file cut short never
//                                   passes for complete
// Payload sections, each a 4-character tag and a u32 section version:
//   "SIM " step index, step size, subcycles, fluid present; version 2
//          adds the grains' slab cut on MPI ranks (inner boundaries)
//   "DEM " DemEngine::save_state (particles, time, slip history, ...)
//   "FLUI" FluidSolver::save_state (only with fluid)
//   "COUP" coupling state: diagnostics counters, porosity, mean drag, source term
// Doubles are stored as their bits, never printed, so a restart is exact.
// The sections' records (Writer, Reader: byte order, section tags and
// versions, bounded reads, the refusal messages) are core/binary_stream.hpp,
// so the engines write their state without depending on coupling/; this file
// adds what needs the scene: its fingerprint, the particle hash and the file
// around the payload.
//
// Writing the file atomically is the caller's job: write to a memory buffer
// (std::ostringstream) and hand it to io/atomic_file.hpp's write_file_atomically.
#include <cstddef>
#include <cstdint>
#include <iosfwd>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/binary_stream.hpp"
#include "core/particles.hpp"
#include "scene/scene.hpp"

namespace fdem::checkpoint {

inline constexpr std::uint32_t kFormatVersion = 2;

/// 64-bit FNV-1a over bytes (not cryptographic: it detects accidental
/// corruption and a checkpoint of another scene, not tampering).
class Hasher {
 public:
  void bytes(const void* data, std::size_t size);
  void u64(std::uint64_t v) { bytes(&v, sizeof v); }
  void f64(double v) { bytes(&v, sizeof v); }
  void text(std::string_view s);
  std::uint64_t value() const { return state_; }

 private:
  std::uint64_t state_ = 0xcbf29ce484222325ULL;
};

/// The scene's key numbers: the value of every schema key that changes the
/// result of a step (scene/scene_key_values.hpp, derived from the schema),
/// the particle count and a hash of the initial particles. Leaves out what a
/// restart may change (scene/scene_schema.hpp, fingerprint_exemption: end
/// time, output settings, title).
struct SceneFingerprint {
  std::vector<std::pair<std::string, double>> entries;
  std::uint64_t particle_hash = 0;  // FNV-1a over the initial x, y, z, v, d, m
  std::uint64_t hash() const;
};

/// `scene` with its DEM step resolved, `subcycles` DEM steps per step,
/// `initial` the particles as generated (before the first step).
SceneFingerprint scene_fingerprint(const Scene& scene, int subcycles, const Particles& initial);

/// The MPI ranks a checkpoint was written on and the rank that wrote it.
struct RankLayout {
  std::uint32_t ranks = 1;
  std::uint32_t rank = 0;
};

/// This process's layout (core/petsc_runtime.hpp: 1 rank without MPI).
RankLayout this_run_layout();

/// Header, payload, trailer (see the layout above); the header records
/// this_run_layout().
void write_file(std::ostream& out, const SceneFingerprint& scene, std::string_view payload);

/// Reads only the start of the header (magic, version, byte order, layout),
/// so a run can refuse a checkpoint of another rank count before any
/// set-up. SolverError on a file that is no checkpoint.
RankLayout read_rank_layout(std::istream& in);

/// The file rank `rank` of a run on several ranks reads and writes for the
/// checkpoint `path` (rank 0's, the one --restart names): rank 0 `path`
/// itself, rank k `<stem>.rank<k, 4 digits><extension>` beside it
/// (out/checkpoint.bin -> out/checkpoint.rank0001.bin).
std::string rank_file_path(const std::string& path, std::uint32_t rank);

/// Reads and verifies a whole checkpoint: magic, version, byte order, rank
/// layout (this run's), scene (SolverError naming the keys that differ),
/// length, checksum, trailer. Returns the payload only when all hold.
std::string read_file(std::istream& in, const SceneFingerprint& expected);

}  // namespace fdem::checkpoint
