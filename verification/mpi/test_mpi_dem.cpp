// The DEM decomposed over the MPI ranks (DemEngine::decompose,
// parallel/grain_exchange.hpp) against one process, in the same run: every
// rank also steps an undecomposed engine of the same grains, the reference.
//
// Bitwise, not within a tolerance: on each rank a grain's force is the sum
// of its body force, then its contacts in ascending id (owned and ghost
// neighbours alike, the arrays being in id order), then its walls, exactly
// the additions one process makes in the same order; the ghosts carry their
// owners' bits; the rebuild test sees every rank's exact maxima. So positions,
// velocities and forces agree bit for bit. Only the kinetic energy is summed
// in another order (per rank, then over the ranks): within 1e-12 relative.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>

#include "core/petsc_runtime.hpp"
#include "dem/dem_engine.hpp"
#include "parallel/grain_exchange.hpp"

namespace fdem {
namespace {

Scene dry_box(const Vec3& upper) {
  Scene s;
  s.source_file = "test_mpi_dem";
  s.domain.upper = upper;
  s.effects.fluid = false;
  s.effects.coupling = CouplingMode::off;
  s.effects.buoyancy = false;
  s.contact.normal_stiffness = 200.0;
  s.contact.restitution = 0.5;
  s.time.dem_step = 2e-5;
  return s;
}

// `balancing`: the slab boundaries follow the grain count (GrainExchange::rebalance).
DemEngine decomposed(const Particles& grains, const Scene& scene, bool balancing = true) {
  DemEngine dem(grains, scene);
  auto exchange = std::make_unique<GrainExchange>(
      SlabPartition(scene.domain.lower, scene.domain.upper, mpi_ranks()), scene.effects.rotation);
  exchange->set_balancing(balancing);
  dem.decompose(std::move(exchange));
  return dem;
}

// Every grain of the decomposed run against the reference's of the same id, bit for bit.
void expect_bitwise(const Particles& reference, const Particles& whole) {
  ASSERT_EQ(whole.size(), reference.size());
  for (std::size_t i = 0; i < reference.size(); ++i) {
    ASSERT_EQ(whole.id[i], reference.id[i]);
    EXPECT_EQ(whole.x[i], reference.x[i]) << "id " << reference.id[i];
    EXPECT_EQ(whole.y[i], reference.y[i]) << "id " << reference.id[i];
    EXPECT_EQ(whole.z[i], reference.z[i]) << "id " << reference.id[i];
    EXPECT_EQ(whole.vx[i], reference.vx[i]) << "id " << reference.id[i];
    EXPECT_EQ(whole.vy[i], reference.vy[i]) << "id " << reference.id[i];
    EXPECT_EQ(whole.vz[i], reference.vz[i]) << "id " << reference.id[i];
    EXPECT_EQ(whole.fx[i], reference.fx[i]) << "id " << reference.id[i];
    EXPECT_EQ(whole.fz[i], reference.fz[i]) << "id " << reference.id[i];
    if (!reference.wx.empty()) {
      ASSERT_EQ(whole.wx.size(), reference.wx.size());
      EXPECT_EQ(whole.wx[i], reference.wx[i]) << "id " << reference.id[i];
      EXPECT_EQ(whole.wy[i], reference.wy[i]) << "id " << reference.id[i];
      EXPECT_EQ(whole.wz[i], reference.wz[i]) << "id " << reference.id[i];
      EXPECT_EQ(whole.tx[i], reference.tx[i]) << "id " << reference.id[i];
    }
  }
}

// 448 grains of 1.6-2.4 mm on a 2.6 mm lattice, random velocities, dropped
// into a 40 x 12 x 30 mm box (cut along x, so the bed lies across the slab
// boundary at x = 20 mm on 2 ranks): 4000 steps, 0.08 s, fall and settle.
// friction: tangential contact and rotation on (Eq. 7-10), whose slip
// history travels with the grains (DemEngine::decompose).
void dry_bed_is_one_process_bit_for_bit(bool friction) {
  std::mt19937_64 random(5);
  std::uniform_real_distribution<double> diameter(1.6e-3, 2.4e-3), speed(-0.05, 0.05);
  Particles grains;
  for (int i = 0; i < 448; ++i)
    grains.add(2e-3 + (i % 14) * 2.6e-3, 2e-3 + (i / 14 % 4) * 2.6e-3, 2e-3 + (i / 56) * 2.6e-3, diameter(random),
               2500.0, speed(random), speed(random), speed(random));
  Scene scene = dry_box(Vec3(0.04, 0.012, 0.03));
  if (friction) {
    scene.effects.tangential_contact = true;
    scene.effects.rotation = true;
    scene.contact.tangential_stiffness = 100.0;
    scene.contact.friction = 0.4;
  }
  DemEngine reference(grains, scene);
  DemEngine dem = decomposed(grains, scene);
  std::size_t most_ghosts = 0;
  for (int block = 0; block < 8; ++block) {
    reference.run(500);
    dem.run(500);
    most_ghosts = std::max(most_ghosts, dem.exchange()->ghost_count());
    dem.collect();
    expect_bitwise(reference.particles(), dem.whole_particles());
  }
  const DemDiagnostics one = reference.diagnostics(), many = dem.diagnostics();
  EXPECT_EQ(many.particles, one.particles);
  EXPECT_EQ(many.contacts, one.contacts);
  EXPECT_EQ(many.wall_contacts, one.wall_contacts);
  EXPECT_EQ(many.max_overlap_over_diameter, one.max_overlap_over_diameter);
  EXPECT_NEAR(many.kinetic_energy_j, one.kinetic_energy_j, 1e-12 * one.kinetic_energy_j);
  const double migrated = sum_over_ranks(static_cast<double>(dem.exchange()->counters().migrated));
  const int rank = mpi_rank();
  if (rank == 0)
    std::printf("dry bed%s: %zu grains, %zu contacts (%zu with walls) at t = %.3g s; largest ghost count on rank 0 %zu, "
                "%.0f migrations over the ranks, %zu redistributions\n",
                friction ? " with friction" : "", one.particles, one.contacts, one.wall_contacts, dem.time(), most_ghosts, migrated,
                dem.exchange()->counters().redistributions);
  // The comparison means something only if the bed settled in contact
  // across the slab boundary and grains changed rank.
  EXPECT_GT(one.contacts, 300u);
  if (mpi_ranks() > 1) {
    EXPECT_GT(most_ghosts, 10u);
    EXPECT_GT(migrated, 0.0);
  }
}

TEST(MpiDem, DryBedOnSeveralRanksIsOneProcessBitForBit) { dry_bed_is_one_process_bit_for_bit(false); }

// With friction the angular velocities and torques agree bit for bit too.
TEST(MpiDem, FrictionalDryBedOnSeveralRanksIsOneProcessBitForBit) { dry_bed_is_one_process_bit_for_bit(true); }

// Two 2 mm grains meet head-on at the slab boundary (x = 10 mm on 2 ranks);
// the faster one's centre crosses it while they are in contact (a soft
// spring: a 1.6 ms contact, 0.5 mm overlap), and a thin skin (0.2 mm:
// rebuilds every ~0.1 mm of relative motion) makes it change owner then.
// The boundary stays at x = 10 mm: balanced by grain count, the cut would
// sit between the two grains (one each) and neither would cross it.
TEST(MpiDem, GrainCrossingTheRankBoundaryInACollisionFollowsOneProcess) {
  Scene scene = dry_box(Vec3(0.02, 0.004, 0.004));
  scene.effects.gravity = false;
  scene.contact.normal_stiffness = 20.0;
  scene.contact.restitution = 0.9;
  scene.time.dem_step = 1e-5;
  Particles grains;
  grains.add(0.0085, 0.002, 0.002, 2e-3, 2500.0, 1.0, 0.0, 0.0);    // id 0, rank 0's at first
  grains.add(0.01155, 0.002, 0.002, 2e-3, 2500.0, 0.0, 0.0, 0.0);   // id 1, rank 1's (of 2)
  DemEngine reference(grains, scene);
  DemEngine dem = decomposed(grains, scene, /*balancing=*/false);
  reference.set_skin(2e-4);
  dem.set_skin(2e-4);
  const int rank = mpi_rank();
  bool crossed_in_contact = false, touched = false;
  for (int s = 0; s < 600; ++s) {  // 6 ms: approach 1 ms, contact ~1.6 ms, apart
    reference.step();
    dem.step();
    dem.collect();
    const Particles& one = reference.particles();
    const Particles& whole = dem.whole_particles();
    ASSERT_EQ(whole.size(), 2u);
    for (std::size_t i = 0; i < 2; ++i) {
      ASSERT_EQ(whole.x[i], one.x[i]) << "step " << s << " grain " << i;
      ASSERT_EQ(whole.vx[i], one.vx[i]) << "step " << s << " grain " << i;
    }
    const bool contact = dem.diagnostics().contacts == 1;
    touched = touched || contact;
    // Grain 0 owned by rank 1 while the two touch.
    const Particles& local = dem.particles();
    for (std::size_t i = 0; i < local.size(); ++i)
      if (local.id[i] == 0 && dem.exchange()->ghost_mask()[i] == 0 && rank == 1 && contact)
        crossed_in_contact = true;
  }
  crossed_in_contact = sum_over_ranks(crossed_in_contact ? 1.0 : 0.0) > 0.0;
  EXPECT_TRUE(touched);
  EXPECT_LT(reference.particles().vx[0], 0.2) << "grain 0 gave its momentum to grain 1";
  if (mpi_ranks() > 1) {
    EXPECT_TRUE(crossed_in_contact) << "grain 0 must change rank during the contact";
  }
}

}  // namespace
}  // namespace fdem
