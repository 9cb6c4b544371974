#pragma once
// The subcycle drag kernel (Fig. 3: drag with the particle's current
// velocity and the fluid velocity frozen over the fluid step), compiled once
// per law (drag_law_table.cpp) and once for the semi-implicit exchange's
// frozen coefficients (coupling/drag_coupling.cpp). Every particle goes
// through the same eight-wide block code (the last block padded with
// zero-drag lanes), so its result does not depend on the thread count, its
// position in the block or the memory address of the arrays.
#include <algorithm>
#include <cstddef>

#include "drag_laws/drag_law.hpp"

namespace fdem {

/// coefficient(block index, squared slip, c): c = V_p K of the block's lanes.
template <class Coefficient>
void drag_subcycle_blocks(const DragSubcycle& step, Coefficient coefficient) {
  constexpr std::size_t kBlock = drag_block_size;
  const std::size_t n = step.particles;
  const auto nb = static_cast<std::ptrdiff_t>(step.blocks.size());
  const bool apply = !step.fx.empty();
  const double *pvx = step.vx.data(), *pvy = step.vy.data(), *pvz = step.vz.data();
  double *fx = step.fx.data(), *fy = step.fy.data(), *fz = step.fz.data();
  DragBlock* blocks = step.blocks.data();
#pragma omp parallel for schedule(static) if (nb > 256)
  for (std::ptrdiff_t b = 0; b < nb; ++b) {
    DragBlock& blk = blocks[b];
    const std::size_t base = static_cast<std::size_t>(b) * kBlock;
    const std::size_t m = std::min(kBlock, n - base);
    alignas(64) DragLanes sx, sy, sz, s2, c, gx, gy, gz;
    // 1. Slip u - v and its square. A full block (all but possibly the
    //    last) reads the velocities in place; the last one through
    //    zero-padded copies. Each `omp simd` loop touches one particle array:
    //    the compiler cannot tell that vx, fx, fy ... never alias, and
    //    without the pragma leaves such loops scalar (24 loads, adds and
    //    stores a block for the forces below).
    if (m == kBlock) {
#pragma omp simd
      for (std::size_t l = 0; l < kBlock; ++l) sx[l] = blk.ux[l] - pvx[base + l];
#pragma omp simd
      for (std::size_t l = 0; l < kBlock; ++l) sy[l] = blk.uy[l] - pvy[base + l];
#pragma omp simd
      for (std::size_t l = 0; l < kBlock; ++l) sz[l] = blk.uz[l] - pvz[base + l];
    } else {
      alignas(64) DragLanes vx{}, vy{}, vz{};
      for (std::size_t l = 0; l < m; ++l) {
        vx[l] = pvx[base + l];
        vy[l] = pvy[base + l];
        vz[l] = pvz[base + l];
      }
      for (std::size_t l = 0; l < kBlock; ++l) {
        sx[l] = blk.ux[l] - vx[l];
        sy[l] = blk.uy[l] - vy[l];
        sz[l] = blk.uz[l] - vz[l];
      }
    }
#pragma omp simd
    for (std::size_t l = 0; l < kBlock; ++l) s2[l] = sx[l] * sx[l] + sy[l] * sy[l] + sz[l] * sz[l];
    // 2. The law: c = V_p K.
    coefficient(static_cast<std::size_t>(b), s2, c);
    // 3. Eq. 11: f = c (u - v), summed for the step's mean.
#pragma omp simd
    for (std::size_t l = 0; l < kBlock; ++l) {
      gx[l] = c[l] * sx[l];
      gy[l] = c[l] * sy[l];
      gz[l] = c[l] * sz[l];
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

/// The kernel of one law: its per-subcycle closure on the block's folded coefficients.
template <class Law>
void drag_subcycle(const DragSubcycle& step) {
  DragBlock* blocks = step.blocks.data();
  drag_subcycle_blocks(step, [blocks](std::size_t b, const DragLanes& s2, DragLanes& c) {
    if constexpr (requires { &Law::subcycle_coefficient; })
      Law::subcycle_coefficient(blocks[b].folded, s2, c);  // the law's faster form for the kernel (its file bounds it)
    else
      Law::coefficient(blocks[b].folded, s2, c);
  });
}

}  // namespace fdem
