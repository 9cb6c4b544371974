// Micro benchmarks of the coupling kernels (paper Sect. 3): particle mapping
// (Eq. 23-31), porosity (Eq. 32 and the shape-function scheme), drag in one
// DEM subcycle (Eq. 11-15) and the source term (Eq. 20, 22, Fig. 4-5).
// Each reports particles_per_s (and elements_per_s where the kernel also
// walks the elements): how many particles one second of the kernel serves.
//
// Problems: the two study meshes with the most grains,
//   plume:   100 x 100 x 250 mm, 10 mm cells (12500 tets), 28224 grains
//   channel: 12 x 1.8 x 12 mm, 0.6 mm cells (6000 tets), 4800 grains
// Grains are placed uniformly at random in the box (seeded, so every run sees
// the same set): the coupling kernels do not care about overlaps, and random
// order is the worst case for their memory access (a real run keeps the
// particles in creation order, which is partly sorted). The last argument is
// the OpenMP thread count.
#include <benchmark/benchmark.h>
#include <omp.h>

#include <array>
#include <string>
#include <cmath>
#include <random>
#include <vector>

#include "core/particles.hpp"
#include "coupling/drag.hpp"
#include "coupling/drag_coupling.hpp"
#include "coupling/particle_mapping.hpp"
#include "coupling/porosity.hpp"
#include "coupling/source_term.hpp"
#include "mesh/box_mesh.hpp"
#include "scene/particle_generator.hpp"

namespace {

using fdem::BoxMesh;
using fdem::Particles;

struct Problem {
  BoxMesh mesh;
  Particles particles;
};

// problem 0 = plume, 1 = channel (see the header comment).
Problem make_problem(int which) {
  const bool plume = which == 0;
  const fdem::Vec3 upper = plume ? fdem::Vec3(0.100, 0.100, 0.250) : fdem::Vec3(0.012, 0.0018, 0.012);
  const std::array<int, 3> cells = plume ? std::array<int, 3>{10, 10, 25} : std::array<int, 3>{20, 3, 20};
  const int count = plume ? 28224 : 4800;
  Problem pb{BoxMesh(fdem::Vec3::Zero(), upper, cells), Particles{}};
  std::mt19937_64 rng(20240601);
  for (int i = 0; i < count; ++i) {
    const double d = plume ? 309e-6 : 250e-6;
    pb.particles.add(upper.x() * fdem::uniform01(rng), upper.y() * fdem::uniform01(rng),
                     upper.z() * fdem::uniform01(rng), d, 2170.0, 0.0, 0.0, -0.01);
  }
  return pb;
}

// A smooth, nonzero fluid velocity at the nodes (3 per node, node-major), so
// drag sees a real slip velocity.
std::vector<double> fluid_velocity(const BoxMesh& mesh) {
  std::vector<double> u(3 * static_cast<std::size_t>(mesh.num_nodes()));
  for (fdem::Index n = 0; n < mesh.num_nodes(); ++n) {
    const fdem::Vec3 x = mesh.node(n);
    const auto k = 3 * static_cast<std::size_t>(n);
    u[k] = 0.01 * std::sin(40.0 * x.z());
    u[k + 1] = 0.0;
    u[k + 2] = 0.02 * std::cos(30.0 * x.x());
  }
  return u;
}

void set_counters(benchmark::State& state, std::size_t particles, fdem::Index elements) {
  const auto it = static_cast<double>(state.iterations());
  state.counters["particles_per_s"] = benchmark::Counter(it * static_cast<double>(particles), benchmark::Counter::kIsRate);
  state.counters["particles"] = static_cast<double>(particles);
  if (elements > 0) {  // kernels that also walk the elements
    state.counters["elements_per_s"] = benchmark::Counter(it * static_cast<double>(elements), benchmark::Counter::kIsRate);
    state.counters["elements"] = static_cast<double>(elements);
  }
}

// Eq. 23-31: cell by truncation, element by four volume-coordinate tests.
void BM_ParticleMapping(benchmark::State& state) {
  omp_set_num_threads(static_cast<int>(state.range(1)));
  Problem pb = make_problem(static_cast<int>(state.range(0)));
  fdem::ParticleMapping mapping;
  for (auto _ : state) {
    mapping.update(pb.mesh, pb.particles);
    benchmark::DoNotOptimize(mapping.element.data());
  }
  if (mapping.outside != 0) state.SkipWithError("particles outside the mesh");
  set_counters(state, pb.particles.size(), 0);
}

// BoxMesh::locate_element alone, one thread: the four tests per particle.
void BM_LocateElement(benchmark::State& state) {
  Problem pb = make_problem(static_cast<int>(state.range(0)));
  const std::size_t n = pb.particles.size();
  long sum = 0;
  for (auto _ : state) {
    for (std::size_t i = 0; i < n; ++i)
      sum += pb.mesh.locate_element(fdem::Vec3(pb.particles.x[i], pb.particles.y[i], pb.particles.z[i]));
    benchmark::DoNotOptimize(sum);
  }
  set_counters(state, n, 0);
}

// Eq. 32 (centre), the shape-function scheme and the exact intersection
// volumes (scheme 2): one porosity update.
void BM_Porosity(benchmark::State& state) {
  omp_set_num_threads(static_cast<int>(state.range(2)));
  Problem pb = make_problem(static_cast<int>(state.range(0)));
  const fdem::PorosityScheme schemes[] = {fdem::PorosityScheme::centre, fdem::PorosityScheme::shape_function,
                                          fdem::PorosityScheme::intersection};
  const char* names[] = {"centre", "shape_function", "intersection"};
  const auto scheme = schemes[state.range(1)];
  state.SetLabel(names[state.range(1)]);
  fdem::ParticleMapping mapping;
  mapping.update(pb.mesh, pb.particles);
  fdem::PorosityField porosity(pb.mesh, scheme, 0.1);
  for (auto _ : state) {
    const auto r = porosity.update(pb.particles, mapping);
    benchmark::DoNotOptimize(r);
  }
  set_counters(state, pb.particles.size(), pb.mesh.num_elements());
}

// Drag in one DEM subcycle (Eq. 11-15, Ergun / Wen & Yu with Rowe & Henwood):
// DragCoupling::add with the fluid velocity frozen at the particles.
// BM_DragSubcycleLaw: the same for the law in row `law` of
// drag_laws/drag_law_table.cpp (0: ergun_wen_yu, as BM_DragSubcycle).
void drag_subcycle(benchmark::State& state, std::size_t law) {
  omp_set_num_threads(static_cast<int>(state.range(1)));
  Problem pb = make_problem(static_cast<int>(state.range(0)));
  fdem::ParticleMapping mapping;
  mapping.update(pb.mesh, pb.particles);
  fdem::PorosityField porosity(pb.mesh, fdem::PorosityScheme::centre, 0.1);
  porosity.update(pb.particles, mapping);
  const std::vector<double> u = fluid_velocity(pb.mesh);
  fdem::DragCoupling drag(fdem::drag_laws()[law], fdem::FluidProperties{}, true);
  drag.begin_step(pb.mesh, mapping, pb.particles, u, porosity.values());
  const std::size_t n = pb.particles.size();
  std::vector<double> fx(n), fy(n), fz(n);
  for (auto _ : state) {
    drag.add(pb.particles, fx, fy, fz);
    benchmark::DoNotOptimize(fz.data());
  }
  set_counters(state, n, 0);
}
void BM_DragSubcycle(benchmark::State& state) { drag_subcycle(state, 0); }
void BM_DragSubcycleLaw(benchmark::State& state) {
  const auto law = static_cast<std::size_t>(state.range(2));
  state.SetLabel(std::string(fdem::drag_laws()[law].name));
  drag_subcycle(state, law);
}

// Source term (Eq. 20, 22, Fig. 4-5): mean drag per element, volume weighted,
// to the nodes; both forms (paper, conservative).
void BM_SourceTerm(benchmark::State& state) {
  omp_set_num_threads(static_cast<int>(state.range(2)));
  Problem pb = make_problem(static_cast<int>(state.range(0)));
  const auto form = state.range(1) == 0 ? fdem::SourceForm::paper : fdem::SourceForm::conservative;
  state.SetLabel(state.range(1) == 0 ? "paper" : "conservative");
  fdem::ParticleMapping mapping;
  mapping.update(pb.mesh, pb.particles);
  fdem::PorosityField porosity(pb.mesh, fdem::PorosityScheme::centre, 0.1);
  porosity.update(pb.particles, mapping);
  const std::size_t n = pb.particles.size();
  std::vector<double> dx(n, 1e-9), dy(n, -2e-9), dz(n, 5e-8);
  fdem::SourceTerm source(pb.mesh, form);
  for (auto _ : state) {
    source.compute(pb.particles, mapping, porosity.values(), dx, dy, dz);
    benchmark::DoNotOptimize(source.nodal_force_density().data());
  }
  set_counters(state, n, pb.mesh.num_elements());
}

// Arguments: problem (0 plume, 1 channel) [, scheme/form] , OpenMP threads.
BENCHMARK(BM_ParticleMapping)->ArgNames({"problem", "omp"})->ArgsProduct({{0, 1}, {1, 2}})->Unit(benchmark::kMicrosecond)->UseRealTime();
BENCHMARK(BM_LocateElement)->ArgNames({"problem"})->Args({0})->Args({1})->Unit(benchmark::kMicrosecond)->UseRealTime();
BENCHMARK(BM_Porosity)->ArgNames({"problem", "scheme", "omp"})->ArgsProduct({{0, 1}, {0, 1, 2}, {1, 2}})->Unit(benchmark::kMicrosecond)->UseRealTime();
BENCHMARK(BM_DragSubcycle)->ArgNames({"problem", "omp"})->ArgsProduct({{0, 1}, {1, 2}})->Unit(benchmark::kMicrosecond)->UseRealTime();
// Every registered law on the plume, one thread.
BENCHMARK(BM_DragSubcycleLaw)
    ->ArgNames({"problem", "omp", "law"})
    ->Apply([](benchmark::internal::Benchmark* b) {
      for (std::size_t law = 0; law < fdem::drag_laws().size(); ++law) b->Args({0, 1, static_cast<long>(law)});
    })
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime();
BENCHMARK(BM_SourceTerm)->ArgNames({"problem", "form", "omp"})->ArgsProduct({{0, 1}, {0, 1}, {1, 2}})->Unit(benchmark::kMicrosecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
