#include "fluid/fluid_element.hpp"

#include <cmath>


namespace fdem {

FluidStabilization fluid_stabilization(double h, const Eigen::Vector3d& mean_velocity, double density,
                                       double viscosity, double dt) {
  FluidStabilization s;
  s.h = h;
  const double nu = viscosity / density;
  const double advective = 2.0 * mean_velocity.norm() / s.h;
  const double diffusive = 4.0 * nu / (s.h * s.h);
  const double transient = 2.0 / dt;  // 0 for a steady solve (dt = inf)
  s.tau_momentum = 1.0 / std::sqrt(transient * transient + advective * advective + diffusive * diffusive);
  s.tau_continuity = s.h * s.h / (12.0 * s.tau_momentum);  // Whiting & Jansen, tr G ~ 12 / h^2
  return s;
}

void fluid_element_system(const FluidElementInput& in, FluidElementSystem& out) {
  const auto& g = in.gradients;
  const double V = in.volume;
  const double rho = in.density;
  const double sigma = rho * in.alpha0 / in.dt;   // rho alpha0 / dt [kg/(m^3 s)]
  const double rho_over_dt = rho / in.dt;

  const Eigen::Vector3d a_mean = in.advecting.colwise().mean().transpose();
  const FluidStabilization stab = fluid_stabilization(in.h, a_mean, rho, in.viscosity, in.dt);
  const double tau = stab.tau_momentum;

  // Element-constant quantities.
  const Eigen::Vector4d a_grad = g * a_mean;                    // a_e . grad N_a
  double div_a = 0.0;
  for (int a = 0; a < 4; ++a) div_a += in.advecting.row(a).dot(g.row(a));
  const Eigen::Matrix4d grad_dot = V * g * g.transpose();      // V grad N_a . grad N_b
  // Sum_c M_ac a_c = V/20 (sum_c a_c + a_a): advecting velocity weighted by the P1 mass matrix.
  const Eigen::Vector3d a_sum = in.advecting.colwise().sum().transpose();
  Eigen::Matrix4d convection;                                   // int N_a a.grad N_b
  for (int a = 0; a < 4; ++a) {
    const Eigen::Vector3d weighted = V / 20.0 * (a_sum + in.advecting.row(a).transpose());
    for (int b = 0; b < 4; ++b) convection(a, b) = weighted.dot(g.row(b));
  }
  // Strong residual's known part at the (constant-weight) centroid: f + rho/dt u_hist.
  const Eigen::Vector3d source_mean =
      (in.body_force.colwise().mean() + rho_over_dt * in.history.colwise().mean()).transpose();

  out.matrix.setZero();
  out.rhs.setZero();
  for (int a = 0; a < 4; ++a) {
    const int ra = 4 * a;
    for (int b = 0; b < 4; ++b) {
      const int cb = 4 * b;
      const double mass = V / 20.0 * (a == b ? 2.0 : 1.0);
      // R_M's velocity operator applied to N_b, integrated against a constant weight.
      const double residual_u = sigma * V / 4.0 + rho * V * a_grad[b];
      const double diag = sigma * mass + rho * (convection(a, b) + 0.5 * div_a * mass) +
                          in.viscosity * grad_dot(a, b) + tau * a_grad[a] * residual_u;  // SUPG
      for (int i = 0; i < 3; ++i) {
        out.matrix(ra + i, cb + i) += diag;
        for (int j = 0; j < 3; ++j)  // LSIC grad-div
          out.matrix(ra + i, cb + j) += rho * stab.tau_continuity * V * g(a, i) * g(b, j);
        // pressure: -(div w, p) Galerkin + SUPG (tau a.grad w, grad p)
        out.matrix(ra + i, cb + 3) += -V / 4.0 * g(a, i) + tau * V * a_grad[a] * g(b, i);
        // continuity: (q, div u) Galerkin + PSPG (tau/rho grad q, R_M(u))
        out.matrix(ra + 3, cb + i) += V / 4.0 * g(b, i) + tau / rho * g(a, i) * residual_u;
      }
      out.matrix(ra + 3, cb + 3) += tau / rho * grad_dot(a, b);  // PSPG (tau/rho grad q, grad p)
      for (int i = 0; i < 3; ++i)
        out.rhs[ra + i] += mass * (in.body_force(b, i) + rho_over_dt * in.history(b, i));
    }
    for (int i = 0; i < 3; ++i) out.rhs[ra + i] += tau * V * a_grad[a] * source_mean[i];  // SUPG
    out.rhs[ra + 3] += tau / rho * V * g.row(a).dot(source_mean);                         // PSPG
  }
}

}  // namespace fdem
