// GrainArray (core/grain_array.hpp): each large per-grain array starts on its
// own cache line within a 4 KiB page, so the DEM's ~24 streams of a step do
// not share L1 sets; the contents behave as a std::vector's.
#include <gtest/gtest.h>

#include <cstdint>
#include <numeric>
#include <set>
#include <vector>

#include "core/grain_array.hpp"
#include "core/particles.hpp"

namespace fdem {
namespace {

std::uintptr_t page_offset(const double* p) { return reinterpret_cast<std::uintptr_t>(p) % 4096; }

// 28224 grains (the plume's): every array well above the 128 KiB from which
// glibc maps each allocation page-aligned, which put every array on one offset.
TEST(GrainArray, LargeArraysOfAParticleSetStartOnDistinctCacheLines) {
  constexpr std::size_t n = 28224;
  Particles p;
  for (GrainArray* a : {&p.x, &p.y, &p.z, &p.vx, &p.vy, &p.vz, &p.fx, &p.fy, &p.fz, &p.diameter, &p.mass, &p.wx,
                        &p.wy, &p.wz, &p.tx, &p.ty, &p.tz, &p.inertia})
    a->assign(n, 1.0);
  std::set<std::uintptr_t> offsets;
  for (const GrainArray* a : {&p.x, &p.y, &p.z, &p.vx, &p.vy, &p.vz, &p.fx, &p.fy, &p.fz, &p.diameter, &p.mass,
                              &p.wx, &p.wy, &p.wz, &p.tx, &p.ty, &p.tz, &p.inertia}) {
    EXPECT_EQ(page_offset(a->data()) % 64, 0u) << "a whole cache line, vector-aligned";
    offsets.insert(page_offset(a->data()) / 64);
  }
  EXPECT_EQ(offsets.size(), 18u) << "one L1 set offset each";
}

// Any 64 successive large allocations take 64 distinct line offsets (a
// stride of 37 lines, coprime to the 64 lines of a page).
TEST(GrainArray, SixtyFourSuccessiveAllocationsCoverEveryLineOfAPage) {
  std::vector<GrainArray> arrays(64);
  std::set<std::uintptr_t> lines;
  for (GrainArray& a : arrays) {
    a.resize(4096);  // 32 KiB: staggered
    lines.insert(page_offset(a.data()) / 64);
  }
  EXPECT_EQ(lines.size(), 64u);
}

// Growth, copies and moves keep the values (the data moves to new blocks,
// each freed through the page it starts in: ASan checks the frees).
TEST(GrainArray, BehavesAsAVectorThroughGrowthCopyAndMove) {
  GrainArray a;
  for (int i = 0; i < 100000; ++i) a.push_back(0.5 * i);  // small, then staggered blocks
  GrainArray b = a;
  const GrainArray c = std::move(a);
  ASSERT_EQ(b.size(), 100000u);
  EXPECT_EQ(b, c);
  EXPECT_EQ(std::accumulate(b.begin(), b.end(), 0.0), 0.5 * 99999.0 * 100000.0 / 2.0);
  b.resize(10);  // shrink_to_fit moves back below the staggering size
  b.shrink_to_fit();
  EXPECT_EQ(b[9], 4.5);
}

}  // namespace
}  // namespace fdem
