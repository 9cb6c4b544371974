#pragma once
// The block buffer of the vector pair passes (touching_pairs_avx512.hpp,
// touching_pairs_avx2.hpp): one block's touching pairs in pair order, what
// the law needs of each, then the force on i.
#include "core/types.hpp"

namespace fdem {

/// Block pairs and a vector's spill of Width lanes (the stores write whole
/// vectors), each array on its own cache line.
template <int Block, int Width>
struct TouchingLanes {
  static constexpr int capacity = Block + Width;
  alignas(64) Index i[capacity];
  alignas(64) Index j[capacity];
  alignas(64) double dx[capacity], dy[capacity], dz[capacity], dist2[capacity], ri[capacity], rj[capacity];
  alignas(64) double fx[capacity], fy[capacity], fz[capacity];
};

}  // namespace fdem
