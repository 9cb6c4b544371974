// Verlet list from a compact cell grid (see neighbour_list.hpp).
#include "dem/neighbour_list.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <omp.h>

#include "dem/avx2_lanes.hpp"
#include "dem/avx512_lanes.hpp"

namespace fdem {

namespace {
// The search grid may have up to 16 cells a particle (64 B a particle of
// cell starts at most) before its edge is coarsened past the cutoff: a
// deformed cloud (the plume at 0.9 s, 28224 grains) filled the old bound of
// 4 and got cells 1.5x or more too large, so each grain tested ~3x the
// candidates (callgrind, one build: 76.4e6 -> 33.5e6 instructions; same
// list, since rows are sorted and hold every pair within the cutoff). The
// grain sort keeps its own grid (cell_order.cpp, the default bound): the
// order, and so every bit of a sorted run, is unchanged.
constexpr double kCellsPerParticle = 16.0;
}  // namespace

void NeighbourList::build(const Particles& p, double skin_m) {
  const std::size_t n = p.size();
  skin_ = skin_m;
  ++builds_;
  x0_ = p.x;
  y0_ = p.y;
  z0_ = p.z;
  offsets_.assign(n + 1, 0);
  indices_.clear();
  listed_.clear();
  if (n == 0) return;

  // 1. Cells of edge at least the largest possible pair cutoff, over the
  //    particles' bounding box, the particles counting-sorted into them.
  double d_max = 0.0;
  for (std::size_t i = 0; i < n; ++i) d_max = std::max(d_max, p.diameter[i]);
  grid_.build(p, d_max + skin_m, kCellsPerParticle);
  const int nx = grid_.dims[0], ny = grid_.dims[1], nz = grid_.dims[2];
  const Index* const cell_of = grid_.cell_of.data();
  const Index* const cell_start = grid_.cell_start.data();
  const Index* const slots = grid_.slots.data();
  const double* const x = p.x.data();
  const double* const y = p.y.data();
  const double* const z = p.z.data();
  const double* const d = p.diameter.data();

  // 2. The particles' centres and radii in slot order, so that a cell's
  //    candidates are read as contiguous runs, not gathered by index.
  const auto sn = static_cast<std::ptrdiff_t>(n);
  slot_x_.resize(n);
  slot_y_.resize(n);
  slot_z_.resize(n);
  slot_r_.resize(n);
  {
    double* const sx = slot_x_.data();
    double* const sy = slot_y_.data();
    double* const sz = slot_z_.data();
    double* const sr = slot_r_.data();
#pragma omp parallel for simd schedule(static) if (sn > 2500)
    for (std::ptrdiff_t s = 0; s < sn; ++s) {
      const auto j = static_cast<std::size_t>(slots[s]);
      sx[s] = x[j];
      sy[s] = y[j];
      sz[s] = z[j];
      sr[s] = 0.5 * d[j];
    }
  }
  const double* const sx = slot_x_.data();
  const double* const sy = slot_y_.data();
  const double* const sz = slot_z_.data();
  const double* const sr = slot_r_.data();

  // 3. The 27 cells around each particle: per (z, y) row of cells the
  //    three cells along x are adjacent in the cell numbering, so their
  //    particles are one run of slots. Which candidates are within the
  //    cutoff is random, so the run is tested without a branch, each
  //    candidate written at the end of `found` and kept by advancing the
  //    count (the row sorted after).
  auto visit = [=](std::size_t i, Index* found) {
    const int c = cell_of[i];
    const int cx = c % nx, cy = (c / nx) % ny, cz = c / (nx * ny);
    const int kx0 = std::max(cx - 1, 0), kx1 = std::min(cx + 1, nx - 1);
    const double ri = 0.5 * d[i];
    const double xi = x[i], yi = y[i], zi = z[i];
    const auto self = static_cast<Index>(i);
    std::size_t count = 0;
    for (int kz = std::max(cz - 1, 0); kz <= std::min(cz + 1, nz - 1); ++kz)
      for (int ky = std::max(cy - 1, 0); ky <= std::min(cy + 1, ny - 1); ++ky) {
        const auto row = static_cast<std::size_t>((kz * ny + ky) * nx);
        const auto last = static_cast<std::size_t>(cell_start[row + static_cast<std::size_t>(kx1) + 1]);
        const auto first = static_cast<std::size_t>(cell_start[row + static_cast<std::size_t>(kx0)]);
#ifdef FDEM_DEM_AVX512
        // Eight candidates a vector, the kept ones compressed to the front
        // of a register and stored as a whole vector (`found` has a
        // vector's spill): a run (three cells, a few grains each) is one or
        // two iterations. Not a compress-store to memory: Zen 4 microcodes
        // it (one a ~100 cycles), which made this build 3x slower there.
        const __m512d vx = _mm512_set1_pd(xi), vy = _mm512_set1_pd(yi), vz = _mm512_set1_pd(zi);
        const __m512d vr = _mm512_set1_pd(ri), vskin = _mm512_set1_pd(skin_m);
        const __m256i vself = _mm256_set1_epi32(self);
        for (std::size_t s = first; s < last; s += 8) {
          const __mmask8 lanes = avx512_lanes::first_lanes(static_cast<std::ptrdiff_t>(last - s));
          const __m512d dx = _mm512_sub_pd(_mm512_maskz_loadu_pd(lanes, sx + s), vx);
          const __m512d dy = _mm512_sub_pd(_mm512_maskz_loadu_pd(lanes, sy + s), vy);
          const __m512d dz = _mm512_sub_pd(_mm512_maskz_loadu_pd(lanes, sz + s), vz);
          const __m512d dist2 = _mm512_fmadd_pd(dz, dz, _mm512_fmadd_pd(dy, dy, _mm512_mul_pd(dx, dx)));
          const __m512d cut = _mm512_add_pd(_mm512_add_pd(vr, _mm512_maskz_loadu_pd(lanes, sr + s)), vskin);
          const __m256i j = _mm256_maskz_loadu_epi32(lanes, slots + s);
          const __mmask8 keep = _mm512_mask_cmp_pd_mask(lanes, dist2, _mm512_mul_pd(cut, cut), _CMP_LT_OQ) &
                                _mm256_cmpneq_epi32_mask(j, vself);
          _mm256_storeu_si256(reinterpret_cast<__m256i*>(found + count), _mm256_maskz_compress_epi32(keep, j));
          count += static_cast<std::size_t>(__builtin_popcount(keep));
        }
#elif defined(FDEM_DEM_AVX2)
        // As above, four candidates a vector: the kept ones moved to the
        // front and stored as a whole vector (`found` has a vector's spill).
        const __m256d vx = _mm256_set1_pd(xi), vy = _mm256_set1_pd(yi), vz = _mm256_set1_pd(zi);
        const __m256d vr = _mm256_set1_pd(ri), vskin = _mm256_set1_pd(skin_m);
        const __m128i vself = _mm_set1_epi32(self);
        for (std::size_t s = first; s < last; s += 4) {
          const __m128i lanes = avx2_lanes::first_lanes(static_cast<std::ptrdiff_t>(last - s));
          const __m256i dlanes = avx2_lanes::double_lanes(lanes);
          const __m256d dx = _mm256_sub_pd(_mm256_maskload_pd(sx + s, dlanes), vx);
          const __m256d dy = _mm256_sub_pd(_mm256_maskload_pd(sy + s, dlanes), vy);
          const __m256d dz = _mm256_sub_pd(_mm256_maskload_pd(sz + s, dlanes), vz);
          const __m256d dist2 = _mm256_fmadd_pd(dz, dz, _mm256_fmadd_pd(dy, dy, _mm256_mul_pd(dx, dx)));
          const __m256d cut = _mm256_add_pd(_mm256_add_pd(vr, _mm256_maskload_pd(sr + s, dlanes)), vskin);
          const __m128i j = _mm_maskload_epi32(slots + s, lanes);
          const int other = ~avx2_lanes::lane_bits(_mm_cmpeq_epi32(j, vself));
          const int keep = _mm256_movemask_pd(_mm256_cmp_pd(dist2, _mm256_mul_pd(cut, cut), _CMP_LT_OQ)) & other &
                           avx2_lanes::lane_bits(lanes);
          _mm_storeu_si128(reinterpret_cast<__m128i*>(found + count), avx2_lanes::compress(keep, j));
          count += static_cast<std::size_t>(__builtin_popcount(static_cast<unsigned>(keep)));
        }
#else
        for (std::size_t s = first; s < last; ++s) {
          const double dx = sx[s] - xi, dy = sy[s] - yi, dz = sz[s] - zi;
          const double cut = ri + sr[s] + skin_m;
          const Index j = slots[s];
          found[count] = j;
          count += (dx * dx + dy * dy + dz * dz < cut * cut) & (j != self) ? 1u : 0u;
        }
#endif
      }
    return count;
  };
  // One pass: each thread fills the rows of a contiguous block of particles
  // into its own buffer, then copies it to its place in the list once the
  // row lengths are known (the same list as a count-then-fill in two passes,
  // for half the distance tests).
#pragma omp parallel if (sn > 2500)
  {
    const auto threads = static_cast<std::ptrdiff_t>(omp_get_num_threads());
    const auto t = static_cast<std::ptrdiff_t>(omp_get_thread_num());
#pragma omp single
    thread_rows_.resize(static_cast<std::size_t>(threads));
    const std::ptrdiff_t begin = sn * t / threads, end = sn * (t + 1) / threads;
    std::vector<Index>& rows = thread_rows_[static_cast<std::size_t>(t)].rows;
    std::vector<Index>& found = thread_rows_[static_cast<std::size_t>(t)].found;
    found.resize(n + 8);  // a row's candidates are at most every particle; + a vector loop's spill (8 lanes)
    rows.clear();
    for (std::ptrdiff_t i = begin; i < end; ++i) {
      const auto ui = static_cast<std::size_t>(i);
      const std::size_t count = visit(ui, found.data());
      std::sort(found.begin(), found.begin() + static_cast<std::ptrdiff_t>(count));
      rows.insert(rows.end(), found.begin(), found.begin() + static_cast<std::ptrdiff_t>(count));
      offsets_[ui + 1] = static_cast<Index>(count);
    }
#pragma omp barrier
#pragma omp single
    {
      for (std::size_t i = 0; i < n; ++i) {
        if (offsets_[i + 1] > 0) listed_.push_back(static_cast<Index>(i));
        offsets_[i + 1] += offsets_[i];
      }
      indices_.resize(static_cast<std::size_t>(offsets_[n]));
    }
    std::copy(rows.begin(), rows.end(), indices_.begin() + offsets_[static_cast<std::size_t>(begin)]);
  }
}

bool NeighbourList::needs_rebuild(const Particles& p) const {
  const std::size_t n = p.size();
  if (n != x0_.size()) return true;
  constexpr double inf = std::numeric_limits<double>::infinity();
  double max2 = 0.0, lo_x = inf, lo_y = inf, lo_z = inf, hi_x = -inf, hi_y = -inf, hi_z = -inf;
  const auto sn = static_cast<std::ptrdiff_t>(n);
#pragma omp parallel for simd schedule(static) if (sn > 2500) reduction(max : max2, hi_x, hi_y, hi_z) \
    reduction(min : lo_x, lo_y, lo_z)
  for (std::ptrdiff_t si = 0; si < sn; ++si) {
    const auto i = static_cast<std::size_t>(si);
    const double dx = p.x[i] - x0_[i], dy = p.y[i] - y0_[i], dz = p.z[i] - z0_[i];
    max2 = std::max(max2, dx * dx + dy * dy + dz * dz);
    lo_x = std::min(lo_x, dx); hi_x = std::max(hi_x, dx);
    lo_y = std::min(lo_y, dy); hi_y = std::max(hi_y, dy);
    lo_z = std::min(lo_z, dz); hi_z = std::max(hi_z, dz);
  }
  return n > 0 && skin_exceeded(skin_, max2, hi_x - lo_x, hi_y - lo_y, hi_z - lo_z);
}

}  // namespace fdem
