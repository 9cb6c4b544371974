// The per-element sums completed between ranks (parallel/element_sums.hpp)
// against brute force, on the ranks mpirun gives (CI: 2). Every rank draws
// the same random grains, so each can compute every rank's partial sums (the
// grains owned by a slab, ascending id, as the exchange leaves them) and
// from them the complete field p_0 + p_1 + ... in rank order: bit for bit
// where the rank needs the element, 0 elsewhere, and the whole field on
// rank 0 after the gather. The mesh is cut along z (the fluid's layers and
// the grains' slabs both z intervals) and along x (every rank's grains meet
// every rank's fluid layers).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "core/petsc_runtime.hpp"
#include "fluid/petsc_linear_solver.hpp"
#include "mesh/box_mesh.hpp"
#include "parallel/element_sums.hpp"
#include "parallel/grain_exchange.hpp"

namespace fdem {
namespace {

Particles random_grains(std::size_t count, const Vec3& lower, const Vec3& upper, unsigned seed) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0), size(0.5e-3, 1.0e-3);
  Particles p;
  for (std::size_t i = 0; i < count; ++i) {
    const Vec3 at = lower + (upper - lower).cwiseProduct(Vec3(unit(random), unit(random), unit(random)));
    p.add(at.x(), at.y(), at.z(), size(random), 1e-6, unit(random), unit(random), unit(random));
    p.id.push_back(static_cast<Index>(i));
  }
  return p;
}

void check_sums(const Vec3& upper, const std::array<int, 3>& cells) {
  const int ranks = mpi_ranks(), rank = mpi_rank();
  const Vec3 lower = Vec3::Zero();
  const BoxMesh mesh(lower, upper, cells);
  const double cutoff = 2.0e-3;
  const Particles all = random_grains(3000, lower, upper, 11);
  GrainExchange grains(SlabPartition(lower, upper, ranks), false);
  grains.set_cutoff(cutoff);
  Particles local = all;
  grains.redistribute(local);
  std::vector<std::pair<Index, Index>> rows;
  for (int r = 0; r < ranks; ++r) rows.push_back(PetscLinearSolver::owned_node_range(mesh.num_nodes(), r, ranks));
  const ElementSums sums(MeshCells{mesh.cells(), mesh.lower(), mesh.cell_size()}, rows, grains);

  // Two fields, as the source term's: 3 values and 1 value per element.
  const auto ne = static_cast<std::size_t>(mesh.num_elements());
  const auto deposit = [&](const Particles& p, const auto& counted, std::vector<double>& force,
                           std::vector<double>& solid) {
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (!counted(i)) continue;
      const Index e = mesh.locate_element(Vec3(p.x[i], p.y[i], p.z[i]));
      if (e < 0) continue;
      const auto k = static_cast<std::size_t>(e);
      force[3 * k] += p.vx[i];
      force[3 * k + 1] += p.vy[i];
      force[3 * k + 2] += p.vz[i];
      solid[k] += p.diameter[i];
    }
  };
  std::vector<double> force(3 * ne, 0.0), solid(ne, 0.0);
  deposit(local, [&](std::size_t i) { return grains.ghost_mask()[i] == 0; }, force, solid);
  sums.sum_over_ranks(std::vector<ElementSums::Field>{{force, 3}, {solid, 1}});

  // Brute force: each rank's partial sums from the whole set, added in rank order from +0.
  std::vector<double> whole_force(3 * ne, 0.0), whole_solid(ne, 0.0);
  for (int r = 0; r < ranks; ++r) {
    std::vector<double> f(3 * ne, 0.0), s(ne, 0.0);
    deposit(all, [&](std::size_t i) { return grains.slabs().owner(all.x[i], all.y[i], all.z[i]) == r; }, f, s);
    for (std::size_t k = 0; k < 3 * ne; ++k) whole_force[k] += f[k];
    for (std::size_t k = 0; k < ne; ++k) whole_solid[k] += s[k];
  }
  // Every element this rank's grains (owned and ghosts) sit in is needed here.
  for (std::size_t i = 0; i < local.size(); ++i) {
    const Index e = mesh.locate_element(Vec3(local.x[i], local.y[i], local.z[i]));
    if (e >= 0) {
      EXPECT_TRUE(sums.needs_element(e)) << "grain " << local.id[i] << " in element " << e;
    }
  }
  std::size_t needed = 0, owned = 0, nonzero = 0;
  for (std::size_t k = 0; k < ne; ++k) {
    const auto e = static_cast<Index>(k);
    if (whole_solid[k] != 0.0) ++nonzero;
    if (sums.owns_element(e)) {
      ++owned;
      EXPECT_TRUE(sums.needs_element(e)) << "an owned element is complete on its owner: " << e;
    }
    if (sums.needs_element(e)) {
      ++needed;
      EXPECT_EQ(solid[k], whole_solid[k]) << "element " << e;
      for (std::size_t c = 0; c < 3; ++c) EXPECT_EQ(force[3 * k + c], whole_force[3 * k + c]) << "element " << e;
    } else {
      EXPECT_EQ(solid[k], 0.0) << "element " << e;
    }
  }
  // The owned blocks tile the mesh; the whole field comes back on rank 0.
  double counts[2] = {static_cast<double>(owned), static_cast<double>(sums.bytes_sent())};
  grains.sum_over_ranks(counts);
  EXPECT_EQ(counts[0], static_cast<double>(ne));
  const std::vector<double> gathered = sums.gather_elements(solid, 1);
  if (rank == 0) {
    ASSERT_EQ(gathered.size(), ne);
    for (std::size_t k = 0; k < ne; ++k) EXPECT_EQ(gathered[k], whole_solid[k]) << "element " << k;
  } else {
    EXPECT_TRUE(gathered.empty());
  }
  if (ranks > 1) {
    // Records of 5 doubles for elements that hold grains: at most every
    // touched element to every other rank, far below the whole mesh's 4 x 8 bytes per element.
    EXPECT_LE(counts[1], static_cast<double>((ranks - 1) * nonzero * 5 * sizeof(double)));
    EXPECT_GT(counts[1], 0.0);
    // The read band spans the neighbours' slabs too (element_sums.hpp): on
    // 2 ranks each needs the whole mesh, from 3 ranks on a part only.
    if (ranks > 2) {
      EXPECT_LT(needed, ne) << "a rank needs part of the mesh only";
    }
  }
}

TEST(ElementSums, CutAlongZMatchesBruteForce) { check_sums(Vec3(0.03, 0.02, 0.1), {6, 4, 20}); }
TEST(ElementSums, CutAlongXMatchesBruteForce) { check_sums(Vec3(0.1, 0.02, 0.03), {20, 4, 6}); }

}  // namespace
}  // namespace fdem
