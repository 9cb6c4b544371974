#include "fluid/fluid_element.hpp"

#include <cmath>


namespace fdem {

FluidStabilization fluid_stabilization(double h, const Eigen::Vector3d& mean_velocity, double density,
                                       double viscosity, double dt, double reaction_rate) {
  FluidStabilization s;
  s.h = h;
  const double nu = viscosity / density;
  const double advective = 2.0 * mean_velocity.norm() / s.h;
  const double diffusive = 4.0 * nu / (s.h * s.h);
  const double transient = 2.0 / dt;  // 0 for a steady solve (dt = inf)
  s.tau_momentum = 1.0 / std::sqrt(transient * transient + advective * advective + diffusive * diffusive +
                                   reaction_rate * reaction_rate);
  s.tau_continuity = s.h * s.h / (12.0 * s.tau_momentum);  // Whiting & Jansen, tr G ~ 12 / h^2
  return s;
}

namespace {

// The simplified model's kernel (Eq. 21-22), kept as it was written before the
// volume-averaged terms: the general kernel below reduces to it for eps = 1,
// beta = 0 in exact arithmetic, but the compiler's FMA contraction rounds its
// longer expressions differently (measured: 1e-15 relative drift), and the
// paper's studies keep their results bit for bit.
void simplified_element_system(const FluidElementInput& in, FluidElementSystem& out) {
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

  // Every matrix entry is written once (no clearing pass): the diagonal
  // velocity entries as diag + LSIC, the sum the former clear-then-add order
  // formed (0 + diag, then + LSIC: the same rounding).
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
        for (int j = 0; j < 3; ++j)  // LSIC grad-div, over the diagonal's value
          out.matrix(ra + i, cb + j) = (i == j ? diag : 0.0) + rho * stab.tau_continuity * V * g(a, i) * g(b, j);
        // pressure: -(div w, p) Galerkin + SUPG (tau a.grad w, grad p)
        out.matrix(ra + i, cb + 3) = -V / 4.0 * g(a, i) + tau * V * a_grad[a] * g(b, i);
        // continuity: (q, div u) Galerkin + PSPG (tau/rho grad q, R_M(u))
        out.matrix(ra + 3, cb + i) = V / 4.0 * g(b, i) + tau / rho * g(a, i) * residual_u;
      }
      out.matrix(ra + 3, cb + 3) = tau / rho * grad_dot(a, b);  // PSPG (tau/rho grad q, grad p)
      for (int i = 0; i < 3; ++i)
        out.rhs[ra + i] += mass * (in.body_force(b, i) + rho_over_dt * in.history(b, i));
    }
    for (int i = 0; i < 3; ++i) out.rhs[ra + i] += tau * V * a_grad[a] * source_mean[i];  // SUPG
    out.rhs[ra + 3] += tau / rho * V * g.row(a).dot(source_mean);                         // PSPG
  }
}

// The weak form is written out in fluid_element.hpp.
void volume_averaged_element_system(const FluidElementInput& in, FluidElementSystem& out) {
  const auto& g = in.gradients;
  const double V = in.volume;
  const double rho = in.density;
  const double beta = in.exchange_coefficient;

  // Porosity: element mean e, constant gradient (from differences to the
  // mean, so that a uniform field has an exactly zero gradient), mean rate.
  const double eps_mean = in.porosity.mean();
  const Eigen::Vector3d grad_eps = g.transpose() * (in.porosity - Eigen::Vector4d::Constant(eps_mean));
  const double rate_mean = in.porosity_rate.mean();
  const bool stress_weighted = in.porosity_weighted_stress;
  const double s_mean = stress_weighted ? eps_mean : 1.0;
  const Eigen::Vector3d grad_s = stress_weighted ? grad_eps : Eigen::Vector3d::Zero();
  // int N_a eps = V/4 (eps_a + sum eps) / 5 (exact: V/20 (1 + delta_ab) against eps_b).
  const double eps_sum = in.porosity.sum();
  Eigen::Vector4d eps_moment, s_moment;
  for (int a = 0; a < 4; ++a) {
    eps_moment[a] = V / 4.0 * ((in.porosity[a] + eps_sum) / 5.0);
    s_moment[a] = stress_weighted ? eps_moment[a] : V / 4.0;
  }

  const double sigma = rho * in.alpha0 / in.dt * eps_mean;  // rho e alpha0 / dt [kg/(m^3 s)]
  const double rho_over_dt = rho / in.dt * eps_mean;         // rho e / dt
  const double rho_eps = rho * eps_mean;

  const Eigen::Vector3d a_mean = in.advecting.colwise().mean().transpose();
  const FluidStabilization stab =
      fluid_stabilization(in.h, a_mean, rho, in.viscosity, in.dt, beta / (rho * eps_mean));
  const double tau = stab.tau_momentum;

  // Element-constant quantities.
  const Eigen::Vector4d a_grad = g * a_mean;                    // a_e . grad N_a
  double div_a = 0.0;
  for (int a = 0; a < 4; ++a) div_a += in.advecting.row(a).dot(g.row(a));
  // div(eps a) + r (the continuity residual of the advecting velocity): Temam's term.
  const double div_eps_a = eps_mean * div_a + a_mean.dot(grad_eps) + rate_mean;
  const Eigen::Matrix4d grad_dot = V * g * g.transpose();      // V grad N_a . grad N_b
  // Sum_c M_ac a_c = V/20 (sum_c a_c + a_a): advecting velocity weighted by the P1 mass matrix.
  const Eigen::Vector3d a_sum = in.advecting.colwise().sum().transpose();
  Eigen::Matrix4d convection;                                   // int N_a a.grad N_b
  for (int a = 0; a < 4; ++a) {
    const Eigen::Vector3d weighted = V / 20.0 * (a_sum + in.advecting.row(a).transpose());
    for (int b = 0; b < 4; ++b) convection(a, b) = weighted.dot(g.row(b));
  }
  // Strong residual's known part at the (constant-weight) centroid: f + rho e/dt u_hist + beta v.
  const Eigen::Vector3d source_mean =
      (in.body_force.colwise().mean() + rho_over_dt * in.history.colwise().mean()).transpose() +
      beta * in.exchange_velocity;
  const double lumped = beta * V / 4.0;  // beta int N_a, the exchange's lumped mass-like weight

  out.matrix.setZero();
  out.rhs.setZero();
  for (int a = 0; a < 4; ++a) {
    const int ra = 4 * a;
    // LSIC weight (s div w, rho tau_C R_C) for w = N_a e_i: s rho tau_C V g(a, i).
    const double lsic = s_mean * rho * stab.tau_continuity * V;
    for (int b = 0; b < 4; ++b) {
      const int cb = 4 * b;
      const double mass = V / 20.0 * (a == b ? 2.0 : 1.0);
      // R_M's velocity operator applied to N_b, integrated against a constant weight.
      const double residual_u = sigma * V / 4.0 + rho_eps * V * a_grad[b] + lumped;
      const double diag = sigma * mass + rho * (eps_mean * convection(a, b) + 0.5 * div_eps_a * mass) +
                          s_mean * in.viscosity * grad_dot(a, b) + tau * a_grad[a] * residual_u +  // SUPG
                          (a == b ? lumped : 0.0);
      for (int i = 0; i < 3; ++i) {
        out.matrix(ra + i, cb + i) += diag;
        for (int j = 0; j < 3; ++j)  // LSIC grad-div: R_C(N_b e_j) integrated = V (e g(b, j) + grad eps_j / 4)
          out.matrix(ra + i, cb + j) += lsic * g(a, i) * (eps_mean * g(b, j) + grad_eps[j] / 4.0);
        // pressure: -(div(s w), p) Galerkin + SUPG (tau a.grad w, s grad p)
        out.matrix(ra + i, cb + 3) += -s_moment[b] * g(a, i) - grad_s[i] * mass + tau * s_mean * V * a_grad[a] * g(b, i);
        // continuity: (q, eps div u + u.grad eps) Galerkin + PSPG (tau/rho grad q, R_M(u))
        out.matrix(ra + 3, cb + i) += eps_moment[a] * g(b, i) + mass * grad_eps[i] + tau / rho * g(a, i) * residual_u;
      }
      out.matrix(ra + 3, cb + 3) += tau / rho * s_mean * grad_dot(a, b);  // PSPG (tau/rho grad q, s grad p)
      for (int i = 0; i < 3; ++i)
        out.rhs[ra + i] += mass * (in.body_force(b, i) + rho_over_dt * in.history(b, i));
      out.rhs[ra + 3] -= mass * in.porosity_rate[b];  // -(q, r)
    }
    for (int i = 0; i < 3; ++i)
      out.rhs[ra + i] += tau * V * a_grad[a] * source_mean[i]  // SUPG
                         - lsic * g(a, i) * rate_mean        // LSIC's known part: -(s div w, rho tau_C r)
                         + lumped * in.exchange_velocity[i];  // (w, beta v)
    out.rhs[ra + 3] += tau / rho * V * g.row(a).dot(source_mean);                         // PSPG
  }
}

}  // namespace

void fluid_element_system(const FluidElementInput& in, FluidElementSystem& out) {
  if (in.volume_averaged || in.exchange_coefficient != 0.0) {
    volume_averaged_element_system(in, out);
  } else {
    simplified_element_system(in, out);
  }
}

}  // namespace fdem
