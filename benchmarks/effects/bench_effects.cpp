// Effects cost nothing when off (benchmarks/README.md, "Effects"): a dry DEM
// scene run with tangential contact, rotation or fluid off must be as fast as
// the same physics compiled without them, and memory per particle must drop
// when no slip history is kept.
//
// Scene: a dense, dry bed of 4800 equal spheres, d 0.25 mm, rho 2170 kg/m^3,
// on a 20 x 20 x 12 simple cubic lattice whose spacing is 0.5 % below d, in a
// box whose walls touch the outer spheres: every grain has six particle
// contacts (three pairs), plus walls at the boundary, at every step (the
// contact-bound regime of the anchors' settled bed B). Kn 1e5 N/m,
// Cn 0.026 N s/m and dt 1e-7 s as in bed B (stable: dt = 0.34 t_c0/pi of the
// pair); Kt = 2/7 Kn and mu 0.5 where tangential contact is on. Small random
// initial velocities (1 mm/s, seeded) keep the contacts sliding and spinning.
//
// What is compared (particle_steps_per_s; same scene, same thread count):
//   reference_normal_only   the physics with no effect machinery at all: a
//                           hand-written velocity-Verlet loop over the same
//                           NeighbourList and contact law (contact_force<false, LinearSpringDashpotForce<false>>),
//                           normal contact + walls + gravity only
//   engine_normal_only      DemEngine with tangential, rotation (and fluid) off
//   engine_tangential       ... with tangential contact on (slip history)
//   engine_rotation         ... with rotation on (no tangential: torque zero)
//   engine_tangential_rotation
//   simulation_fluid_off    Simulation (the coupled driver) with effects.fluid
//                           off: must cost what DemEngine alone costs
// effects/compare_effects.py runs these with repetitions and states whether
// each "off" figure is within the noise band of the reference.
// BM_MemoryPerParticle reports heap bytes per particle (mallinfo2: arena plus
// mmapped blocks) of a DemEngine after its first steps, tangential off and on.
#include <benchmark/benchmark.h>
#include <malloc.h>
#include <omp.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "core/particles.hpp"
#include "coupling/simulation.hpp"
#include "dem/contact_law.hpp"
#include "dem/dem_engine.hpp"
#include "dem/neighbour_list.hpp"
#include "scene/particle_generator.hpp"
#include "scene/scene.hpp"

namespace {

using fdem::Particles;
using fdem::Scene;
using fdem::Vec3;

constexpr double kDiameter = 0.25e-3;        // [m]
constexpr double kSpacing = 0.995 * kDiameter;  // lattice spacing: 0.5 % overlap per contact
constexpr int kNx = 20, kNy = 20, kNz = 12;  // 4800 grains

enum class Variant { normal_only, tangential, rotation, tangential_rotation };

Scene bed_scene(Variant v) {
  Scene s;
  s.title = "effects bed";
  s.domain.lower = Vec3::Zero();
  s.domain.upper = Vec3(kNx * kSpacing, kNy * kSpacing, kNz * kSpacing);
  s.effects.fluid = false;
  s.effects.coupling = fdem::CouplingMode::off;
  s.effects.buoyancy = false;
  s.effects.tangential_contact = v == Variant::tangential || v == Variant::tangential_rotation;
  s.effects.rotation = v == Variant::rotation || v == Variant::tangential_rotation;
  s.contact.normal_stiffness = 1e5;
  s.contact.normal_damping = 0.026;
  s.contact.tangential_stiffness = 2.0 / 7.0 * 1e5;
  s.contact.friction = 0.5;
  s.time.dem_step = 1e-7;
  s.time.fluid_step = 0.0;  // dry: Simulation steps one DEM step at a time
  s.time.end_time = 1.0;
  fdem::ParticleSet set;
  set.name = "bed";
  set.placement = fdem::PlacementKind::lattice;
  set.region = s.domain;
  set.lattice = {kNx, kNy, kNz};
  set.size.kind = fdem::SizeKind::fixed;
  set.size.diameter = kDiameter;
  set.density = 2170.0;
  s.particles.push_back(set);
  return s;
}

Particles bed_particles(const Scene& s) {
  Particles p = fdem::generate_particles(s);
  std::mt19937_64 rng(7);
  for (std::size_t i = 0; i < p.size(); ++i) {
    p.vx[i] = 1e-3 * (2.0 * fdem::uniform01(rng) - 1.0);
    p.vy[i] = 1e-3 * (2.0 * fdem::uniform01(rng) - 1.0);
    p.vz[i] = 1e-3 * (2.0 * fdem::uniform01(rng) - 1.0);
  }
  return p;
}

void set_counters(benchmark::State& state, std::size_t particles) {
  state.counters["particle_steps_per_s"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * static_cast<double>(particles),
                         benchmark::Counter::kIsRate);
  state.counters["particles"] = static_cast<double>(particles);
}

// The same physics as DemEngine with every effect but normal contact, walls
// and gravity off, written without any effect switch: velocity Verlet
// (kick-drift-kick), Verlet list rebuilt past skin/2, Eq. 6 per pair and per
// wall, the lost-particle scan the engine also does.
class ReferenceNormalOnly {
 public:
  explicit ReferenceNormalOnly(const Scene& s) : p_(bed_particles(s)), box_(s.domain), dt_(s.time.dem_step) {
    law_ = fdem::contact_law_of(s.contact);
    g_ = s.gravity;
    skin_ = 0.5 * kDiameter;
    list_.build(p_, skin_);
    forces();
  }

  void step() {
    const auto n = static_cast<std::ptrdiff_t>(p_.size());
    const double h = 0.5 * dt_;
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t si = 0; si < n; ++si) {
      const auto i = static_cast<std::size_t>(si);
      kick(i, h);
      p_.x[i] += dt_ * p_.vx[i];
      p_.y[i] += dt_ * p_.vy[i];
      p_.z[i] += dt_ * p_.vz[i];
    }
    long outside = 0;
    for (std::size_t i = 0; i < p_.size(); ++i)
      outside += !(p_.x[i] >= box_.lower.x() && p_.x[i] <= box_.upper.x() && p_.y[i] >= box_.lower.y() &&
                   p_.y[i] <= box_.upper.y() && p_.z[i] >= box_.lower.z() && p_.z[i] <= box_.upper.z());
    lost_ += outside;
    if (list_.needs_rebuild(p_)) list_.build(p_, skin_);
    forces();
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t si = 0; si < n; ++si) kick(static_cast<std::size_t>(si), h);
  }

  std::size_t size() const { return p_.size(); }
  long lost() const { return lost_; }

 private:
  // Half a velocity step, v += (h / m) F, for particle i.
  void kick(std::size_t i, double h) {
    const double a = h / p_.mass[i];
    p_.vx[i] += a * p_.fx[i];
    p_.vy[i] += a * p_.fy[i];
    p_.vz[i] += a * p_.fz[i];
  }

  void forces() {
    const auto n = static_cast<std::ptrdiff_t>(p_.size());
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t si = 0; si < n; ++si) {
      const auto i = static_cast<std::size_t>(si);
      Vec3 f = p_.mass[i] * g_;
      const double ri = 0.5 * p_.diameter[i];
      const Vec3 xi(p_.x[i], p_.y[i], p_.z[i]), vi(p_.vx[i], p_.vy[i], p_.vz[i]);
      for (const fdem::Index j : list_.neighbours(i)) {
        const auto uj = static_cast<std::size_t>(j);
        const Vec3 dx = Vec3(p_.x[uj], p_.y[uj], p_.z[uj]) - xi;
        const double sum_r = ri + 0.5 * p_.diameter[uj];
        const double dist2 = dx.squaredNorm();
        if (dist2 >= sum_r * sum_r) continue;
        const double dist = std::sqrt(dist2);
        const Vec3 nrm = dx / dist;
        const double m_eff = p_.mass[i] * p_.mass[uj] / (p_.mass[i] + p_.mass[uj]);
        const Vec3 v_rel = vi - Vec3(p_.vx[uj], p_.vy[uj], p_.vz[uj]);
        f += fdem::contact_force<false, Hooke>(law_, m_eff, sum_r - dist, nrm, v_rel, dt_, nullptr).normal;  // Eq. 6
      }
      for (int w = 0; w < 6; ++w) {
        const int axis = w / 2;
        const double gap = (w % 2 == 0) ? xi[axis] - box_.lower[axis] : box_.upper[axis] - xi[axis];
        if (gap >= ri) continue;
        Vec3 nrm = Vec3::Zero();
        nrm[axis] = (w % 2 == 0) ? -1.0 : 1.0;
        f += fdem::contact_force<false, Hooke>(law_, p_.mass[i], ri - gap, nrm, vi, dt_, nullptr).normal;  // Eq. 6
      }
      p_.fx[i] = f.x();
      p_.fy[i] = f.y();
      p_.fz[i] = f.z();
    }
  }

  Particles p_;
  fdem::Box box_;
  double dt_, skin_ = 0.0;
  Vec3 g_ = Vec3::Zero();
  using Hooke = fdem::LinearSpringDashpotForce<false>;  // Kn, Cn given (the bed scene's)
  fdem::ContactLaw law_;
  fdem::NeighbourList list_;
  long lost_ = 0;
};

void BM_Effects_reference_normal_only(benchmark::State& state) {
  omp_set_num_threads(static_cast<int>(state.range(0)));
  ReferenceNormalOnly ref(bed_scene(Variant::normal_only));
  for (auto _ : state) ref.step();
  if (ref.lost() != 0) state.SkipWithError("grains left the box");
  set_counters(state, ref.size());
}

void run_engine(benchmark::State& state, Variant v) {
  omp_set_num_threads(static_cast<int>(state.range(0)));
  const Scene s = bed_scene(v);
  fdem::DemEngine engine(bed_particles(s), s);
  for (auto _ : state) engine.step();
  if (engine.diagnostics().particles_removed != 0) state.SkipWithError("grains left the box");
  set_counters(state, engine.particles().size());
}

void BM_Effects_engine_normal_only(benchmark::State& state) { run_engine(state, Variant::normal_only); }
void BM_Effects_engine_tangential(benchmark::State& state) { run_engine(state, Variant::tangential); }
void BM_Effects_engine_rotation(benchmark::State& state) { run_engine(state, Variant::rotation); }
void BM_Effects_engine_tangential_rotation(benchmark::State& state) {
  run_engine(state, Variant::tangential_rotation);
}

// The coupled driver on a dry scene: one step() = one DEM step, no mesh, no fluid.
void BM_Effects_simulation_fluid_off(benchmark::State& state) {
  omp_set_num_threads(static_cast<int>(state.range(0)));
  fdem::Simulation sim(bed_scene(Variant::normal_only));
  if (sim.mesh() != nullptr) state.SkipWithError("a dry scene built a mesh");
  for (auto _ : state) sim.step();
  set_counters(state, sim.particles().size());
}

std::size_t heap_bytes() {
  const struct mallinfo2 mi = mallinfo2();
  return mi.uordblks + mi.hblkhd;  // arena in use + mmapped blocks (large vectors)
}

// Heap per particle of a DemEngine (particles, neighbour list, slip history)
// after two steps: heap in use then minus heap in use before the particles
// were generated.
void BM_MemoryPerParticle(benchmark::State& state) {
  const auto v = state.range(0) == 0 ? Variant::normal_only : Variant::tangential;
  state.SetLabel(state.range(0) == 0 ? "tangential_off" : "tangential_on");
  double bytes = 0.0;
  std::size_t n = 0;
  for (auto _ : state) {
    const Scene s = bed_scene(v);
    const std::size_t before = heap_bytes();
    {
      fdem::DemEngine engine(bed_particles(s), s);
      engine.run(2);
      n = engine.particles().size();
      bytes = static_cast<double>(heap_bytes()) - static_cast<double>(before);
    }
    benchmark::DoNotOptimize(bytes);
  }
  state.counters["bytes_per_particle"] = bytes / static_cast<double>(n);
  state.counters["particles"] = static_cast<double>(n);
  std::fprintf(stderr, "memory per particle, %s: %.1f bytes (4800-grain bed, 6 contacts per grain)\n",
               state.range(0) == 0 ? "tangential off" : "tangential on ", bytes / static_cast<double>(n));
}

BENCHMARK(BM_Effects_reference_normal_only)->ArgName("omp")->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Effects_engine_normal_only)->ArgName("omp")->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Effects_simulation_fluid_off)->ArgName("omp")->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Effects_engine_rotation)->ArgName("omp")->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Effects_engine_tangential)->ArgName("omp")->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Effects_engine_tangential_rotation)->ArgName("omp")->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_MemoryPerParticle)->ArgName("tangential")->Arg(0)->Arg(1)->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
