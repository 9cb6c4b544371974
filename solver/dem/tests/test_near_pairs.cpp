// The pair pass tests only the near set (DemEngine: the half pairs within a
// margin of touching at their last filtering, kept while the spread of the
// drift velocities bounds how much closer any two grains came since). A
// pair it wrongly left out would be a contact without its force: checked
// here against every pair in overlap, found without the neighbour list, in
// a lattice whose grains move in all directions, one thread (the threaded
// pass gives one thread's bits: DemDeterminism).
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <utility>
#include <vector>

#include "dem/dem_engine.hpp"
#include "dem/tests/lattice_grains.hpp"
#include "scene/tests/dry_box_scene.hpp"

namespace fdem {
namespace {

constexpr double kStiffness = 200.0;  // N/m, no damping: the force is a function of the positions alone

// 3072 grains of 0.8-1.2 mm on a 1.2 mm lattice (none overlapping),
// velocities +-0.05 m/s per axis: at dt 2e-5 s any two grains close by up
// to ~3.5 um a step, so the margin is ~16 steps' worth, 55 um, the list is
// rebuilt every ~150 steps and the near set refiltered ~10 times between.
Particles packed_grains() { return dem_test::lattice_grains(1.2e-3, 5); }

Scene undamped_box() {
  Scene s = scene_test::dry_box_scene("test_near_pairs", Vec3(0.025, 0.025, 0.08));
  s.contact.normal_stiffness = kStiffness;
  s.contact.normal_damping = 0.0;
  s.time.dem_step = 2e-5;
  return s;
}

// F of every grain from all pairs in overlap (sweep along x, no list), the
// walls of the box and gravity; and each grain's sum of force magnitudes,
// the scale of its rounding.
struct Forces {
  std::vector<double> fx, fy, fz, magnitude;
  std::size_t overlapping_pairs = 0;
};
Forces brute_force(const Particles& p, const Scene& s) {
  const std::size_t n = p.size();
  Forces f{std::vector<double>(n), std::vector<double>(n), std::vector<double>(n), std::vector<double>(n)};
  for (std::size_t i = 0; i < n; ++i) {
    f.fx[i] = p.mass[i] * s.gravity.x();
    f.fy[i] = p.mass[i] * s.gravity.y();
    f.fz[i] = p.mass[i] * s.gravity.z();
    f.magnitude[i] = p.mass[i] * s.gravity.norm();
  }
  std::vector<std::size_t> by_x(n);
  std::iota(by_x.begin(), by_x.end(), std::size_t{0});
  std::sort(by_x.begin(), by_x.end(), [&](std::size_t a, std::size_t b) { return p.x[a] < p.x[b]; });
  const double d_max = *std::max_element(p.diameter.begin(), p.diameter.end());
  for (std::size_t a = 0; a < n; ++a) {
    const std::size_t i = by_x[a];
    for (std::size_t b = a + 1; b < n && p.x[by_x[b]] - p.x[i] < d_max; ++b) {
      const std::size_t j = by_x[b];
      const double dx = p.x[j] - p.x[i], dy = p.y[j] - p.y[i], dz = p.z[j] - p.z[i];
      const double dist = std::sqrt(dx * dx + dy * dy + dz * dz);
      const double overlap = 0.5 * (p.diameter[i] + p.diameter[j]) - dist;
      if (overlap <= 0.0) continue;
      ++f.overlapping_pairs;
      const double push = kStiffness * overlap / dist;  // along (dx, dy, dz) on j, the opposite on i
      f.fx[i] -= push * dx, f.fy[i] -= push * dy, f.fz[i] -= push * dz;
      f.fx[j] += push * dx, f.fy[j] += push * dy, f.fz[j] += push * dz;
      f.magnitude[i] += kStiffness * overlap;
      f.magnitude[j] += kStiffness * overlap;
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    const double r = 0.5 * p.diameter[i];
    const double pos[3] = {p.x[i], p.y[i], p.z[i]};
    double* const out[3] = {&f.fx[i], &f.fy[i], &f.fz[i]};
    for (int a = 0; a < 3; ++a) {
      const double lower = r - (pos[a] - s.domain.lower[a]), upper = r - (s.domain.upper[a] - pos[a]);
      if (lower > 0.0) *out[a] += kStiffness * lower, f.magnitude[i] += kStiffness * lower;
      if (upper > 0.0) *out[a] -= kStiffness * upper, f.magnitude[i] += kStiffness * upper;
    }
  }
  return f;
}

void expect_every_contact_applied(int threads) {
  const int saved = omp_get_max_threads();
  omp_set_num_threads(threads);
  const Scene scene = undamped_box();
  DemEngine dem(packed_grains(), scene);
  std::size_t steps_with_contacts = 0, worst_grain_off = 0, overlapping_pairs = 0;
  double worst = 0.0;
  for (int step = 0; step < 600; ++step) {
    dem.step();
    const Particles& p = dem.particles();
    const Forces f = brute_force(p, scene);
    overlapping_pairs += f.overlapping_pairs;
    bool any_contact = false;
    for (std::size_t i = 0; i < p.size(); ++i) {
      // Same terms in another order and form: each overlap, a difference
      // of ~1 mm lengths, is rounded to ~1e-19 m, so the forces agree to a
      // few 1e-17 N and a few ulp of the magnitudes. A contact left out is
      // off by its whole force, Kn times its overlap: the tolerance misses
      // only overlaps below 1e-12 m (1e-9 of a diameter).
      const double off = std::abs(p.fx[i] - f.fx[i]) + std::abs(p.fy[i] - f.fy[i]) + std::abs(p.fz[i] - f.fz[i]);
      const double ratio = off / (1e-12 * f.magnitude[i] + 1e-9 * kStiffness * p.diameter[i]);
      if (ratio > worst) worst = ratio, worst_grain_off = i;
      any_contact = any_contact || f.magnitude[i] > 1.001 * p.mass[i] * scene.gravity.norm();
    }
    steps_with_contacts += any_contact ? 1 : 0;
  }
  omp_set_num_threads(saved);
  const DemDiagnostics d = dem.diagnostics();
  EXPECT_LT(worst, 1.0) << "grain " << worst_grain_off << " on " << threads << " threads";
  EXPECT_GT(steps_with_contacts, 400u) << d.contacts;
  // The near set was in use: refiltered between list builds, and smaller
  // than the half list (each pair is twice in the list's entries).
  EXPECT_GT(d.phases.near_pair_filters, 4 * d.neighbour_rebuilds);
  EXPECT_LT(d.phases.pairs_tested, d.phases.pair_entries_tested / 4);
  // The pass's count of touching pairs (the benchmarks' work per step) is
  // the reference's count of pairs in overlap, summed over the steps (the
  // construction's evaluation, on the lattice, has none). Exact: the two
  // tests round differently only for an overlap within ~1e-19 m of zero.
  EXPECT_EQ(d.phases.pairs_touching, overlapping_pairs) << "on " << threads << " threads";
  std::printf("near pairs: %zu filters, %zu rebuilds, %zu threaded passes, %.0f pairs tested a step of %.0f, "
              "%zu contacts at the end\n",
              d.phases.near_pair_filters, d.neighbour_rebuilds, d.phases.threaded_pair_passes,
              static_cast<double>(d.phases.pairs_tested) / static_cast<double>(d.phases.force_evaluations),
              0.5 * static_cast<double>(d.phases.pair_entries_tested) / static_cast<double>(d.phases.force_evaluations),
              d.contacts);
}

TEST(NearPairs, EveryContactOfAMovingLatticeGetsItsForce) { expect_every_contact_applied(1); }
TEST(NearPairs, EveryContactOfAMovingLatticeGetsItsForceOnTwoThreads) { expect_every_contact_applied(2); }

// With a dashpot (Cn given: the law the vector pass takes, where the build
// has AVX-512 or AVX2) every force is Kn delta + Cn delta_dot along the normal, the
// closing rate from the half-step velocities the pass saw: v^{n+1/2} =
// v^{n+1} - dt / (2 m) F^{n+1}, read back from the particles (rounding of a
// few 1e-18 m/s, 1e-20 N of dashpot). The lattice is lifted 10 mm so that
// no grain reaches a wall in the 300 steps (the reference has no walls).
void expect_damped_contacts(int threads) {
  constexpr double kDamping = 0.01;  // N s/m: zeta ~0.3 for these grains, dashpot and spring of one order
  const int saved = omp_get_max_threads();
  omp_set_num_threads(threads);
  Scene scene = undamped_box();
  scene.contact.normal_damping = kDamping;
  Particles grains = packed_grains();
  for (double& z : grains.z) z += 10e-3;
  DemEngine dem(std::move(grains), scene);
  double worst = 0.0, largest_dashpot = 0.0;
  std::size_t contacts_checked = 0;
  for (int step = 0; step < 300; ++step) {
    dem.step();
    const Particles& p = dem.particles();
    const std::size_t n = p.size();
    const double half_dt = 0.5 * scene.time.dem_step;
    std::vector<double> fx(n), fy(n), fz(n), magnitude(n);
    for (std::size_t i = 0; i < n; ++i) {
      fx[i] = p.mass[i] * scene.gravity.x();
      fy[i] = p.mass[i] * scene.gravity.y();
      fz[i] = p.mass[i] * scene.gravity.z();
      magnitude[i] = p.mass[i] * scene.gravity.norm();
    }
    const auto v_half = [&](std::size_t i, int axis) {
      const double v[3] = {p.vx[i], p.vy[i], p.vz[i]}, f[3] = {p.fx[i], p.fy[i], p.fz[i]};
      return v[axis] - half_dt / p.mass[i] * f[axis];
    };
    std::vector<std::size_t> by_x(n);  // a sweep along x, as brute_force
    std::iota(by_x.begin(), by_x.end(), std::size_t{0});
    std::sort(by_x.begin(), by_x.end(), [&](std::size_t a, std::size_t b) { return p.x[a] < p.x[b]; });
    const double d_max = *std::max_element(p.diameter.begin(), p.diameter.end());
    for (std::size_t a = 0; a < n; ++a)
      for (std::size_t b = a + 1; b < n && p.x[by_x[b]] - p.x[by_x[a]] < d_max; ++b) {
        const std::size_t i = by_x[a], j = by_x[b];
        const double dx = p.x[j] - p.x[i], dy = p.y[j] - p.y[i], dz = p.z[j] - p.z[i];
        const double reach = 0.5 * (p.diameter[i] + p.diameter[j]);
        if (dx * dx + dy * dy + dz * dz >= reach * reach) continue;
        const double dist = std::sqrt(dx * dx + dy * dy + dz * dz);
        const double nx = dx / dist, ny = dy / dist, nz = dz / dist;
        const double closing = (v_half(i, 0) - v_half(j, 0)) * nx + (v_half(i, 1) - v_half(j, 1)) * ny +
                               (v_half(i, 2) - v_half(j, 2)) * nz;
        const double spring = kStiffness * (reach - dist), dashpot = kDamping * closing;
        const double push = spring + dashpot;  // on j along n, on i against it
        fx[i] -= push * nx, fy[i] -= push * ny, fz[i] -= push * nz;
        fx[j] += push * nx, fy[j] += push * ny, fz[j] += push * nz;
        magnitude[i] += std::abs(spring) + std::abs(dashpot);
        magnitude[j] += std::abs(spring) + std::abs(dashpot);
        largest_dashpot = std::max(largest_dashpot, std::abs(dashpot));
        ++contacts_checked;
      }
    for (std::size_t i = 0; i < n; ++i) {
      // As above: a few ulp of the magnitudes; a contact left out, or its
      // dashpot dropped or of the wrong sign, is off by a whole term.
      const double off = std::abs(p.fx[i] - fx[i]) + std::abs(p.fy[i] - fy[i]) + std::abs(p.fz[i] - fz[i]);
      worst = std::max(worst, off / (1e-12 * magnitude[i] + 1e-9 * kStiffness * p.diameter[i]));
    }
  }
  omp_set_num_threads(saved);
  EXPECT_LT(worst, 1.0) << threads << " threads";
  EXPECT_EQ(dem.diagnostics().wall_contacts, 0u);
  EXPECT_GT(contacts_checked, 10000u);                 // ~100 contacts a step on average
  EXPECT_GT(largest_dashpot, 1e-9 * kStiffness * 1e-3);  // the dashpot term is larger than the tolerance's floor
  std::printf("damped contacts: %zu checked over 300 steps, largest dashpot %.3e N, worst %.3g of the tolerance\n",
              contacts_checked, largest_dashpot, worst);
}

TEST(NearPairs, DampedContactsGetSpringPlusDashpotOnOneThread) { expect_damped_contacts(1); }
TEST(NearPairs, DampedContactsGetSpringPlusDashpotOnTwoThreads) { expect_damped_contacts(2); }

}  // namespace
}  // namespace fdem
