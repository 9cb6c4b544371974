// The grains near a box face (see near_wall_grains.hpp).
#include "dem/near_wall_grains.hpp"

#include <algorithm>
#include <cmath>

#include <omp.h>

namespace fdem {

NearWallGrains::Scan NearWallGrains::scan(const Particles& p, const NeighbourList& list, const Box& domain,
                                          const double (&lowest)[3], const double (&highest)[3], bool test_all,
                                          std::ptrdiff_t parallel_min) {
  const double approach[faces] = {-lowest[0], highest[0], -lowest[1], highest[1], -lowest[2], highest[2]};
  bool refilter = stale_;
  for (int f = 0; f < faces; ++f) refilter = refilter || !(approach[f] + rounding_ <= reach_[f]);
  if (refilter) filter_candidates(p, list, domain, approach);
  const std::size_t count = test_all ? p.size() : candidates_.size();
  const BoxFaces box(domain);
  std::size_t outside = 0, found = 0;
  near_.resize(count);
  Index* const near_grains = near_.data();
  const double* const x = p.x.data();
  const double* const y = p.y.data();
  const double* const z = p.z.data();
  const double* const d = p.diameter.data();
  const Index* const candidates = candidates_.data();
  // Candidates [c0, c1), the near ones compacted in order from near_grains[c0]; returns how many.
  const auto scan_range = [&](std::size_t c0, std::size_t c1, std::size_t& outside_count) {
    std::size_t at = c0;
    for (std::size_t c = c0; c < c1; ++c) {  // no branch: which grains are near is random
      const Index k = test_all ? static_cast<Index>(c) : candidates[c];
      const auto i = static_cast<std::size_t>(k);
      outside_count += box.contains(x[i], y[i], z[i]) ? 0u : 1u;
      near_grains[at] = k;
      at += box.near_face(x[i], y[i], z[i], 0.5 * d[i]) ? 1u : 0u;
    }
    return at - c0;
  };
  const auto scount = static_cast<std::ptrdiff_t>(count);
  if (scount > parallel_min && omp_get_max_threads() > 1) {
    // A slab bed (scene B, 1.8 mm deep) has every grain a candidate: in
    // threads, each compacting its share in place, the shares then joined
    // in order (the same ascending set as one thread's scan).
    found_.assign(static_cast<std::size_t>(omp_get_max_threads()), 0);
    std::ptrdiff_t scan_threads = 1;
#pragma omp parallel reduction(+ : outside)
    {
      const auto threads = static_cast<std::ptrdiff_t>(omp_get_num_threads());
      const auto t = static_cast<std::ptrdiff_t>(omp_get_thread_num());
      if (t == 0) scan_threads = threads;
      found_[static_cast<std::size_t>(t)] = scan_range(
          static_cast<std::size_t>(scount * t / threads), static_cast<std::size_t>(scount * (t + 1) / threads), outside);
    }
    for (std::ptrdiff_t t = 0; t < scan_threads; ++t) {
      const auto c0 = static_cast<std::size_t>(scount * t / scan_threads);
      const std::size_t m = found_[static_cast<std::size_t>(t)];
      if (c0 != found) std::copy(near_grains + c0, near_grains + c0 + m, near_grains + found);
      found += m;
    }
  } else {
    found = scan_range(0, count, outside);
  }
  near_.resize(found);
  return {outside, found};
}

// The candidates: the grains within reach_[f] of a face f (gap less
// radius) at the list build, ascending; each reach at least twice the
// approach so far (or half the skin).
void NearWallGrains::filter_candidates(const Particles& p, const NeighbourList& list, const Box& domain,
                                       const double (&approach)[faces]) {
  stale_ = false;
  const std::size_t n = p.size();
  const double* const x0 = list.reference_x().data();
  const double* const y0 = list.reference_y().data();
  const double* const z0 = list.reference_z().data();
  const double* const d = p.diameter.data();
  const Vec3 lo = domain.lower, hi = domain.upper;
  // The displacements and gaps are rounded to a few ulp of the box's
  // coordinates: a margin a million times that.
  double scale = 0.0;
  for (int a = 0; a < 3; ++a) scale = std::max({scale, std::abs(lo[a]), std::abs(hi[a])});
  rounding_ = 1e-10 * scale;
  for (int f = 0; f < faces; ++f) reach_[f] = std::max(2.0 * (std::max(approach[f], 0.0) + rounding_), 0.5 * list.skin());
  candidates_.clear();
  for (std::size_t i = 0; i < n; ++i) {
    const double r = 0.5 * d[i];
    const bool candidate = x0[i] - lo.x() - r < reach_[0] || hi.x() - x0[i] - r < reach_[1] ||
                           y0[i] - lo.y() - r < reach_[2] || hi.y() - y0[i] - r < reach_[3] ||
                           z0[i] - lo.z() - r < reach_[4] || hi.z() - z0[i] - r < reach_[5] ||
                           !std::isfinite(x0[i] + y0[i] + z0[i]);
    if (candidate) candidates_.push_back(static_cast<Index>(i));
  }
}

}  // namespace fdem
