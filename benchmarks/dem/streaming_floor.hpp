#pragma once
// The streaming floor of a per-grain pass: the time this host takes to load
// and store the same per-grain arrays as the pass, with no other work (one
// add a stream). A pass over that many bytes cannot beat it, so a pass's
// time over its floor, measured in the same process, says how far it is from
// the machine's limit independently of how fast this host runs today (hosts
// of this kind differ 1.2-2.3x). The arrays are GrainArrays, staggered as the
// engine's are (core/grain_array.hpp), so the floor sees the same cache sets.
//
// The shapes of the two passes that dominate the plume's DEM step
// (plume_dem_profile, plume_workload.py):
//  * the fused kick-drift (dem_engine.cpp, kick_drift): reads the kick and
//    body factors and the list's reference positions (5 arrays), reads and
//    writes positions, velocities and forces (9 arrays);
//  * the drag subcycle (drag_laws/drag_kernel.hpp): reads the fluid velocity
//    and the law's four coefficients of every grain (7 arrays' worth, in
//    DragBlocks) and the velocities (3), reads and writes the drag sums and
//    the forces (6).
#include <algorithm>
#include <array>
#include <chrono>
#include <cstddef>
#include <vector>

#include "core/grain_array.hpp"

namespace fdem::bench {

/// read_only arrays loaded, read_write arrays loaded and stored, a grain at a time.
struct StreamShape {
  int read_only;
  int read_write;
};
inline constexpr StreamShape kKickDriftStreams{5, 9};
inline constexpr StreamShape kDragStreams{10, 6};

namespace detail {

template <int ReadOnly, int ReadWrite>
void stream_pass(const std::array<const double*, ReadOnly>& in, const std::array<double*, ReadWrite>& out,
                 std::ptrdiff_t n) {
#pragma omp parallel for simd schedule(static)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    double sum = 0.0;
    for (int r = 0; r < ReadOnly; ++r) sum += in[static_cast<std::size_t>(r)][i];
    for (int w = 0; w < ReadWrite; ++w) out[static_cast<std::size_t>(w)][i] += sum;
  }
}

template <int ReadOnly, int ReadWrite>
double floor_seconds(std::size_t grains, int passes, int rounds) {
  std::vector<GrainArray> arrays(ReadOnly + ReadWrite, GrainArray(grains, 0.0));
  std::array<const double*, ReadOnly> in{};
  std::array<double*, ReadWrite> out{};
  for (int r = 0; r < ReadOnly; ++r) in[static_cast<std::size_t>(r)] = arrays[static_cast<std::size_t>(r)].data();
  for (int w = 0; w < ReadWrite; ++w)
    out[static_cast<std::size_t>(w)] = arrays[static_cast<std::size_t>(ReadOnly + w)].data();
  const auto n = static_cast<std::ptrdiff_t>(grains);
  stream_pass<ReadOnly, ReadWrite>(in, out, n);  // first touch, pages mapped
  double best = 0.0;
  for (int round = 0; round < rounds; ++round) {
    const auto start = std::chrono::steady_clock::now();
    for (int p = 0; p < passes; ++p) stream_pass<ReadOnly, ReadWrite>(in, out, n);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / passes;
    best = round == 0 ? seconds : std::min(best, seconds);
  }
  return best;
}

}  // namespace detail

/// Seconds of one pass of that shape over `grains` grains on the present
/// OpenMP threads: the best of `rounds` means of `passes` passes (the best,
/// as a floor: a busy neighbour only ever slows a round down).
template <StreamShape Shape>
double streaming_floor_seconds(std::size_t grains, int passes = 200, int rounds = 5) {
  return detail::floor_seconds<Shape.read_only, Shape.read_write>(grains, passes, rounds);
}

}  // namespace fdem::bench
