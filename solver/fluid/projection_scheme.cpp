// GCC 12's false -Wmaybe-uninitialized inside Eigen's AVX-512 code: see fluid_solver.cpp.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#include "fluid/projection_scheme.hpp"

#include <Eigen/IterativeLinearSolvers>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <fmt/format.h>

#include "core/error.hpp"
#include "fluid/fluid_element.hpp"
#include "mesh/layer_colouring.hpp"

namespace fdem {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

}  // namespace

ProjectionScheme::ProjectionScheme(const BoxMesh& mesh, const FluidSpec& spec, const FluidConstraints& constraints)
    : mesh_(mesh),
      density_(spec.density),
      viscosity_(spec.viscosity),
      h_(std::cbrt(mesh.cell_size().prod())),  // one tau per cell, as the monolithic scheme (fluid_element.hpp)
      num_nodes_(mesh.num_nodes()),
      velocity_fixed_(constraints.velocity_fixed),
      pressure_node_(constraints.pressure_node) {
  const auto n = static_cast<std::size_t>(num_nodes_);
  // Components with equal prescribed sets (every component on no-slip and
  // inlet faces) solve with one matrix.
  for (int d = 1; d < 3; ++d) {
    matrix_of_[static_cast<std::size_t>(d)] = d;
    for (int c = 0; c < d; ++c) {
      bool same = true;
      for (std::size_t node = 0; node < n && same; ++node)
        same = velocity_fixed_[3 * node + static_cast<std::size_t>(d)] == velocity_fixed_[3 * node + static_cast<std::size_t>(c)];
      if (same) {
        matrix_of_[static_cast<std::size_t>(d)] = matrix_of_[static_cast<std::size_t>(c)];
        break;
      }
    }
  }

  // The scalar P1 pattern: node a couples to every node of its elements.
  std::vector<std::vector<int>> neighbours(n);
  for (Index e = 0; e < mesh.num_elements(); ++e)
    for (Index a : mesh.element_nodes(e))
      for (Index b : mesh.element_nodes(e)) neighbours[static_cast<std::size_t>(a)].push_back(static_cast<int>(b));
  std::vector<Eigen::Triplet<double, int>> pattern;
  for (std::size_t a = 0; a < n; ++a) {
    auto& list = neighbours[a];
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
    for (int b : list) pattern.emplace_back(static_cast<int>(a), b, 0.0);
  }
  predictor_.resize(num_nodes_, num_nodes_);
  predictor_.setFromTriplets(pattern.begin(), pattern.end());
  predictor_.makeCompressed();
  const int* outer = predictor_.outerIndexPtr();
  const int* inner = predictor_.innerIndexPtr();
  entry_.resize(static_cast<std::size_t>(mesh.num_elements()));
  for (Index e = 0; e < mesh.num_elements(); ++e) {
    const auto& nodes = mesh.element_nodes(e);
    for (std::size_t a = 0; a < 4; ++a)
      for (std::size_t b = 0; b < 4; ++b) {
        const int row = static_cast<int>(nodes[a]);
        const int* at = std::lower_bound(inner + outer[row], inner + outer[row + 1], static_cast<int>(nodes[b]));
        entry_[static_cast<std::size_t>(e)][4 * a + b] = static_cast<int>(at - inner);
      }
  }

  node_volume_.assign(n, 0.0);
  for (Index e = 0; e < mesh.num_elements(); ++e)
    for (Index a : mesh.element_nodes(e)) node_volume_[static_cast<std::size_t>(a)] += mesh.element_volume(e) / 4.0;

  // phi = 0 on outlet nodes (the do-nothing outlet's p n = mu du/dn ~ 0), or
  // at the pinned node of a closed domain (only grad phi is defined there;
  // the compatible right-hand side makes the pinned solution the null-space one).
  phi_fixed_.assign(n, 0);
  for (int f = 0; f < box_face_count; ++f)
    if (spec.faces[static_cast<std::size_t>(f)].condition == FaceCondition::outlet)
      for (Index node : mesh.face_nodes(static_cast<BoxFace>(f))) phi_fixed_[static_cast<std::size_t>(node)] = 1;
  if (pressure_node_ >= 0) phi_fixed_[static_cast<std::size_t>(pressure_node_)] = 1;

  // The P1 Laplacian (grad N_a, grad N_b), fixed nodes eliminated
  // symmetrically (their rows and columns an identity): SPD.
  std::vector<Eigen::Triplet<double, int>> laplacian;
  laplacian.reserve(16 * static_cast<std::size_t>(mesh.num_elements()) + n);
  for (Index e = 0; e < mesh.num_elements(); ++e) {
    const auto& g = mesh.shape_gradients(e);
    const double V = mesh.element_volume(e);
    const auto& nodes = mesh.element_nodes(e);
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) {
        const auto na = static_cast<std::size_t>(nodes[static_cast<std::size_t>(a)]);
        const auto nb = static_cast<std::size_t>(nodes[static_cast<std::size_t>(b)]);
        if (!phi_fixed_[na] && !phi_fixed_[nb])
          laplacian.emplace_back(static_cast<int>(na), static_cast<int>(nb), V * g.row(a).dot(g.row(b)));
      }
  }
  for (std::size_t a = 0; a < n; ++a)
    if (phi_fixed_[a]) laplacian.emplace_back(static_cast<int>(a), static_cast<int>(a), 1.0);
  Eigen::SparseMatrix<double> poisson_matrix(num_nodes_, num_nodes_);
  poisson_matrix.setFromTriplets(laplacian.begin(), laplacian.end());
  poisson_.compute(poisson_matrix);
  if (poisson_.info() != Eigen::Success)
    throw SolverError("fluid (projection scheme): the pressure Laplacian's Cholesky factorization failed");
  for (auto& r : rhs_) r.resize(num_nodes_);
}

// The predictor's scalar matrix and the three components' right-hand sides.
void ProjectionScheme::assemble(const ProjectionStepInput& in, std::span<const double> pressure) {
  double* values = predictor_.valuePtr();
  std::fill_n(values, predictor_.nonZeros(), 0.0);
  for (auto& r : rhs_) r.setZero();
  const double rho = density_, mu = viscosity_;
  const double sigma = rho * in.alpha0 / in.dt;
  const bool exchange = !in.exchange_beta.empty();
  for_each_element_by_layer_colour(mesh_, layer_colours_worth_threads(mesh_), [&](Index e) {
    const auto& g = mesh_.shape_gradients(e);
    const double V = mesh_.element_volume(e);
    const auto& nodes = mesh_.element_nodes(e);
    Eigen::Matrix<double, 4, 3> a_nodes, source;  // u*, and f + rho/dt u_hist, at the nodes
    for (int a = 0; a < 4; ++a) {
      const auto s = 3 * static_cast<std::size_t>(nodes[static_cast<std::size_t>(a)]);
      for (int d = 0; d < 3; ++d) {
        const auto i = s + static_cast<std::size_t>(d);
        a_nodes(a, d) = in.advecting[i];
        source(a, d) = in.body_force[i] + rho / in.dt * in.history[i];
      }
    }
    const Eigen::Vector3d a_mean = a_nodes.colwise().mean().transpose();
    const Eigen::Vector3d a_sum = 4.0 * a_mean;
    const double beta = exchange ? in.exchange_beta[static_cast<std::size_t>(e)] : 0.0;
    const double tau = fluid_stabilization(h_, a_mean, rho, mu, in.dt, beta / rho).tau_momentum;
    const Eigen::Vector4d a_grad = g * a_mean;  // a_e . grad N_a
    double div_a = 0.0;
    for (int a = 0; a < 4; ++a) div_a += a_nodes.row(a).dot(g.row(a));
    Eigen::Vector3d grad_p = Eigen::Vector3d::Zero();  // of p^n, element-constant
    for (std::size_t a = 0; a < 4; ++a)
      grad_p += pressure[static_cast<std::size_t>(nodes[a])] * g.row(static_cast<Eigen::Index>(a)).transpose();
    // Element-constant part of the strong residual's known terms: the mean
    // source, -grad p^n, beta v (the SUPG weights are element-constant).
    const Eigen::Vector3d source_mean = source.colwise().mean().transpose();
    Eigen::Vector3d exchange_force = Eigen::Vector3d::Zero();
    if (exchange) {
      const auto s = 3 * static_cast<std::size_t>(e);
      exchange_force = beta * Eigen::Vector3d(in.exchange_velocity[s], in.exchange_velocity[s + 1], in.exchange_velocity[s + 2]);
    }
    const double mass_diag = V / 10.0, mass_off = V / 20.0;  // P1 mass matrix V (1 + delta_ab) / 20
    const auto& at = entry_[static_cast<std::size_t>(e)];
    for (int a = 0; a < 4; ++a) {
      const Eigen::Vector3d weighted = V / 20.0 * (a_sum + a_nodes.row(a).transpose());  // sum_c M_ac u*_c
      const double supg = tau * a_grad[a];
      for (int b = 0; b < 4; ++b) {
        const double mass = a == b ? mass_diag : mass_off;
        double v = (sigma + 0.5 * rho * div_a) * mass + rho * weighted.dot(g.row(b)) +
                   mu * V * g.row(a).dot(g.row(b)) + supg * (sigma * V / 4.0 + rho * V * a_grad[b] + beta * V / 4.0);
        if (a == b) v += beta * V / 4.0;  // lumped exchange
        values[at[static_cast<std::size_t>(4 * a + b)]] += v;
      }
      const auto row = static_cast<Eigen::Index>(nodes[static_cast<std::size_t>(a)]);
      for (int d = 0; d < 3; ++d) {
        // (N_a, source) exactly with the P1 mass matrix, (N_a, beta v - grad p^n) with int N_a = V / 4.
        const double galerkin = mass_off * (source.col(d).sum() + source(a, d)) + V / 4.0 * (exchange_force[d] - grad_p[d]);
        rhs_[static_cast<std::size_t>(d)][row] += galerkin + supg * V * (source_mean[d] + exchange_force[d] - grad_p[d]);
      }
    }
  });
}

ProjectionStepResult ProjectionScheme::step(const ProjectionStepInput& in, int step_number, std::span<double> velocity,
                                            std::span<double> pressure) {
  ProjectionStepResult result;
  const auto n = static_cast<std::size_t>(num_nodes_);
  auto t0 = Clock::now();
  assemble(in, pressure);
  // Prescribed components: identity rows holding their values.
  for (int m = 0; m < 3; ++m) {
    int d = -1;
    for (int c = 0; c < 3 && d < 0; ++c)
      if (matrix_of_[static_cast<std::size_t>(c)] == m) d = c;
    if (d < 0) continue;
    RowMatrix& A = constrained_[static_cast<std::size_t>(m)];
    A = predictor_;
    double* values = A.valuePtr();
    const int* outer = A.outerIndexPtr();
    const int* inner = A.innerIndexPtr();
    for (std::size_t node = 0; node < n; ++node)
      if (velocity_fixed_[3 * node + static_cast<std::size_t>(d)])
        for (int k = outer[node]; k < outer[node + 1]; ++k) values[k] = inner[k] == static_cast<int>(node) ? 1.0 : 0.0;
  }
  for (std::size_t node = 0; node < n; ++node)
    for (std::size_t d = 0; d < 3; ++d)
      if (velocity_fixed_[3 * node + d]) rhs_[d][static_cast<Eigen::Index>(node)] = in.prescribed[4 * node + d];
  result.assembly_seconds = seconds_since(t0);

  // 1. Predictor: BiCGSTAB with a Jacobi preconditioner, from u* (at
  //    dt = 0.01 s the matrix is a mass matrix plus ~1e-3 of viscous and
  //    convective terms: a few iterations). The three components' solves
  //    are independent, so they run on threads at once, each one whole on
  //    one thread (Eigen's threaded product inside is then a nested region,
  //    one thread by OpenMP's default; each row's sum is the same on any
  //    number): the same iterates on any thread count. Failures are
  //    reported after the loop, in component order.
  t0 = Clock::now();
  Eigen::VectorXd predicted[3];
  std::array<int, 3> iterations{};
  std::array<double, 3> residual{};
  std::array<bool, 3> failed{};
#pragma omp parallel for schedule(static, 1) if (layer_colours_worth_threads(mesh_))
  for (int d = 0; d < 3; ++d) {
    const auto c = static_cast<std::size_t>(d);
    const auto& b = rhs_[c];
    if (b.squaredNorm() == 0.0) {
      predicted[d] = Eigen::VectorXd::Zero(num_nodes_);
      continue;
    }
    Eigen::BiCGSTAB<RowMatrix, Eigen::DiagonalPreconditioner<double>> krylov;
    krylov.setTolerance(in.linear_tolerance);
    krylov.setMaxIterations(in.max_linear_iterations);
    krylov.compute(constrained_[static_cast<std::size_t>(matrix_of_[c])]);
    Eigen::VectorXd guess(num_nodes_);
    for (std::size_t node = 0; node < n; ++node)
      guess[static_cast<Eigen::Index>(node)] =
          velocity_fixed_[3 * node + c] ? in.prescribed[4 * node + c] : in.advecting[3 * node + c];
    predicted[d] = krylov.solveWithGuess(b, guess);
    iterations[c] = static_cast<int>(krylov.iterations());
    residual[c] = krylov.error();
    failed[c] = krylov.info() != Eigen::Success;
  }
  for (std::size_t c = 0; c < 3; ++c) {
    result.predictor_iterations += iterations[c];
    result.predictor_residual = std::max(result.predictor_residual, residual[c]);
    if (failed[c] || !predicted[c].allFinite())
      throw SolverError(fmt::format(
          "fluid step {} (projection scheme): the velocity predictor's component {} did not converge in {} "
          "BiCGSTAB iterations (relative residual {:.3e}, tolerance {:.1e}, max_linear_iterations {})",
          step_number, c, iterations[c], residual[c], in.linear_tolerance, in.max_linear_iterations));
  }

  // 2. Projection: (grad q, grad phi) = -(rho alpha0 / dt) (q, div u~).
  const double correction = in.dt / (density_ * in.alpha0);
  Eigen::VectorXd poisson_rhs = Eigen::VectorXd::Zero(num_nodes_);
  std::vector<double> divergence(n, 0.0);  // sum_e V_e / 4 div u~_e at the node
  for_each_element_by_layer_colour(mesh_, layer_colours_worth_threads(mesh_), [&](Index e) {
    const auto& g = mesh_.shape_gradients(e);
    const double V = mesh_.element_volume(e);
    const auto& nodes = mesh_.element_nodes(e);
    double div = 0.0;
    for (std::size_t a = 0; a < 4; ++a)
      for (int d = 0; d < 3; ++d) div += predicted[d][static_cast<Eigen::Index>(nodes[a])] * g(static_cast<Eigen::Index>(a), d);
    for (std::size_t a = 0; a < 4; ++a) divergence[static_cast<std::size_t>(nodes[a])] += V / 4.0 * div;
  });
  for (std::size_t node = 0; node < n; ++node)
    if (!phi_fixed_[node]) poisson_rhs[static_cast<Eigen::Index>(node)] = -divergence[node] / correction;
  const Eigen::VectorXd phi = poisson_.solve(poisson_rhs);

  // 3. Correction: nodal grad phi by the lumped L2 projection.
  std::vector<double> grad_phi(3 * n, 0.0);
  for_each_element_by_layer_colour(mesh_, layer_colours_worth_threads(mesh_), [&](Index e) {
    const auto& g = mesh_.shape_gradients(e);
    const double V = mesh_.element_volume(e);
    const auto& nodes = mesh_.element_nodes(e);
    Eigen::Vector3d grad = Eigen::Vector3d::Zero();
    for (std::size_t a = 0; a < 4; ++a)
      grad += phi[static_cast<Eigen::Index>(nodes[a])] * g.row(static_cast<Eigen::Index>(a)).transpose();
    for (std::size_t a = 0; a < 4; ++a)
      for (int d = 0; d < 3; ++d) grad_phi[3 * static_cast<std::size_t>(nodes[a]) + static_cast<std::size_t>(d)] += V / 4.0 * grad[d];
  });
  for (std::size_t node = 0; node < n; ++node) {
    for (std::size_t d = 0; d < 3; ++d) {
      const double u = predicted[d][static_cast<Eigen::Index>(node)];
      velocity[3 * node + d] = velocity_fixed_[3 * node + d] ? u : u - correction * grad_phi[3 * node + d] / node_volume_[node];
    }
    // The rotational term -mu div u~ (Timmermans et al.): not on outlet
    // nodes, whose p n = mu du/dn is the do-nothing condition's.
    const bool outlet = phi_fixed_[node] && static_cast<Index>(node) != pressure_node_;
    pressure[node] += phi[static_cast<Eigen::Index>(node)] - (outlet ? 0.0 : viscosity_ * divergence[node] / node_volume_[node]);
  }
  if (pressure_node_ >= 0) {
    const double level = pressure[static_cast<std::size_t>(pressure_node_)];
    for (double& p : pressure) p -= level;
  }
  for (double u : velocity)
    if (!std::isfinite(u))
      throw SolverError(fmt::format("fluid step {} (projection scheme): non-finite velocity", step_number));
  result.solve_seconds = seconds_since(t0);
  return result;
}

}  // namespace fdem
