#pragma once
// Binary records of a checkpoint's state (crash safety): the
// primitives the engines write their state with (DemEngine::save_state,
// FluidSolver::save_state, Simulation's "SIM " and "COUP" sections), in core
// so that dem/ and fluid/ need nothing of coupling/ to save and load.
// The file around these records (header, scene fingerprint, checksum,
// trailer) is coupling/checkpoint_format.hpp.
//
// Every number is stored in the writer's native byte order (the file header's
// byte-order mark lets a reader on another order refuse); doubles are stored
// as their bits, never printed, so a restart is exact. A payload is a
// sequence of sections, each a 4-character tag and a u32 section version, so
// a reader refuses a section it does not know or a newer version of it.
//
// The reader turns every short read into a SolverError naming what it was
// reading, and reads arrays in bounded chunks, so a truncated or corrupt file
// is refused before it can allocate or return garbage.
#include <cstddef>
#include <cstdint>
#include <iosfwd>
#include <span>
#include <string_view>
#include <vector>

#include "core/types.hpp"

namespace fdem::checkpoint {

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

}  // namespace fdem::checkpoint
