#pragma once
// Stokes' law f = 3 pi mu d (u - v), K = 18 mu / d^2 (Stokes 1851; the
// Re -> 0 limit of every closure at eps = 1), independent of eps and of the
// slip: the reference for Stokes settling, not a closure for suspensions.
// Folded: k[0] = c = V_p 18 mu / d^2 [kg/s]; the subcycle only copies it.
#include "drag_laws/vector_math.hpp"
#include "drag_laws/drag_law.hpp"
#include "core/types.hpp"

namespace fdem {

struct Stokes {
  static void fold(const DragLanes& eps, const DragLanes& d, const FluidProperties& fluid, FoldedDrag& out) {
    const double mu = fluid.viscosity;
#pragma omp simd
    for (std::size_t l = 0; l < drag_block_size; ++l) {
      const bool fluid_here = eps[l] > 0.0;
      const double di = fluid_here ? d[l] : 1.0;
      const double vp = pi / 6.0 * di * di * di;  // V_p (Eq. 11)
      out.k[0][l] = fluid_here ? vp * (18.0 * mu / (di * di)) : 0.0;
      out.k[1][l] = out.k[2][l] = out.k[3][l] = 0.0;
    }
  }

  static void coefficient(const FoldedDrag& f, const DragLanes&, DragLanes& c) { c = f.k[0]; }
};

}  // namespace fdem
