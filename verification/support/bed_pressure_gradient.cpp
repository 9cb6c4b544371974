#include "bed_pressure_gradient.hpp"

namespace fdem::verification {

double ergun_gradient(double eps, double U, double d, double rho, double mu) {
  return 150.0 * (1 - eps) * (1 - eps) * mu * U / (eps * eps * eps * d * d) +
         1.75 * (1 - eps) * rho * U * U / (eps * eps * eps * d);
}

double simplified_gradient(double eps, double U, double d, double rho, double mu) {
  return 150.0 * (1 - eps) * (1 - eps) * mu * U / (eps * eps * d * d) + 1.75 * (1 - eps) * rho * U * U / (eps * d);
}

}  // namespace fdem::verification
