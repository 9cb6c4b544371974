#pragma once
// The checkpoint file of a run (issue 9, crash safety): exact binary state for
// a restart that reproduces the uninterrupted run bit for bit (same scene,
// same thread count).
//
// File layout (version 1; every number in the writer's native byte order,
// which the byte-order mark lets a reader on another order refuse):
//   "FDEMCKPT"                      8 bytes, magic
//   u32 format version              kFormatVersion
//   u32 byte-order mark             0x01020304
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
//   "SIM " step index, step size, subcycles, fluid present
//   "DEM " DemEngine::save_state (particles, time, slip history, ...)
//   "FLUI" FluidSolver::save_state (only with fluid)
//   "COUP" coupling state: diagnostics counters, porosity, mean drag, source term
// Doubles are stored as their bits, never printed, so a restart is exact.
//
// The reader (Reader) turns every short read into a SolverError naming what
// it was reading, and reads arrays in bounded chunks, so a truncated or
// corrupt file is refused before it can allocate or return garbage.
//
// Writing the file atomically is the caller's job: write to a memory buffer
// (std::ostringstream) and hand it to io/atomic_file.hpp's write_file_atomically.
#include <array>
#include <cstdint>
#include <iosfwd>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/types.hpp"
#include "dem/particles.hpp"
#include "scene/scene.hpp"

namespace fdem::checkpoint {

inline constexpr std::uint32_t kFormatVersion = 1;

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

/// Binary record writer over a stream (native byte order, exact doubles).
class Writer {
 public:
  explicit Writer(std::ostream& out) : out_(out) {}
  void section(std::string_view tag4, std::uint32_t version);
  void u8(std::uint8_t v) { raw(&v, sizeof v); }
  void u32(std::uint32_t v) { raw(&v, sizeof v); }
  void u64(std::uint64_t v) { raw(&v, sizeof v); }
  void i64(std::int64_t v) { raw(&v, sizeof v); }
  void f64(double v) { raw(&v, sizeof v); }
  void boolean(bool v) { u8(v ? 1 : 0); }
  void vec3(const Vec3& v) {
    f64(v.x());
    f64(v.y());
    f64(v.z());
  }
  /// Length (u64) then the values.
  void doubles(std::span<const double> v);
  void indices(std::span<const Index> v);
  void raw(const void* data, std::size_t size);

 private:
  std::ostream& out_;
};

/// Binary record reader: every failure is a SolverError that names `what`.
class Reader {
 public:
  explicit Reader(std::istream& in) : in_(in) {}
  /// Reads a section tag and version; refuses another tag or a newer version.
  std::uint32_t section(std::string_view tag4, std::uint32_t max_version);
  std::uint8_t u8(const char* what);
  std::uint32_t u32(const char* what);
  std::uint64_t u64(const char* what);
  std::int64_t i64(const char* what);
  double f64(const char* what);
  bool boolean(const char* what);
  Vec3 vec3(const char* what);
  /// Length-prefixed arrays, refused when longer than max_count. Read in
  /// bounded chunks: a corrupt length cannot allocate more than the file holds.
  std::vector<double> doubles(const char* what, std::size_t max_count);
  std::vector<Index> indices(const char* what, std::size_t max_count);
  /// A length-prefixed array that must hold exactly `count` values.
  std::vector<double> doubles_exactly(const char* what, std::size_t count);
  void raw(void* data, std::size_t size, const char* what);

 private:
  std::istream& in_;
};

/// The scene's key numbers: everything that changes the result of a step
/// (domain, mesh, effects, fluid, contact, steps, coupling, gravity, the
/// initial particles). Leaves out what a restart may change: end time,
/// output settings, title, file name.
struct SceneFingerprint {
  std::vector<std::pair<std::string, double>> entries;
  std::uint64_t particle_hash = 0;  // FNV-1a over the initial x, y, z, v, d, m
  std::uint64_t hash() const;
};

/// `scene` with its DEM step resolved, `subcycles` DEM steps per step,
/// `initial` the particles as generated (before the first step).
SceneFingerprint scene_fingerprint(const Scene& scene, int subcycles, const Particles& initial);

/// Header, payload, trailer (see the layout above).
void write_file(std::ostream& out, const SceneFingerprint& scene, std::string_view payload);

/// Reads and verifies a whole checkpoint: magic, version, byte order, scene
/// (SolverError naming the keys that differ), length, checksum, trailer.
/// Returns the payload only when all hold.
std::string read_file(std::istream& in, const SceneFingerprint& expected);

}  // namespace fdem::checkpoint
