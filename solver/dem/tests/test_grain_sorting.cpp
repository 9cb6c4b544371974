// DemEngine::sort_in_cell_order (dem/cell_order.hpp): every grain keeps its
// state through a sort, bit for bit; where each grain has at most one
// contact a sorted run gives the unsorted run's bits (a grain's force is
// then one sum in one order either way); in a dense pack the sort changes
// the order of each grain's contact sum and only rounding separates the
// runs; and sorted runs stay bit-identical for any thread count.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <span>
#include <vector>

#include "dem/cell_order.hpp"
#include "dem/dem_engine.hpp"
#include "scene/tests/dry_box_scene.hpp"

// A namespace of its own: the executable compiles its files as one unit.
namespace fdem::grain_sorting_test {
namespace {

struct LinearDrag final : ExternalForce {
  void add(const Particles& p, std::span<double> fx, std::span<double> fy, std::span<double> fz) override {
    for (std::size_t i = 0; i < p.size(); ++i) {
      fx[i] -= 0.03 * p.mass[i] * p.vx[i];
      fy[i] -= 0.03 * p.mass[i] * p.vy[i];
      fz[i] -= 0.03 * p.mass[i] * p.vz[i];
    }
  }
};

// The particles in a random order (as a deformed cloud's are), ids kept.
Particles shuffled(const Particles& in, unsigned seed) {
  std::vector<std::size_t> order(in.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::mt19937_64 rng(seed);
  std::shuffle(order.begin(), order.end(), rng);
  Particles p;
  for (std::size_t k : order) {
    p.add(in.x[k], in.y[k], in.z[k], in.diameter[k], 2500.0, in.vx[k], in.vy[k], in.vz[k]);
    p.id.push_back(static_cast<Index>(k));
  }
  return p;
}

// 3072 grains of 0.8-1.2 mm on a 1.3 mm lattice with random velocities in a
// walled box (test_dem_determinism.cpp's pack): ~60 pairs in overlap.
Particles dense_pack() {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> d(0.8e-3, 1.2e-3), v(-0.05, 0.05);
  Particles p;
  for (int i = 0; i < 3072; ++i)
    p.add(1.5e-3 + (i % 16) * 1.3e-3, 1.5e-3 + (i / 16 % 16) * 1.3e-3, 1e-3 + (i / 256) * 1.3e-3, d(rng), 2500.0,
          v(rng), v(rng), v(rng));
  return shuffled(p, 5);
}

// 512 isolated pairs of 1 mm grains 4 mm apart, each pair 1.05 mm centre
// to centre and closing at 0.04 m/s, off centre: every grain meets its
// partner and no other (it travels < 0.5 mm in the runs below).
Particles isolated_pairs() {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Particles p;
  for (int k = 0; k < 512; ++k) {
    const double cx = 3e-3 + (k % 8) * 4e-3, cy = 3e-3 + (k / 8 % 8) * 4e-3, cz = 3e-3 + (k / 64) * 4e-3;
    const Vec3 axis = Vec3(u(rng), u(rng), u(rng)).normalized(), side = Vec3(u(rng), u(rng), u(rng)) * 0.01;
    const Vec3 a = Vec3(cx, cy, cz) - 0.525e-3 * axis, b = Vec3(cx, cy, cz) + 0.525e-3 * axis;
    const Vec3 va = 0.02 * axis + side, vb = -0.02 * axis - side;
    p.add(a.x(), a.y(), a.z(), 1e-3, 2500.0, va.x(), va.y(), va.z());
    p.add(b.x(), b.y(), b.z(), 1e-3, 2500.0, vb.x(), vb.y(), vb.z());
  }
  return shuffled(p, 9);
}

Scene box_scene(bool tangential) {
  Scene s = scene_test::dry_box_scene("test_grain_sorting", Vec3(0.035, 0.035, 0.08));
  s.effects.tangential_contact = tangential;
  s.effects.rotation = tangential;
  s.contact.normal_stiffness = 200.0;
  s.contact.normal_damping = 2e-3;
  s.contact.tangential_stiffness = 150.0;
  s.contact.tangential_damping = 1e-3;
  s.contact.friction = 0.3;
  s.time.dem_step = 2e-5;
  return s;
}

// A field in id order.
std::vector<double> by_id(const Particles& p, std::span<const double> v) {
  std::vector<double> out(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) out[static_cast<std::size_t>(p.id[i])] = v[i];
  return out;
}

// Every grain's state, in id order.
std::vector<std::vector<double>> state_by_id(const Particles& p) {
  std::vector<std::vector<double>> out;
  for (const auto* v : {&p.x, &p.y, &p.z, &p.vx, &p.vy, &p.vz, &p.fx, &p.fy, &p.fz, &p.wx, &p.wy, &p.wz, &p.tx,
                        &p.ty, &p.tz, &p.diameter, &p.mass})
    if (v->size() == p.size()) out.push_back(by_id(p, *v));
  return out;
}

// steps DEM steps, sorted after every `sort_every` (0: never).
Particles run(Particles grains, const Scene& scene, int steps, int sort_every, int threads,
              std::size_t* sorts = nullptr) {
  const int saved = omp_get_max_threads();
  omp_set_num_threads(threads);
  DemEngine dem(std::move(grains), scene);
  LinearDrag drag;
  dem.set_external_force(&drag);
  for (int s = 1; s <= steps; ++s) {
    dem.step();
    if (sort_every > 0 && s % sort_every == 0) dem.sort_in_cell_order();
  }
  omp_set_num_threads(saved);
  if (sorts != nullptr) *sorts = dem.diagnostics().grain_sorts;
  return dem.particles();
}

double max_abs_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double m = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) m = std::max(m, std::abs(a[i] - b[i]));
  return m;
}

TEST(GrainSorting, EveryGrainKeepsItsStateAndTheGrainsEndInCellOrder) {
  const Scene scene = box_scene(true);
  DemEngine dem(dense_pack(), scene);
  dem.run(150);  // contacts with slip histories
  const DemDiagnostics before = dem.diagnostics();
  ASSERT_GT(before.contacts, 20u);
  const std::vector<std::vector<double>> state = state_by_id(dem.particles());
  const std::vector<Index> ids_before = dem.particles().id;
  const std::span<const Index> order = dem.sort_in_cell_order();
  ASSERT_EQ(order.size(), ids_before.size()) << "a shuffled pack is not in cell order";
  const Particles& p = dem.particles();
  for (std::size_t k = 0; k < order.size(); ++k) EXPECT_EQ(p.id[k], ids_before[static_cast<std::size_t>(order[k])]);
  EXPECT_EQ(state_by_id(p), state);  // bit for bit, forces and torques F^n included
  const DemDiagnostics after = dem.diagnostics();
  EXPECT_EQ(after.contacts, before.contacts);
  EXPECT_EQ(after.grain_sorts, 1u);
  EXPECT_TRUE(dem.sort_in_cell_order().empty()) << "sorted grains stay as they are";
  double d_max = 0.0;
  for (double d : p.diameter) d_max = std::max(d_max, d);
  const std::vector<Index> again = cell_order(p, d_max + 0.5 * d_max);  // the engine's skin: half d_max
  for (std::size_t k = 0; k < again.size(); ++k) ASSERT_EQ(again[k], static_cast<Index>(k));
}

// One contact per grain at most: the sorted and unsorted runs are the same
// computation in another order of grains, to the bit, normal contact alone
// (the half-list pass) and with friction and rotation (slip histories
// carried across each sort, mid-contact).
TEST(GrainSorting, GrainsWithOneContactGetTheUnsortedRunsBits) {
  for (const bool tangential : {false, true}) {
    const Scene scene = box_scene(tangential);
    std::size_t sorts = 0;
    const Particles plain = run(isolated_pairs(), scene, 600, 0, 1);
    const Particles sorted = run(isolated_pairs(), scene, 600, 150, 1, &sorts);
    EXPECT_GE(sorts, 2u) << "grains that moved across cells are sorted again";
    EXPECT_EQ(state_by_id(sorted), state_by_id(plain)) << "tangential " << tangential;
    EXPECT_NE(by_id(plain, plain.vx), by_id(plain, isolated_pairs().vx)) << "the pairs collided";
  }
}

TEST(GrainSorting, DensePackDiffersFromTheUnsortedRunByRoundingAndNotByThreads) {
  const Scene scene = box_scene(false);
  const Particles plain = run(dense_pack(), scene, 400, 0, 1);
  const Particles one = run(dense_pack(), scene, 400, 100, 1), two = run(dense_pack(), scene, 400, 100, 2),
                  three = run(dense_pack(), scene, 400, 100, 3);
  EXPECT_EQ(state_by_id(one), state_by_id(two));
  EXPECT_EQ(state_by_id(one), state_by_id(three));
  const double dx = std::max({max_abs_difference(by_id(one, one.x), by_id(plain, plain.x)),
                              max_abs_difference(by_id(one, one.y), by_id(plain, plain.y)),
                              max_abs_difference(by_id(one, one.z), by_id(plain, plain.z))});
  const double dv = std::max({max_abs_difference(by_id(one, one.vx), by_id(plain, plain.vx)),
                              max_abs_difference(by_id(one, one.vy), by_id(plain, plain.vy)),
                              max_abs_difference(by_id(one, one.vz), by_id(plain, plain.vz))});
  RecordProperty("max_position_difference_m", std::to_string(dx));
  RecordProperty("max_velocity_difference_mps", std::to_string(dv));
  std::printf("sorted - unsorted after 400 steps: |dx| %.3g m, |dv| %.3g m/s\n", dx, dv);
  EXPECT_GT(dx + dv, 0.0) << "the contact sums changed order";
  // Rounding only: each contact sum in another order differs by ulps of
  // the force, and 400 steps (a few contact times) do not amplify it much.
  // Measured |dv| 3.5e-18 m/s (1e-16 of the 0.05 m/s speeds), |dx| 0 (dt dv
  // is below an ulp of the positions); bounds ~1e3 ulps of the speeds, and
  // what such a velocity error moves a grain in 400 steps.
  EXPECT_LT(dv, 1e-14);
  EXPECT_LT(dx, 400 * scene.time.dem_step * 1e-14);
}

}  // namespace
}  // namespace fdem::grain_sorting_test
