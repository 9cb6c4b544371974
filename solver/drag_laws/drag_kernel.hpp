#pragma once
// The subcycle drag kernel (Fig. 3: drag with the particle's current
// velocity and the fluid velocity frozen over the fluid step), compiled once
// per law (drag_law_table.cpp) and once for the semi-implicit exchange's
// frozen coefficients (coupling/drag_coupling.cpp). Every particle goes
// through the same eight-wide block code (the last block padded with
// zero-drag lanes), so its result does not depend on the thread count, its
// position in the block or the memory address of the arrays. The blocks go
// to the law in groups (drag_group_size), so a law can run a long per-lane
// polynomial for many blocks in one loop (ergun_wen_yu.hpp); that too
// changes no lane's arithmetic.
#include <algorithm>
#include <cstddef>

#include "drag_laws/drag_law.hpp"

namespace fdem {

/// coefficient(first block, blocks in the group (1 .. drag_group_size),
/// squared slips, c): c = V_p K of the group's lanes.
template <class GroupCoefficient>
void drag_subcycle_groups(const DragSubcycle& step, GroupCoefficient coefficient) {
  constexpr std::size_t kBlock = drag_block_size, kGroup = drag_group_size;
  const std::size_t n = step.particles;
  const std::size_t nb = step.blocks.size();
  const auto groups = static_cast<std::ptrdiff_t>((nb + kGroup - 1) / kGroup);
  const bool apply = !step.fx.empty();
  const double *pvx = step.vx.data(), *pvy = step.vy.data(), *pvz = step.vz.data();
  double *fx = step.fx.data(), *fy = step.fy.data(), *fz = step.fz.data();
  DragBlock* blocks = step.blocks.data();
#pragma omp parallel for schedule(static) if (nb > 256)
  for (std::ptrdiff_t g = 0; g < groups; ++g) {
    const std::size_t b0 = static_cast<std::size_t>(g) * kGroup;
    const std::size_t count = std::min(kGroup, nb - b0);
    alignas(64) DragGroupLanes sx, sy, sz, s2, c;
    // 1. Slip u - v and its square. A full block (all but possibly the
    //    last) reads the velocities in place; the last one through
    //    zero-padded copies. Each `omp simd` loop touches one particle array:
    //    the compiler cannot tell that vx, fx, fy ... never alias, and
    //    without the pragma leaves such loops scalar (24 loads, adds and
    //    stores a block for the forces below).
    for (std::size_t q = 0; q < count; ++q) {
      const DragBlock& blk = blocks[b0 + q];
      const std::size_t base = (b0 + q) * kBlock;
      const std::size_t m = std::min(kBlock, n - base);
      if (m == kBlock) {
#pragma omp simd
        for (std::size_t l = 0; l < kBlock; ++l) sx[q][l] = blk.ux[l] - pvx[base + l];
#pragma omp simd
        for (std::size_t l = 0; l < kBlock; ++l) sy[q][l] = blk.uy[l] - pvy[base + l];
#pragma omp simd
        for (std::size_t l = 0; l < kBlock; ++l) sz[q][l] = blk.uz[l] - pvz[base + l];
      } else {
        alignas(64) DragLanes vx{}, vy{}, vz{};
        for (std::size_t l = 0; l < m; ++l) {
          vx[l] = pvx[base + l];
          vy[l] = pvy[base + l];
          vz[l] = pvz[base + l];
        }
        for (std::size_t l = 0; l < kBlock; ++l) {
          sx[q][l] = blk.ux[l] - vx[l];
          sy[q][l] = blk.uy[l] - vy[l];
          sz[q][l] = blk.uz[l] - vz[l];
        }
      }
#pragma omp simd
      for (std::size_t l = 0; l < kBlock; ++l)
        s2[q][l] = sx[q][l] * sx[q][l] + sy[q][l] * sy[q][l] + sz[q][l] * sz[q][l];
    }
    // 2. The law: c = V_p K.
    coefficient(b0, count, s2, c);
    // 3. Eq. 11: f = c (u - v), summed for the step's mean.
    for (std::size_t q = 0; q < count; ++q) {
      DragBlock& blk = blocks[b0 + q];
      const std::size_t base = (b0 + q) * kBlock;
      const std::size_t m = std::min(kBlock, n - base);
      alignas(64) DragLanes gx, gy, gz;
#pragma omp simd
      for (std::size_t l = 0; l < kBlock; ++l) {
        gx[l] = c[q][l] * sx[q][l];
        gy[l] = c[q][l] * sy[q][l];
        gz[l] = c[q][l] * sz[q][l];
        blk.sum_x[l] += gx[l];
        blk.sum_y[l] += gy[l];
        blk.sum_z[l] += gz[l];
      }
      if (!apply) continue;
      if (m == kBlock) {
#pragma omp simd
        for (std::size_t l = 0; l < kBlock; ++l) fx[base + l] += gx[l];
#pragma omp simd
        for (std::size_t l = 0; l < kBlock; ++l) fy[base + l] += gy[l];
#pragma omp simd
        for (std::size_t l = 0; l < kBlock; ++l) fz[base + l] += gz[l];
      } else {
        for (std::size_t l = 0; l < m; ++l) {
          fx[base + l] += gx[l];
          fy[base + l] += gy[l];
          fz[base + l] += gz[l];
        }
      }
    }
  }
}

/// The same with a coefficient(block index, squared slip, c) of one block.
template <class Coefficient>
void drag_subcycle_blocks(const DragSubcycle& step, Coefficient coefficient) {
  drag_subcycle_groups(step, [&coefficient](std::size_t b0, std::size_t count, const DragGroupLanes& s2,
                                            DragGroupLanes& c) {
    for (std::size_t q = 0; q < count; ++q) coefficient(b0 + q, s2[q], c[q]);
  });
}

/// The kernel of one law: its per-subcycle closure on the blocks' folded coefficients.
template <class Law>
void drag_subcycle(const DragSubcycle& step) {
  DragBlock* blocks = step.blocks.data();
  if constexpr (requires { &Law::subcycle_coefficients; }) {
    // The law's faster form for the kernel (its file bounds it).
    drag_subcycle_groups(step, [blocks](std::size_t b0, std::size_t count, const DragGroupLanes& s2,
                                        DragGroupLanes& c) { Law::subcycle_coefficients(blocks + b0, count, s2, c); });
  } else {
    drag_subcycle_blocks(step, [blocks](std::size_t b, const DragLanes& s2, DragLanes& c) {
      Law::coefficient(blocks[b].folded, s2, c);
    });
  }
}

}  // namespace fdem
