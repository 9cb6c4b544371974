#pragma once
// A root of a scalar function on a bracket by Brent's method (GSL's
// gsl_root_fsolver_brent): the reference terminal velocity
// (settling_reference.cpp) and the studies' closed forms (Ergun's U_mf, the
// porosity of a homogeneous expansion, the viscosity for a target Reynolds
// number) are each one such root.
#include <functional>

namespace fdem {

/// The x in [lo, hi] with f(x) = 0, to a relative bracket width rel_tol.
/// Throws std::invalid_argument when f(lo) and f(hi) have the same sign (no
/// bracket), std::runtime_error when 200 iterations do not converge.
double brent_root(const std::function<double(double)>& f, double lo, double hi, double rel_tol = 1e-12);

}  // namespace fdem
