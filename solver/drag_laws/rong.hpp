#pragma once
// Rong, Dong and Yu (2013), "Lattice-Boltzmann simulation of fluid flow
// through packed beds of uniform spheres: Effect of porosity", Chem. Eng.
// Sci. 99, 44-58, Eq. 13: Di Felice's form (di_felice.hpp) with the voidage
// exponent refitted to LB simulations of packed beds, eps 0.37-0.98 and
// Re 0.1-1000:
//   chi = 2.65 (eps + 1) - (5.3 - 3.5 eps) eps^2 exp(-(1.5 - log10 Re)^2 / 2)
#include "drag_laws/di_felice.hpp"

namespace fdem {

struct RongExponent {
  static double a(double eps) { return 2.65 * (eps + 1.0); }
  static double b(double eps) { return (5.3 - 3.5 * eps) * eps * eps; }
};
using Rong = VoidageFunctionLaw<RongExponent>;

}  // namespace fdem
