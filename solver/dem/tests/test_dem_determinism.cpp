// The DEM step's results do not depend on how it is observed or run: the
// second kick deferred into the next step's pass (DemEngine::step) gives the
// same bits whether or not the particles are read between steps, and the
// normal-contact kernel (the plume's and scenes P/B's) gives the same bits
// on 1, 2 and 3 OpenMP threads (above the engine's parallel threshold).
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <numeric>
#include <random>
#include <span>
#include <vector>

#include "dem/dem_engine.hpp"
#include "dem/tests/lattice_grains.hpp"
#include "scene/tests/dry_box_scene.hpp"

namespace fdem {
namespace {

// A linear drag through the ExternalForce hook, as the coupling's drag uses it.
struct LinearDrag final : ExternalForce {
  void add(const Particles& p, std::span<double> fx, std::span<double> fy, std::span<double> fz) override {
    for (std::size_t i = 0; i < p.size(); ++i) {
      fx[i] -= 0.03 * p.mass[i] * p.vx[i];
      fy[i] -= 0.03 * p.mass[i] * p.vy[i];
      fz[i] -= 0.03 * p.mass[i] * p.vz[i];
    }
  }
};

// 3072 grains of 0.8-1.2 mm on a 1.3 mm lattice (16 x 16 x 12) with random
// velocities in a walled box: contacts form within tens of steps.
Particles lattice_grains(double spacing = 1.3e-3) { return dem_test::lattice_grains(spacing, 11); }

Scene box_scene() {
  Scene s = scene_test::dry_box_scene("test_dem_determinism", Vec3(0.025, 0.025, 0.08));
  s.contact.normal_stiffness = 200.0;
  s.contact.normal_damping = 2e-3;  // absolute Cn, as the plume
  s.time.dem_step = 2e-5;
  return s;
}

struct Outcome {
  Particles particles;
  std::size_t threaded_pair_passes = 0;
  std::size_t near_pair_filters = 0;
  std::size_t threaded_near_filters = 0;
};

// 400 steps of `grains` in the box on `threads` threads, with `drag` when
// given; read_every_step reads a velocity after each step.
// omp_set_num_threads overrides OMP_NUM_THREADS (the fast tier sets it to 1).
Outcome run_grains(const Particles& grains, int threads, ExternalForce* drag, bool read_every_step) {
  const int saved = omp_get_max_threads();
  omp_set_num_threads(threads);
  DemEngine dem(grains, box_scene());
  if (drag != nullptr) dem.set_external_force(drag);
  double checksum = 0.0;
  for (int s = 0; s < 400; ++s) {
    dem.step();
    if (read_every_step) checksum += dem.particles().vz[7];
  }
  omp_set_num_threads(saved);
  // Pairs in overlap at the end (measured 58 at the 1.3 mm spacing): the pair loop and the walls run.
  const DemDiagnostics diagnostics = dem.diagnostics();
  EXPECT_GT(diagnostics.contacts, 20u);
  (void)checksum;
  return {dem.particles(), diagnostics.phases.threaded_pair_passes, diagnostics.phases.near_pair_filters,
          diagnostics.phases.threaded_near_filters};
}

// The lattice at `spacing` with the linear drag.
Outcome run_with(int threads, bool read_every_step, double spacing) {
  LinearDrag drag;
  return run_grains(lattice_grains(spacing), threads, &drag, read_every_step);
}

// Positions, velocities and forces equal to the bit.
void expect_same_bits(const Particles& a, const Particles& b) {
  EXPECT_EQ(a.x, b.x);
  EXPECT_EQ(a.y, b.y);
  EXPECT_EQ(a.z, b.z);
  EXPECT_EQ(a.vx, b.vx);
  EXPECT_EQ(a.vy, b.vy);
  EXPECT_EQ(a.vz, b.vz);
  EXPECT_EQ(a.fx, b.fx);
  EXPECT_EQ(a.fy, b.fy);
  EXPECT_EQ(a.fz, b.fz);
}

Particles run(int threads, bool read_every_step) { return run_with(threads, read_every_step, 1.3e-3).particles; }

TEST(DemDeterminism, ReadingTheParticlesBetweenStepsChangesNoBit) {
  const Particles a = run(1, false), b = run(1, true);
  expect_same_bits(a, b);
}

TEST(DemDeterminism, NormalContactKernelIsBitIdenticalForOneTwoAndThreeThreads) {
  const Particles a = run(1, false), b = run(2, false), c = run(3, true);
  expect_same_bits(a, b);
  expect_same_bits(a, c);
  EXPECT_NE(a.z, lattice_grains().z);  // it moved
}

// The lattice above tests too few pairs a step for the threaded pair pass
// (below the engine's parallel threshold, it runs in one thread whatever
// the count): packed at 1.08 mm, grains of 0.8-1.2 mm start with thousands
// of pairs within reach, so on 2 and 3 threads the threaded pass (shares
// of the pairs cut at grain rows, each thread forming again the pairs
// that cross into its grains, walls in the same region) runs, which the
// engine counts, and must give one thread's bits.
TEST(DemDeterminism, ThreadedPairPassOfADensePackIsBitIdenticalToOneThread) {
  const Outcome a = run_with(1, false, 1.08e-3), b = run_with(2, false, 1.08e-3), c = run_with(3, false, 1.08e-3);
  EXPECT_EQ(a.threaded_pair_passes, 0u);
  EXPECT_GT(b.threaded_pair_passes, 100u);  // of 401 force evaluations
  EXPECT_GT(c.threaded_pair_passes, 100u);
  // The near-pair filter runs too, in shares on the threads
  // (near_filter_in_shares, above the engine's parallel threshold).
  EXPECT_GT(b.near_pair_filters, 0u);
  EXPECT_GT(b.threaded_near_filters, 0u);
  EXPECT_GT(c.threaded_near_filters, 0u);
  EXPECT_EQ(a.threaded_near_filters, 0u);
  for (const Outcome* r : {&b, &c}) expect_same_bits(a.particles, r->particles);
}

// The dense pack in a shuffled grain order, dry: a grain's neighbours then
// lie anywhere in the index range, so on 3 threads the last thread's grains
// get crossing pairs from both earlier threads' rows, and with no external
// force each thread integrates the grains of its pair rows (the kick-drift
// on the pair pass's split). Both must give one thread's bits.
Outcome run_shuffled_dry(int threads) {
  const Particles packed = lattice_grains(1.08e-3);
  std::vector<std::size_t> order(packed.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::shuffle(order.begin(), order.end(), std::mt19937_64(5));
  Particles shuffled;
  for (std::size_t k : order)
    shuffled.add(packed.x[k], packed.y[k], packed.z[k], packed.diameter[k], 2500.0, packed.vx[k], packed.vy[k],
                 packed.vz[k]);
  return run_grains(shuffled, threads, nullptr, false);
}

TEST(DemDeterminism, ShuffledDryPackIsBitIdenticalOnOneTwoAndThreeThreads) {
  const Outcome a = run_shuffled_dry(1), b = run_shuffled_dry(2), c = run_shuffled_dry(3);
  EXPECT_EQ(a.threaded_pair_passes, 0u);
  EXPECT_GT(b.threaded_pair_passes, 100u);  // of 401 force evaluations
  EXPECT_GT(c.threaded_pair_passes, 100u);
  for (const Outcome* r : {&b, &c}) expect_same_bits(a.particles, r->particles);
}

}  // namespace
}  // namespace fdem
