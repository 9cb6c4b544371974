#pragma once
// Di Felice (1994), "The voidage function for fluid-particle interaction
// systems", Int. J. Multiphase Flow 20(1), 153-159, Eq. 5, 9, 14:
//   f_D = 1/2 Cd0 rho (pi d^2 / 4) eps^2 |u - v| (u - v) eps^-chi
//   Cd0 = (0.63 + 4.8 / sqrt(Re))^2                         (Dallavalle)
//   chi = 3.7 - 0.65 exp(-(1.5 - log10 Re)^2 / 2)
//   Re  = eps rho |u - v| d / mu                             (Eq. 15, superficial slip)
// i.e. the isolated sphere's drag at the superficial slip eps (u - v),
// raised by the voidage function eps^-chi. In the form of Eq. 11:
//   K = 3/4 Cd0 rho |u-v| eps^(2 - chi) / d.
// Rong et al. (2013, rong.hpp) keep the form and change chi, so both are
// the one template below with their own chi = A(eps) - B(eps) g(Re),
// g = exp(-(1.5 - log10 Re)^2 / 2).
//
// Folded per step (s = |u - v|, a = eps rho d / mu, Re = a s):
//   Cd0 s = (0.63 sqrt(s) + 4.8 / sqrt(a))^2   (finite at zero slip: 23.04 / a)
//   c = V_p K = (0.63 sqrt(s) + k0)^2 exp(k1 + k2 g),   log10 Re = (k3 + ln s) / ln 10
//   k0 = 4.8 / sqrt(a), k1 = ln(pi d^2 rho / 8) + (2 - A) ln eps, k2 = B ln eps, k3 = ln a
// (V_p 3/4 rho / d = pi d^2 rho / 8). A lane without fluid gets k1 = -inf:
// exp(-inf) = 0 exactly, so c = 0. At zero slip g = exp(-inf) = 0 (the
// viscous limit chi = A), again exact IEEE arithmetic, no special case.
// Per subcycle: two square roots, one log, two exp (libmvec).
#include <limits>
#include <numbers>

#include "drag_laws/vector_math.hpp"
#include "drag_laws/drag_law.hpp"
#include "core/types.hpp"

namespace fdem {

/// Cd0 = (0.63 + 4.8 / sqrt(Re))^2, the Dallavalle (1948) single-sphere
/// drag coefficient both voidage-function laws use. Re must be > 0.
inline double dallavalle_drag_coefficient(double reynolds) {
  const double root = 0.63 + 4.8 / std::sqrt(reynolds);
  return root * root;
}

/// The Di Felice form with the voidage exponent chi = A(eps) - B(eps) g(Re).
template <class VoidageExponent>
struct VoidageFunctionLaw {
  static void fold(const DragLanes& eps, const DragLanes& d, const FluidProperties& fluid, FoldedDrag& out) {
    const double mu = fluid.viscosity, rho = fluid.density;
    for (std::size_t l = 0; l < drag_block_size; ++l) {  // once a step: scalar libm is fine
      if (!(eps[l] > 0.0)) {
        out.k[0][l] = out.k[2][l] = out.k[3][l] = 0.0;
        out.k[1][l] = -std::numeric_limits<double>::infinity();
        continue;
      }
      const double e = eps[l], di = d[l], ln_eps = std::log(e);
      const double a = e * rho * di / mu;  // Re / s
      out.k[0][l] = 4.8 / std::sqrt(a);
      out.k[1][l] = std::log(pi * di * di * rho / 8.0) + (2.0 - VoidageExponent::a(e)) * ln_eps;
      out.k[2][l] = VoidageExponent::b(e) * ln_eps;
      out.k[3][l] = std::log(a);
    }
  }

  static void coefficient(const FoldedDrag& f, const DragLanes& s2, DragLanes& c) {
    constexpr double inv_ln10 = 1.0 / std::numbers::ln10;
#pragma omp simd
    for (std::size_t l = 0; l < drag_block_size; ++l) {
      const double root_s = std::sqrt(std::sqrt(s2[l]));
      const double cd_root = 0.63 * root_s + f.k[0][l];                     // sqrt(Cd0 s)
      const double x = 1.5 - (f.k[3][l] + 0.5 * log(s2[l])) * inv_ln10;   // 1.5 - log10 Re
      const double g = exp(-0.5 * x * x);
      c[l] = cd_root * cd_root * exp(f.k[1][l] + f.k[2][l] * g);
    }
  }
};

/// Di Felice (1994): chi = 3.7 - 0.65 g(Re).
struct DiFeliceExponent {
  static double a(double) { return 3.7; }
  static double b(double) { return 0.65; }
};
using DiFelice = VoidageFunctionLaw<DiFeliceExponent>;

}  // namespace fdem
