#pragma once
// Beetstra, van der Hoef and Kuipers (2007), "Drag force of intermediate
// Reynolds number flow past mono- and bidisperse arrays of spheres", AIChE J.
// 53(2), 489-501, Eq. 16 (monodisperse), fitted to LB simulations for
// phi = 1 - eps up to 0.6 and Re up to 1000:
//   f_D = 3 pi mu d eps F (u - v)        (F: the drag over Stokes' at the superficial slip)
//   F = 10 phi / eps^2 + eps^2 (1 + 1.5 sqrt(phi))
//     + 0.413 Re / (24 eps^2) (1/eps + 3 phi eps + 8.4 Re^-0.343) / (1 + 10^(3 phi) Re^-(1 + 4 phi)/2)
//   Re = eps rho |u - v| d / mu          (Eq. 15, superficial slip)
// In the form of Eq. 11: K = 18 mu eps F / d^2. At eps = 1, Re -> 0: F = 1, Stokes.
//
// The Re part rewritten to stay finite at zero slip (multiply the fraction
// by Re^((1+4 phi)/2) / Re^((1+4 phi)/2)):
//   0.413 / (24 eps^2) (Re (1/eps + 3 phi eps) + 8.4 Re^0.657) / (1 + 10^(3 phi) Re^-(1+4 phi)/2)
// with Re^p = exp(p ln Re): at Re = 0 it is (0 + 0) / (1 + inf) = 0, exactly.
// Folded per step: k0 = V_p 18 mu eps / d^2 (10 phi / eps^2 + eps^2 (1 + 1.5 sqrt(phi)))
// (the Re -> 0 part), k1 = V_p 18 mu eps / d^2 * 0.413 / (24 eps^2), k2 = phi,
// k3 = ln a (a = eps rho d / mu); a lane without fluid gets all zero (c = 0).
// Per subcycle: ln Re = k3 + ln s, one log and three exp (libmvec).
#include <numbers>

#include "drag_laws/vector_math.hpp"
#include "drag_laws/drag_law.hpp"
#include "core/types.hpp"

namespace fdem {

struct Beetstra {
  static void fold(const DragLanes& eps, const DragLanes& d, const FluidProperties& fluid, FoldedDrag& out) {
    const double mu = fluid.viscosity, rho = fluid.density;
    for (std::size_t l = 0; l < drag_block_size; ++l) {  // once a step: scalar libm is fine
      if (!(eps[l] > 0.0)) {
        for (auto& k : out.k) k[l] = 0.0;
        continue;
      }
      const double e = eps[l], di = d[l], phi = 1.0 - e;
      const double vp = pi / 6.0 * di * di * di;
      const double stokes = vp * 18.0 * mu * e / (di * di);  // V_p 18 mu eps / d^2
      out.k[0][l] = stokes * (10.0 * phi / (e * e) + e * e * (1.0 + 1.5 * std::sqrt(phi)));
      out.k[1][l] = stokes * 0.413 / (24.0 * e * e);
      out.k[2][l] = phi;
      out.k[3][l] = std::log(e * rho * di / mu);
    }
  }

  static void coefficient(const FoldedDrag& f, const DragLanes& s2, DragLanes& c) {
    constexpr double ln10 = std::numbers::ln10;
#pragma omp simd
    for (std::size_t l = 0; l < drag_block_size; ++l) {
      const double phi = f.k[2][l], e = 1.0 - phi;
      const double ln_re = f.k[3][l] + 0.5 * log(s2[l]);
      const double re = exp(ln_re);
      const double numerator = re * (1.0 / e + 3.0 * phi * e) + 8.4 * exp(0.657 * ln_re);
      const double denominator = 1.0 + exp(3.0 * phi * ln10 - 0.5 * (1.0 + 4.0 * phi) * ln_re);
      c[l] = f.k[0][l] + f.k[1][l] * numerator / denominator;
    }
  }
};

}  // namespace fdem
