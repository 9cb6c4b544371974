#pragma once
// The element system of the stabilized P1/P1 Navier-Stokes equations on one
// linear tetrahedron (paper Sect. 2.2, Eq. 21-22; EdgeCFD's SUPG/PSPG form).
//
// Local unknowns: 4*a + c for node a = 0..3, component c = 0,1,2 (velocity),
// 3 (pressure). With BDF coefficients alpha_k (du/dt ~ (alpha0 u + sum_k alpha_k
// u^{n+1-k}) / dt), the linearized (Picard: advecting velocity a = the last
// iterate) element equations are
//
//   momentum   (w, rho alpha0/dt u + rho a.grad u + rho/2 (div a) u) + (grad w, mu grad u)
//              - (div w, p) + (div w, rho tau_C div u)
//              + sum_e (tau_M a_e.grad w, R_M)                                   [SUPG]
//            = (w, f + rho/dt u_hist)
//   continuity (q, div u) + sum_e (tau_M/rho grad q, R_M) = 0                     [PSPG]
//
//   R_M = rho alpha0/dt u + rho a_e.grad u + grad p - f - rho/dt u_hist  (strong residual;
//         mu lap u vanishes on P1), u_hist = -(alpha1 u^n + alpha2 u^{n-1}).
//
// The Laplacian viscous form makes the natural boundary condition
// mu du/dn - p n = 0: exact for parallel outflow (do-nothing outlet), and equal
// to zero tangential stress on a flat free-slip wall where u.n = 0. The
// (div a) term is Temam's skew-symmetrization: it keeps the discrete
// convection energy-neutral although div a is only weakly zero.
//
// Stabilization parameters (Tezduyar 1992 / Shakib 1991 form, element-constant,
// evaluated with the element-mean advecting velocity a_e):
//   tau_M = ((2/dt)^2 + (2|a_e|/h)^2 + (4 nu/h^2)^2)^(-1/2)          [s]
//   tau_C = h^2 / (12 tau_M)                                          [m^2/s]
//   h: the element length, given by the caller. The solver passes the cube root
//   of the box cell's volume for all 5 tetrahedra of a cell: one tau per cell
//   keeps sum_e tau_e int grad N_a = 0 at interior nodes, so PSPG adds no
//   spurious mass source at interior nodes where R_M is a constant (the
//   dropped mu lap u of P1); element-wise h would make the corner and central
//   tetrahedra's tau differ by 2^(2/3).
// tau_C (Whiting & Jansen 2001 form, 1/(tau_M tr G) with tr G ~ 12/h^2) tends to
// nu/3 in the Stokes limit, h|a|/6 in the advective limit and h^2/(6 dt) for
// small steps, where the grad-div term is what keeps div u small: measured on a
// body-force blob, ||div u|| / ||grad u|| fell from 0.40 to 0.27 in the first
// step against tau_C without the 2/dt part.
//
// Galerkin terms are integrated exactly (P1 mass matrix V(1+delta_ab)/20);
// the stabilization terms are exact as well because their weights are
// element-constant. A steady solve is a step with dt -> infinity.
//
// Volume-averaged equations (paper Eq. 18-19; Zhou, Kuang, Chu & Yu 2010,
// J. Fluid Mech. 661, sets II = model A and I = model B). eps is a P1 field
// (nodal values, element mean e = sum eps_a / 4, gradient grad eps constant),
// r = d(eps)/dt its BDF rate (nodal; 0 when the switch is off), s the stress
// weight: s = eps for model A, s = 1 for model B. In non-conservative form
// (the conservative rho d(eps u)/dt + rho div(eps u u) minus rho u times the
// continuity equation):
//
//   rho eps (du/dt + u.grad u) = -s grad p + div(s mu grad u) + f - beta (u - v)     (Eq. 19)
//   r + div(eps u) = 0                                                                (Eq. 18)
//
// Weak form assembled (beta, v: the momentum exchange, constant per element):
//
//   momentum   (w, rho e alpha0/dt u + rho e a.grad u + rho/2 (div(eps a) + r) u)
//              + (grad w, s mu grad u) - (div(s w), p) + beta V/4 sum_a w_a.u_a [lumped]
//              + (s div w, rho tau_C R_C) + sum_e (tau_M a_e.grad w, R_M)              [LSIC, SUPG]
//            = (w, f + rho e/dt u_hist) + (w, beta v)
//   continuity (q, eps div u + u.grad eps) + sum_e (tau_M/rho grad q, R_M) = -(q, r)  [PSPG]
//
//   R_M = rho e (alpha0/dt u + a_e.grad u - u_hist/dt) + s grad p + beta (u - v) - f
//   R_C = e div u + u.grad eps + r
//   tau_M = ((2/dt)^2 + (2|a_e|/h)^2 + (4 nu/h^2)^2 + (beta/(rho e))^2)^(-1/2)
//
// -(div(s w), p) = -(s div w, p) - (w.grad s, p) is the integrated form of
// (w, s grad p): its natural boundary condition s (mu du/dn - p n) = 0 is the
// do-nothing outlet of the simplified model, and it is exactly minus the
// transpose of the continuity's (q, div(eps u)) in model A (the saddle point
// keeps its structure). Why the stabilization has the simplified model's form:
// the subscale velocity of the eps-weighted momentum equation is u' = -tau_M
// R_M / (rho e); SUPG (rho e a.grad w, -u') and PSPG -(grad q, eps u') then
// read (tau_M a.grad w, R_M) and (tau_M/rho grad q, R_M), the eps cancelling;
// the reaction beta/(rho e) enters tau_M as a rate like 2/dt (Codina 2001), so
// a dense bed (beta/rho ~ 1e3-1e4 1/s) does not get SUPG/PSPG weights sized
// for a free fluid. eps is element-mean (e) in the time, convection and
// viscous terms (the midpoint rule: O(h^2) like the rest) and exact in the
// pressure-continuity pair, where its gradient carries the physics (the fluid
// speeding up into a bed). The viscous term is the paper's Laplacian form
// (Eq. 19), not the full deviatoric div(eps tau); R_M drops
// div(s mu grad u), which on P1 is mu grad u grad s (model A) and 0 (model B).
// The simplified model (Eq. 21-22) is eps = 1, r = 0, s = 1; without an
// exchange it runs the kernel as written before these terms (bitwise the
// same results: the general kernel agrees to round-off only, its longer
// expressions being contracted to FMAs differently).
#include <Eigen/Core>

namespace fdem {

struct FluidElementInput {
  Eigen::Matrix<double, 4, 3> gradients;    // row a = grad N_a [1/m]
  double volume = 0.0;                      // [m^3]
  double h = 0.0;                           // element length for tau [m]
  Eigen::Matrix<double, 4, 3> advecting;    // Picard advecting velocity at the nodes [m/s]
  Eigen::Matrix<double, 4, 3> history;      // u_hist at the nodes [m/s] (see above)
  Eigen::Matrix<double, 4, 3> body_force;   // f at the nodes [N/m^3]
  double density = 0.0;                     // rho [kg/m^3]
  double viscosity = 0.0;                   // mu [Pa s]
  double dt = 0.0;                          // [s]
  double alpha0 = 1.0;                      // BDF leading coefficient (1 BDF1, 3/2 BDF2)
  // Volume-averaged equations (see above); the defaults are the simplified model.
  bool volume_averaged = false;                              // vans_a / vans_b (else eps, r unused)
  Eigen::Vector4d porosity = Eigen::Vector4d::Ones();        // eps at the nodes, new time level
  Eigen::Vector4d porosity_rate = Eigen::Vector4d::Zero();   // r = d(eps)/dt at the nodes [1/s]
  bool porosity_weighted_stress = false;                     // model A: s = eps; else s = 1
  double exchange_coefficient = 0.0;                         // beta [kg/(m^3 s)]
  Eigen::Vector3d exchange_velocity = Eigen::Vector3d::Zero();  // v, mean grain velocity [m/s]
};

struct FluidStabilization {
  double tau_momentum = 0.0;    // tau_M [s]
  double tau_continuity = 0.0;  // tau_C [m^2/s]
  double h = 0.0;               // element size [m]
};

/// reaction_rate: beta / (rho e) [1/s] of a momentum exchange (0: none).
FluidStabilization fluid_stabilization(double h, const Eigen::Vector3d& mean_velocity, double density,
                                       double viscosity, double dt, double reaction_rate = 0.0);

struct FluidElementSystem {
  // Row-major: the solver scatters it row by row into its CSR rows, and a
  // node's 4 columns are then 4 contiguous doubles (the kernels fill it in
  // the same order).
  Eigen::Matrix<double, 16, 16, Eigen::RowMajor> matrix;
  Eigen::Matrix<double, 16, 1> rhs;
};

/// Fills `out` (no allocation: called once per element per Picard iteration).
void fluid_element_system(const FluidElementInput& in, FluidElementSystem& out);

}  // namespace fdem
