#include "reference/brent_root.hpp"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_roots.h>

#include <memory>
#include <stdexcept>
#include <string>

namespace fdem {

double brent_root(const std::function<double(double)>& f, double lo, double hi, double rel_tol) {
  const double f_lo = f(lo), f_hi = f(hi);
  if (f_lo == 0.0) return lo;
  if (f_hi == 0.0) return hi;
  if ((f_lo > 0.0) == (f_hi > 0.0))
    throw std::invalid_argument("brent_root: f has the same sign at both ends of [" + std::to_string(lo) + ", " +
                                std::to_string(hi) + "]");
  gsl_function g;
  g.function = [](double x, void* params) { return (*static_cast<const std::function<double(double)>*>(params))(x); };
  g.params = const_cast<std::function<double(double)>*>(&f);
  std::unique_ptr<gsl_root_fsolver, decltype(&gsl_root_fsolver_free)> solver(
      gsl_root_fsolver_alloc(gsl_root_fsolver_brent), gsl_root_fsolver_free);
  gsl_root_fsolver_set(solver.get(), &g, lo, hi);
  for (int it = 0; it < 200; ++it) {
    gsl_root_fsolver_iterate(solver.get());
    lo = gsl_root_fsolver_x_lower(solver.get());
    hi = gsl_root_fsolver_x_upper(solver.get());
    if (gsl_root_test_interval(lo, hi, 0.0, rel_tol) == GSL_SUCCESS) return gsl_root_fsolver_root(solver.get());
  }
  throw std::runtime_error("brent_root: Brent's method did not converge in 200 iterations");
}

}  // namespace fdem
