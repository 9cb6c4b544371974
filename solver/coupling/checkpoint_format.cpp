#include "coupling/checkpoint_format.hpp"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <istream>
#include <ostream>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/petsc_runtime.hpp"
#include "scene/scene_key_values.hpp"

namespace fdem::checkpoint {

namespace {

constexpr char kMagic[8] = {'F', 'D', 'E', 'M', 'C', 'K', 'P', 'T'};
constexpr char kTrailer[8] = {'F', 'D', 'E', 'M', 'E', 'N', 'D', '.'};
constexpr std::uint32_t kByteOrderMark = 0x01020304;
// The payload is read this many bytes at a time, so a corrupt length fails at
// the end of the data instead of allocating what it claims.
constexpr std::size_t kPayloadChunk = std::size_t{1} << 19;
// Longest key name and most entries a fingerprint may have (sanity bounds).
constexpr std::uint32_t kMaxName = 256, kMaxEntries = 4096;
// Version 1 files (one process) hold no rank layout.
constexpr std::uint32_t kFirstVersionWithRanks = 2;

// Magic, version, byte order and rank layout: the header's start.
RankLayout read_header_start(Reader& r) {
  char magic[8];
  r.raw(magic, sizeof magic, "the file magic");
  if (std::memcmp(magic, kMagic, sizeof magic) != 0)
    throw SolverError("checkpoint: not an fdem checkpoint (the file does not start with FDEMCKPT)");
  const std::uint32_t version = r.u32("the format version");
  const std::uint32_t mark = r.u32("the byte-order mark");
  if (mark != kByteOrderMark)
    throw SolverError("checkpoint: written on a machine of another byte order; restart it on the same kind of machine");
  if (version == 0 || version > kFormatVersion)
    throw SolverError(fmt::format("checkpoint: format version {}, this build reads versions 1 to {}", version,
                                  kFormatVersion));
  RankLayout layout;
  if (version >= kFirstVersionWithRanks) {
    layout.ranks = r.u32("the MPI rank count");
    layout.rank = r.u32("the MPI rank");
    if (layout.ranks == 0 || layout.rank >= layout.ranks)
      throw SolverError(fmt::format("checkpoint: rank {} of {} ranks (corrupt header)", layout.rank, layout.ranks));
  }
  return layout;
}

}  // namespace

RankLayout this_run_layout() {
  return {static_cast<std::uint32_t>(mpi_ranks()), static_cast<std::uint32_t>(mpi_rank())};
}

RankLayout read_rank_layout(std::istream& in) {
  Reader r(in);
  return read_header_start(r);
}

std::string rank_file_path(const std::string& path, std::uint32_t rank) {
  if (rank == 0) return path;
  const std::filesystem::path p(path);
  return (p.parent_path() / fmt::format("{}.rank{:04d}{}", p.stem().string(), rank, p.extension().string())).string();
}

void Hasher::bytes(const void* data, std::size_t size) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < size; ++i) {
    state_ ^= p[i];
    state_ *= 0x100000001b3ULL;  // FNV-1a 64-bit prime
  }
}

void Hasher::text(std::string_view s) {
  u64(s.size());
  bytes(s.data(), s.size());
}

// ---------------------------------------------------------------- fingerprint

std::uint64_t SceneFingerprint::hash() const {
  Hasher h;
  h.u64(entries.size());
  for (const auto& [name, value] : entries) {
    h.text(name);
    h.f64(value);
  }
  h.u64(particle_hash);
  return h.value();
}

SceneFingerprint scene_fingerprint(const Scene& scene, int subcycles, const Particles& initial) {
  Scene resolved = scene;
  resolved.time.subcycles = subcycles;
  SceneFingerprint f;
  f.entries = fingerprinted_values(resolved);  // every schema key that changes a step
  f.entries.emplace_back("particles.count", static_cast<double>(initial.size()));
  Hasher h;
  for (const auto* v : {&initial.x, &initial.y, &initial.z, &initial.vx, &initial.vy, &initial.vz,
                        &initial.diameter, &initial.mass}) {
    h.u64(v->size());
    h.bytes(v->data(), v->size() * sizeof(double));
  }
  f.particle_hash = h.value();
  return f;
}

// ---------------------------------------------------------------- file

void write_file(std::ostream& out, const SceneFingerprint& scene, std::string_view payload) {
  Writer w(out);
  w.raw(kMagic, sizeof kMagic);
  w.u32(kFormatVersion);
  w.u32(kByteOrderMark);
  const RankLayout layout = this_run_layout();
  w.u32(layout.ranks);
  w.u32(layout.rank);
  w.u64(scene.hash());
  w.u32(static_cast<std::uint32_t>(scene.entries.size()));
  for (const auto& [name, value] : scene.entries) {
    w.u32(static_cast<std::uint32_t>(name.size()));
    w.raw(name.data(), name.size());
    w.f64(value);
  }
  w.u64(scene.particle_hash);
  Hasher h;
  h.bytes(payload.data(), payload.size());
  w.u64(payload.size());
  w.u64(h.value());
  w.raw(payload.data(), payload.size());
  w.raw(kTrailer, sizeof kTrailer);
  out.flush();
  if (!out) throw SolverError("checkpoint: the output stream failed while flushing");
}

std::string read_file(std::istream& in, const SceneFingerprint& expected) {
  Reader r(in);
  const RankLayout layout = read_header_start(r), run = this_run_layout();
  // Each rank holds its own part of the state: only the same count, each
  // rank its own file, resumes it (fdem run refuses another count earlier,
  // with the file's name; this guards every other reader).
  if (layout.ranks != run.ranks || layout.rank != run.rank)
    throw SolverError(fmt::format("checkpoint: written by rank {} of {} MPI ranks, read by rank {} of {}; resume it "
                                  "on {} ranks (mpirun -n {})",
                                  layout.rank, layout.ranks, run.rank, run.ranks, layout.ranks, layout.ranks));
  const std::uint64_t scene_hash = r.u64("the scene hash");
  const std::uint32_t count = r.u32("the scene entry count");
  if (count > kMaxEntries) throw SolverError(fmt::format("checkpoint: {} scene entries (corrupt header)", count));
  SceneFingerprint found;
  for (std::uint32_t k = 0; k < count; ++k) {
    const std::uint32_t length = r.u32("a scene key");
    if (length > kMaxName) throw SolverError("checkpoint: corrupt scene key in the header");
    std::string name(length, '\0');
    r.raw(name.data(), length, "a scene key");
    found.entries.emplace_back(std::move(name), r.f64("a scene value"));
  }
  found.particle_hash = r.u64("the particle hash");
  if (found.hash() != scene_hash) throw SolverError("checkpoint: corrupt header (scene hash does not match its entries)");
  if (scene_hash != expected.hash()) {
    // Name what differs, so the user knows which scene the checkpoint belongs to.
    std::string diffs;
    int shown = 0;
    auto note = [&](const std::string& key, const std::string& in_file, const std::string& in_run) {
      if (shown++ < 8) diffs += fmt::format("\n  {}: checkpoint {}, this scene {}", key, in_file, in_run);
    };
    for (const auto& [key, value] : expected.entries) {
      const auto it = std::find_if(found.entries.begin(), found.entries.end(),
                                   [&key](const auto& entry) { return entry.first == key; });
      if (it == found.entries.end()) {
        note(key, "(absent)", fmt::format("{:.17g}", value));
      } else if (std::memcmp(&it->second, &value, sizeof value) != 0) {
        note(key, fmt::format("{:.17g}", it->second), fmt::format("{:.17g}", value));
      }
    }
    if (found.particle_hash != expected.particle_hash)
      diffs += "\n  the initial particles (positions, velocities, diameters or masses) differ";
    if (diffs.empty()) diffs = "\n  (the scene keys of this build differ from the writer's)";
    throw SolverError(fmt::format(
        "checkpoint was written for another scene (scene hash {:016x}, this scene {:016x}); restart it with the "
        "scene it was written by. Differences:{}",
        scene_hash, expected.hash(), diffs));
  }
  const std::uint64_t length = r.u64("the payload length");
  const std::uint64_t checksum = r.u64("the payload checksum");
  std::string payload;
  while (payload.size() < length) {  // bounded chunks: a corrupt length fails at the end of the data
    const std::size_t start = payload.size();
    const auto take = static_cast<std::size_t>(std::min<std::uint64_t>(kPayloadChunk, length - start));
    payload.resize(start + take);
    r.raw(payload.data() + start, take, "the state (payload)");
  }
  Hasher h;
  h.bytes(payload.data(), payload.size());
  if (h.value() != checksum) throw SolverError("checkpoint: the state does not match its checksum (corrupt file)");
  char trailer[8];
  r.raw(trailer, sizeof trailer, "the end marker");
  if (std::memcmp(trailer, kTrailer, sizeof trailer) != 0)
    throw SolverError("checkpoint: missing end marker (file cut short or corrupt)");
  // Anything after the trailer is not ours: a file appended to or overwritten in part.
  std::size_t extra = 0;
  while (in.get() != std::istream::traits_type::eof()) ++extra;
  if (extra > 0)
    throw SolverError(fmt::format("checkpoint: {} bytes after the end marker (corrupt file, or another file appended)",
                                  extra));
  return payload;
}

}  // namespace fdem::checkpoint
