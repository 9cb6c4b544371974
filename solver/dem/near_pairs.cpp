// The pairs that can touch (see near_pairs.hpp).
#include "dem/near_pairs.hpp"

#include <algorithm>
#include <cmath>

#include <omp.h>

#include "dem/pair_lanes.hpp"

namespace fdem {

namespace {

#ifndef FDEM_DEM_PAIR_LANES
// The near filter of a build without vector lanes, with the vector
// filters' contract (pair_lanes::near_filter): the pairs [0, count) with
// |x_j - x_i|^2 < (r_i + r_j + margin)^2, in pair order, into near_i,
// near_j; returns how many. Compacted without a branch, as they are.
std::size_t near_filter_scalar(const Index* pi, const Index* pj, std::size_t count, const double* x, const double* y,
                               const double* z, const double* d, double margin, Index* near_i, Index* near_j) {
  std::size_t kept = 0;
  for (std::size_t k = 0; k < count; ++k) {
    const auto i = static_cast<std::size_t>(pi[k]), j = static_cast<std::size_t>(pj[k]);
    const double dx = x[j] - x[i], dy = y[j] - y[i], dz = z[j] - z[i];
    const double reach = 0.5 * d[i] + 0.5 * d[j] + margin;
    near_i[kept] = pi[k];
    near_j[kept] = pj[k];
    kept += dx * dx + dy * dy + dz * dz < reach * reach ? 1u : 0u;
  }
  return kept;
}
#endif

}  // namespace

void NearPairs::index(const NeighbourList& list, const Particles& p) {
  stale_ = false;
  ++generation_;
  near_valid_ = false;   // no near set yet
  track_drift_ = false;  // the displacements since the build first (select)
  const std::size_t n = p.size();
  const std::vector<Index>& offsets = list.offsets();
  const std::vector<Index>& indices = list.indices();
  half_i_.clear();
  half_j_.clear();
  half_start_.assign(n + 1, 0);
  if (offsets.size() != n + 1) return;
  // Each row's pairs with j > i, in row order, without a branch a pair:
  // which entries are past i is random (a branch on it mispredicted every
  // other entry). Every entry is written, the count advanced by the
  // keep; the arrays have room for all of them.
  half_i_.resize(indices.size());
  half_j_.resize(indices.size());
  Index* const hi = half_i_.data();
  Index* const hj = half_j_.data();
  const Index* const index = indices.data();
  std::size_t at = 0;
  for (std::size_t i = 0; i < n; ++i) {
    half_start_[i] = static_cast<Index>(at);
    const auto row = static_cast<Index>(i);
    for (auto k = static_cast<std::size_t>(offsets[i]); k < static_cast<std::size_t>(offsets[i + 1]); ++k) {
      const Index j = index[k];
      hi[at] = row;
      hj[at] = j;
      at += j > row ? 1u : 0u;
    }
  }
  half_start_[n] = static_cast<Index>(at);
  half_i_.resize(at);
  half_j_.resize(at);
  const double* const x0 = list.reference_x().data();
  const double* const y0 = list.reference_y().data();
  const double* const z0 = list.reference_z().data();
  const double* const d = p.diameter.data();
  double scale = 0.0;  // largest coordinate or diameter, for the rounding allowance
#pragma omp simd reduction(max : scale)
  for (std::size_t i = 0; i < n; ++i)
    scale = std::max(scale, std::max(std::max(std::abs(x0[i]), std::abs(y0[i])), std::max(std::abs(z0[i]), d[i])));
  // The near set's distance test and the contact test are each rounded
  // (a few ulp of the coordinates): a margin a million times that.
  build_scale_ = scale;
  gap_rounding_ = 1e-10 * scale;
}

NearPairs::Selection NearPairs::select(const NeighbourList& list, const Particles& p, double approach, double moved,
                                       std::ptrdiff_t parallel_min) {
  if (stale_) index(list, p);
  const double skin = list.skin();
  near_approach_ += approach;
  if (near_valid_) {
    const bool by_drift = near_approach_ + gap_rounding_ <= near_margin_;
    const bool by_displacement = (moved + near_moved_) * (1.0 + 1e-12) + gap_rounding_ <= near_margin_;
    if (by_drift || by_displacement) return {near()};
    // Ran out: the cloud deforms, and from now to the next build the
    // displacements would keep running out.
    track_drift_ = true;
  }
  double margin = std::numeric_limits<double>::infinity();
  if (std::isfinite(approach))
    margin = std::max(16.0 * approach, skin / 1024.0) + gap_rounding_;
  else if (std::isfinite(moved))
    margin = std::max(4.0 * moved, skin / 1024.0) + gap_rounding_;
  if (!(margin < 0.5 * skin)) {
    near_valid_ = false;
    if (std::isfinite(moved)) track_drift_ = true;  // the drift bound may keep a set next step
    return {all()};
  }
  const bool threaded = filter(margin, p, parallel_min);
  near_moved_ = moved;  // infinite: unknown, so only the drift bound keeps the set
  return {near(), true, threaded};
}

// The near set at the present positions: the half pairs with
// |x_i - x_j| < r_i + r_j + margin, in pair order, compacted without a
// branch (which pairs are near is random), eight pairs a vector on
// AVX-512, four on AVX2 (pair_lanes::near_filter), one at a time in a
// build without them (near_filter_scalar); in shares on threads
// (filter_in_shares), every build alike. The margin holds a rounding
// allowance (gap_rounding_), so a pair the contact test would find
// touching is kept whichever way the test here rounds. Returns whether it
// ran in shares on more than one thread.
bool NearPairs::filter(double margin, const Particles& p, std::ptrdiff_t parallel_min) {
  ++generation_;
  near_valid_ = true;
  near_margin_ = margin;
  near_approach_ = 0.0;
  const std::size_t n = p.size();
  const std::size_t total = half_j_.size();
  near_i_.resize(total + 8);  // + a vector: the vector filters store whole ones
  near_j_.resize(total + 8);
  near_start_.resize(n + 1);
  bool threaded = false;
  const std::size_t kept = filter_in_shares(margin, p, parallel_min, threaded);
  // Where each grain's near pairs start (pairs in ascending i): the pairs
  // counted by row, then summed. (A walk that advanced through the pairs
  // row by row took 90-106 us a filtering of the plume, its loop exit a
  // branch mispredicted at random; 2026-12-07.)
  std::fill(near_start_.begin(), near_start_.end(), Index{0});
  for (std::size_t k = 0; k < kept; ++k) ++near_start_[static_cast<std::size_t>(near_i_[k]) + 1];
  for (std::size_t i = 0; i < n; ++i) near_start_[i + 1] += near_start_[i];
  near_count_ = kept;
  return threaded;
}

// The near filter over the half pairs into near_i_, near_j_; returns how
// many are near. On threads each filters an equal share of the pairs into
// its own buffer, then copies its near pairs to where the earlier shares'
// end: the same pairs in the same order as one filter (the pair pass's
// bits do not depend on the thread count). On one thread it was 7.5 us a
// step of the 13 us that ran alone before the pair threads (the plume, 28k
// pairs filtered every ~15 steps); in shares, 94-97 -> 51-52 us a
// filtering on 2 threads (2026-12-07, Zen 4).
std::size_t NearPairs::filter_in_shares(double margin, const Particles& p, std::ptrdiff_t parallel_min,
                                        bool& threaded) {
  const std::size_t total = half_j_.size();
  const auto filter_range = [&](std::size_t begin, std::size_t end, Index* out_i, Index* out_j) {
#ifdef FDEM_DEM_PAIR_LANES
    return pair_lanes::near_filter(half_i_.data() + begin, half_j_.data() + begin, end - begin, p.x.data(),
                                   p.y.data(), p.z.data(), p.diameter.data(), margin, out_i, out_j);
#else
    return near_filter_scalar(half_i_.data() + begin, half_j_.data() + begin, end - begin, p.x.data(), p.y.data(),
                              p.z.data(), p.diameter.data(), margin, out_i, out_j);
#endif
  };
  const int threads = omp_get_max_threads();
  if (threads == 1 || static_cast<std::ptrdiff_t>(total) <= parallel_min)
    return filter_range(0, total, near_i_.data(), near_j_.data());
  if (shares_.size() < static_cast<std::size_t>(threads)) shares_.resize(static_cast<std::size_t>(threads));
  std::size_t kept = 0;
#pragma omp parallel reduction(+ : kept)
  {
    const auto t = static_cast<std::size_t>(omp_get_thread_num());
    const auto count = static_cast<std::size_t>(omp_get_num_threads());
    const std::size_t begin = total * t / count, end = total * (t + 1) / count;
    Share& mine = shares_[t];
    mine.i.resize(end - begin + 8);  // + a vector: the filter stores whole ones
    mine.j.resize(end - begin + 8);
    mine.count = filter_range(begin, end, mine.i.data(), mine.j.data());
    if (t == 0 && count > 1) threaded = true;
#pragma omp barrier
    std::size_t at = 0;
    for (std::size_t s = 0; s < t; ++s) at += shares_[s].count;
    std::copy_n(mine.i.begin(), mine.count, near_i_.begin() + static_cast<std::ptrdiff_t>(at));
    std::copy_n(mine.j.begin(), mine.count, near_j_.begin() + static_cast<std::ptrdiff_t>(at));
    kept += mine.count;
  }
  return kept;
}

}  // namespace fdem
