// Cost of one fluid step with the volume-averaged equations (fluid.model
// vans_a, vans_b; paper Eq. 18-19) against the paper's simplified model
// (Eq. 21-22), on the same mesh and bed in the same run. The case is a
// packed bed in a duct (verification/packed_bed): inlet at z_min, outlet at
// z_max, free-slip sides; porosity 0.45 in the middle half of the duct and 1
// elsewhere; the bed's drag through the semi-implicit exchange
// (FluidSolver::set_momentum_exchange) with Ergun's beta at the bed's
// porosity (grains at rest), identical for every model (the simplified
// model and model B receive beta / eps, as the coupling passes them). So the
// models differ only in the equations: eps in the mass and momentum terms,
// div(eps u) in continuity and the eps-weighted stabilization.
// Counters: elements, picard_per_step, krylov_per_step; compare the models'
// times within one run (interleaved repetitions), never across runs:
//   bench_fluid_model --benchmark_repetitions=5 --benchmark_enable_random_interleaving=true
#include <benchmark/benchmark.h>
#include <omp.h>

#include <vector>

#include "fluid/fluid_solver.hpp"

namespace {

using namespace fdem;

constexpr double kGrain_m = 1e-3, kBedPorosity = 0.45, kSuperficial_m_s = 3e-3;  // Re_p 3

Scene duct(FluidModel model) {
  Scene scene;
  scene.fluid.model = model;
  scene.fluid.linear_tolerance = 1e-8;
  using FC = FaceCondition;
  auto& f = scene.fluid.faces;
  for (int a = 0; a < 4; ++a) f[static_cast<std::size_t>(a)].condition = FC::free_slip;
  f[4].condition = FC::inlet;
  f[4].velocity = Vec3(0, 0, kSuperficial_m_s);
  f[5].condition = FC::outlet;
  return scene;
}

void BM_FluidStepModel(benchmark::State& state) {
  omp_set_num_threads(1);
  const auto model = static_cast<FluidModel>(state.range(0));
  state.SetLabel(model == FluidModel::simplified ? "simplified" : model == FluidModel::vans_a ? "vans_a" : "vans_b");
  const int n = 12;
  const BoxMesh mesh(Vec3::Zero(), Vec3(0.012, 0.012, 0.048), {n, n, 4 * n});  // 1 mm cells, 34560 tetrahedra
  FluidSolver solver(mesh, duct(model));
  const auto ne = static_cast<std::size_t>(mesh.num_elements());
  std::vector<double> eps(ne, 1.0), beta(ne, 0.0), grain_velocity(3 * ne, 0.0);
  // Ergun's beta (paper Eq. 12, eps < 0.8 branch) at the bed's porosity and the interstitial slip U / eps.
  const double mu = 1e-3, rho = 1000.0, e = kBedPorosity, slip = kSuperficial_m_s / e;
  const double ergun_beta = 150.0 * (1 - e) * (1 - e) * mu / (e * kGrain_m * kGrain_m) +
                            1.75 * (1 - e) * rho * slip / kGrain_m;
  for (std::size_t k = 0; k < ne; ++k) {
    const double z = mesh.element_centroid(static_cast<Index>(k)).z();
    if (z > 0.012 && z < 0.036) {
      eps[k] = e;
      beta[k] = model == FluidModel::vans_a ? ergun_beta : ergun_beta / e;
    }
  }
  solver.set_porosity(eps);
  solver.set_momentum_exchange(beta, grain_velocity);
  const double dt = 1e-3;
  solver.step(dt);  // warm-up: preconditioner built, BDF2 history in place
  solver.step(dt);
  double picard = 0, krylov = 0, steps = 0;
  for (auto _ : state) {
    const FluidStepReport r = solver.step(dt);
    picard += r.picard_iterations;
    krylov += r.linear_iterations;
    steps += 1;
  }
  state.counters["elements"] = static_cast<double>(ne);
  state.counters["picard_per_step"] = picard / steps;
  state.counters["krylov_per_step"] = krylov / steps;
}
BENCHMARK(BM_FluidStepModel)
    ->Arg(static_cast<int>(FluidModel::simplified))
    ->Arg(static_cast<int>(FluidModel::vans_a))
    ->Arg(static_cast<int>(FluidModel::vans_b))
    ->Unit(benchmark::kMillisecond)
    ->MinTime(2.0);

}  // namespace

BENCHMARK_MAIN();
