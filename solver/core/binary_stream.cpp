#include "core/binary_stream.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <istream>
#include <ostream>

#include <fmt/format.h>

#include "core/error.hpp"

namespace fdem::checkpoint {

namespace {

// Arrays are read this many values at a time, so a corrupt length fails at
// the end of the data instead of allocating what it claims.
constexpr std::size_t kChunk = std::size_t{1} << 16;

template <class T>
std::vector<T> read_array(Reader& r, const char* what, std::size_t max_count) {
  const std::uint64_t count = r.u64(what);
  if (count > max_count)
    throw SolverError(fmt::format("checkpoint: {} has {} values, at most {} expected (corrupt or another scene)",
                                  what, count, max_count));
  std::vector<T> v;
  const auto n = static_cast<std::size_t>(count);
  while (v.size() < n) {
    const std::size_t start = v.size(), take = std::min(kChunk, n - start);
    v.resize(start + take);
    r.raw(v.data() + start, take * sizeof(T), what);
  }
  return v;
}

// A section tag as stored: the first four characters, padded with spaces.
std::array<char, 4> padded_tag(std::string_view tag4) {
  std::array<char, 4> tag = {' ', ' ', ' ', ' '};
  std::copy_n(tag4.begin(), std::min<std::size_t>(4, tag4.size()), tag.begin());
  return tag;
}

// One fixed-size value in native byte order.
template <class T>
T read_value(Reader& r, const char* what) {
  T v{};
  r.raw(&v, sizeof v, what);
  return v;
}

}  // namespace

// ---------------------------------------------------------------- Writer

void Writer::raw(const void* data, std::size_t size) {
  out_.write(static_cast<const char*>(data), static_cast<std::streamsize>(size));
  if (!out_) throw SolverError("checkpoint: the output stream refused the data (disk full or closed?)");
}

void Writer::section(std::string_view tag4, std::uint32_t version) {
  raw(padded_tag(tag4).data(), 4);
  u32(version);
}

void Writer::doubles(std::span<const double> v) {
  u64(v.size());
  raw(v.data(), v.size_bytes());
}

void Writer::indices(std::span<const Index> v) {
  u64(v.size());
  raw(v.data(), v.size_bytes());
}

// ---------------------------------------------------------------- Reader

void Reader::raw(void* data, std::size_t size, const char* what) {
  if (size == 0) return;
  in_.read(static_cast<char*>(data), static_cast<std::streamsize>(size));
  if (!in_ || static_cast<std::size_t>(in_.gcount()) != size)
    throw SolverError(fmt::format("checkpoint truncated or unreadable while reading {} (file cut short?)", what));
}

std::uint32_t Reader::section(std::string_view tag4, std::uint32_t max_version) {
  char tag[4];
  raw(tag, 4, "a section tag");
  const std::array<char, 4> expected = padded_tag(tag4);
  const std::string_view expected_text(expected.data(), 4);
  if (std::memcmp(tag, expected.data(), 4) != 0)
    throw SolverError(fmt::format("checkpoint: expected section '{}', found '{}' (corrupt or another format)",
                                  expected_text, std::string_view(tag, 4)));
  const std::uint32_t version = u32("a section version");
  if (version == 0 || version > max_version)
    throw SolverError(fmt::format("checkpoint: section '{}' has version {}, this build reads up to {}",
                                  expected_text, version, max_version));
  return version;
}

std::uint8_t Reader::u8(const char* what) { return read_value<std::uint8_t>(*this, what); }
std::uint32_t Reader::u32(const char* what) { return read_value<std::uint32_t>(*this, what); }
std::uint64_t Reader::u64(const char* what) { return read_value<std::uint64_t>(*this, what); }
std::int64_t Reader::i64(const char* what) { return read_value<std::int64_t>(*this, what); }
double Reader::f64(const char* what) { return read_value<double>(*this, what); }

bool Reader::boolean(const char* what) {
  const std::uint8_t v = u8(what);
  if (v > 1) throw SolverError(fmt::format("checkpoint: {} is {}, not a flag (corrupt)", what, v));
  return v == 1;
}
Vec3 Reader::vec3(const char* what) {
  const double x = f64(what), y = f64(what), z = f64(what);
  return {x, y, z};
}

std::vector<double> Reader::doubles(const char* what, std::size_t max_count) {
  return read_array<double>(*this, what, max_count);
}
std::vector<Index> Reader::indices(const char* what, std::size_t max_count) {
  return read_array<Index>(*this, what, max_count);
}
std::vector<double> Reader::doubles_exactly(const char* what, std::size_t count) {
  std::vector<double> v = read_array<double>(*this, what, count);
  if (v.size() != count)
    throw SolverError(fmt::format("checkpoint: {} has {} values, this run has {} (another scene?)", what, v.size(),
                                  count));
  return v;
}

}  // namespace fdem::checkpoint
