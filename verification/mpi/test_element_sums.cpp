// The per-element sums completed between ranks (parallel/element_sums.hpp)
// against brute force, on the ranks mpirun gives (CI: 2). Every rank draws
// the same random grains, so each can compute every rank's partial sums (the
// grains owned by a slab, ascending id, as the exchange leaves them) and
// from them the complete field p_0 + p_1 + ... in rank order: bit for bit
// where the rank needs the element, 0 elsewhere, and the whole field on
// rank 0 after the gather. The mesh is cut along z (the fluid's layers and
// the grains' slabs both z intervals) and along x (every rank's grains meet
// every rank's fluid layers). The exchange reads the fields only at the
// elements the caller lists as touched: grains on the rank faces, summing
// into every cell their bounding box meets (across the face), check that
// those lists reach every element a partial sum lands in.
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

// Grains centred on the slab faces (exactly, a rounding either side, and
// up to a cutoff either side) and random along the other axes: what the
// contribution bands' edges and the touched lists must get right.
Particles grains_on_faces(const SlabPartition& slabs, std::size_t per_face, const Vec3& lower, const Vec3& upper,
                          double cutoff, unsigned seed) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0), size(0.5e-3, 1.0e-3);
  Particles p;
  const int axis = slabs.axis();
  for (int b = 1; b < slabs.ranks(); ++b) {
    const double face = slabs.boundary(b);
    const std::array<double, 7> along{face, std::nextafter(face, -1.0), std::nextafter(face, 2.0), face - 0.25 * cutoff,
                                      face + 0.25 * cutoff, face - 0.9 * cutoff, face + 0.9 * cutoff};
    for (std::size_t i = 0; i < per_face; ++i) {
      Vec3 at = lower + (upper - lower).cwiseProduct(Vec3(unit(random), unit(random), unit(random)));
      at[axis] = along[i % along.size()];
      p.add(at.x(), at.y(), at.z(), size(random), 1e-6, unit(random), unit(random), unit(random));
      p.id.push_back(static_cast<Index>(p.size() - 1));
    }
  }
  return p;
}

// Partial sums of the grains `counted`, as the coupling's: `reach` false,
// into the element of the centre (centre porosity, source term, exchange);
// true, into every element of every cell the grain's bounding box touches
// (the intersection porosity), the touched list naming each.
struct Deposit {
  std::vector<double> force, solid;
  std::vector<Index> touched;
};
template <class Counted>
Deposit deposit(const BoxMesh& mesh, const Particles& p, const Counted& counted, bool reach) {
  const auto ne = static_cast<std::size_t>(mesh.num_elements());
  Deposit d{std::vector<double>(3 * ne, 0.0), std::vector<double>(ne, 0.0), {}};
  const auto add = [&](std::size_t i, Index e, double weight) {
    const auto k = static_cast<std::size_t>(e);
    d.force[3 * k] += weight * p.vx[i];
    d.force[3 * k + 1] += weight * p.vy[i];
    d.force[3 * k + 2] += weight * p.vz[i];
    d.solid[k] += weight * p.diameter[i];
    d.touched.push_back(e);
  };
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!counted(i)) continue;
    const Vec3 c(p.x[i], p.y[i], p.z[i]);
    if (!reach) {
      const Index e = mesh.locate_element(c);
      if (e >= 0) add(i, e, 1.0);
      continue;
    }
    std::array<int, 3> first{}, last{};
    for (int a = 0; a < 3; ++a) {
      const double r = 0.5 * p.diameter[i], h = mesh.cell_size()[a], lo = mesh.lower()[a];
      const int n = mesh.cells()[static_cast<std::size_t>(a)] - 1;
      first[static_cast<std::size_t>(a)] = std::clamp(static_cast<int>(std::floor((c[a] - r - lo) / h)), 0, n);
      last[static_cast<std::size_t>(a)] = std::clamp(static_cast<int>(std::floor((c[a] + r - lo) / h)), 0, n);
    }
    for (int k = first[2]; k <= last[2]; ++k)
      for (int j = first[1]; j <= last[1]; ++j)
        for (int ci = first[0]; ci <= last[0]; ++ci) {
          const Index cell = mesh.cell_index(ci, j, k);
          for (Index e = 5 * cell; e < 5 * cell + 5; ++e) add(i, e, 1.0 + 0.1 * static_cast<double>(e - 5 * cell));
        }
  }
  return d;
}

void check_sums(const Vec3& upper, const std::array<int, 3>& cells, bool on_faces) {
  const int ranks = mpi_ranks(), rank = mpi_rank();
  const Vec3 lower = Vec3::Zero();
  const BoxMesh mesh(lower, upper, cells);
  const double cutoff = 2.0e-3;
  GrainExchange grains(SlabPartition(lower, upper, ranks), false);
  grains.set_cutoff(cutoff);
  const Particles all =
      on_faces ? grains_on_faces(grains.slabs(), 700, lower, upper, cutoff, 13) : random_grains(3000, lower, upper, 11);
  Particles local = all;
  grains.redistribute(local);
  std::vector<std::pair<Index, Index>> rows;
  for (int r = 0; r < ranks; ++r) rows.push_back(PetscLinearSolver::owned_node_range(mesh.num_nodes(), r, ranks));
  const ElementSums sums(MeshCells{mesh.cells(), mesh.lower(), mesh.cell_size()}, rows, grains);

  // Two fields, as the source term's: 3 values and 1 value per element.
  const auto ne = static_cast<std::size_t>(mesh.num_elements());
  Deposit here = deposit(mesh, local, [&](std::size_t i) { return grains.ghost_mask()[i] == 0; }, on_faces);
  std::vector<double>& force = here.force;
  std::vector<double>& solid = here.solid;
  sums.sum_over_ranks(std::vector<ElementSums::Field>{{force, 3}, {solid, 1}}, here.touched);

  // Brute force: each rank's partial sums from the whole set, added in rank order from +0.
  std::vector<double> whole_force(3 * ne, 0.0), whole_solid(ne, 0.0);
  std::size_t across = 0;         // elements a rank's grains touch in a cell centred in another slab
  std::size_t rank_touched = 0;   // elements with a rank's non-zero partial sum, over the ranks
  for (int r = 0; r < ranks; ++r) {
    const Deposit d =
        deposit(mesh, all, [&](std::size_t i) { return grains.slabs().owner(all.x[i], all.y[i], all.z[i]) == r; },
                on_faces);
    for (std::size_t k = 0; k < 3 * ne; ++k) whole_force[k] += d.force[k];
    for (std::size_t k = 0; k < ne; ++k) {
      whole_solid[k] += d.solid[k];
      if (d.solid[k] != 0.0) ++rank_touched;
      if (d.solid[k] != 0.0 && grains.slabs().owner(mesh.element_centroid(static_cast<Index>(k))) != r) ++across;
    }
  }
  if (on_faces) {
    EXPECT_GT(across, 0u) << "the face case deposits across the faces";
  }
  // Every element this rank's grains (owned and ghosts) sit in is needed here.
  for (std::size_t i = 0; i < local.size(); ++i) {
    const Index e = mesh.locate_element(Vec3(local.x[i], local.y[i], local.z[i]));
    if (e >= 0) {
      EXPECT_TRUE(sums.needs_element(e)) << "grain " << local.id[i] << " in element " << e;
    }
  }
  std::size_t needed = 0, owned = 0;
  for (std::size_t k = 0; k < ne; ++k) {
    const auto e = static_cast<Index>(k);
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
    // rank's touched elements to every other rank, far below the whole mesh's 4 x 8 bytes per element.
    EXPECT_LE(counts[1], static_cast<double>((ranks - 1) * rank_touched * 5 * sizeof(double)));
    EXPECT_GT(counts[1], 0.0);
    // The read band spans the neighbours' slabs too (element_sums.hpp): on
    // 2 ranks each needs the whole mesh, from 3 ranks on a part only.
    if (ranks > 2) {
      EXPECT_LT(needed, ne) << "a rank needs part of the mesh only";
    }
  }
}

// The nodal counterpart (the shape-function and diffused porosity's solid):
// each grain's value to the 4 corners of its element, with weights as P1
// volume coordinates are; complete on the corners of the needed elements,
// or (everywhere, the diffused scheme's solve) on every node of every rank.
void check_node_sums(const Vec3& upper, const std::array<int, 3>& cells, bool on_faces, bool everywhere) {
  const int ranks = mpi_ranks();
  const Vec3 lower = Vec3::Zero();
  const BoxMesh mesh(lower, upper, cells);
  const double cutoff = 2.0e-3;
  GrainExchange grains(SlabPartition(lower, upper, ranks), false);
  grains.set_cutoff(cutoff);
  const Particles all =
      on_faces ? grains_on_faces(grains.slabs(), 700, lower, upper, cutoff, 17) : random_grains(3000, lower, upper, 19);
  Particles local = all;
  grains.redistribute(local);
  std::vector<std::pair<Index, Index>> rows;
  for (int r = 0; r < ranks; ++r) rows.push_back(PetscLinearSolver::owned_node_range(mesh.num_nodes(), r, ranks));
  const ElementSums sums(MeshCells{mesh.cells(), mesh.lower(), mesh.cell_size()}, rows, grains);
  const auto nn = static_cast<std::size_t>(mesh.num_nodes());
  const auto deposit_nodes = [&](const Particles& p, const auto& counted, std::vector<double>& solid,
                                 std::vector<Index>& touched) {
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (!counted(i)) continue;
      const Index e = mesh.locate_element(Vec3(p.x[i], p.y[i], p.z[i]));
      if (e < 0) continue;
      const auto& corners = mesh.element_nodes(e);
      for (std::size_t a = 0; a < 4; ++a) {
        solid[static_cast<std::size_t>(corners[a])] += (0.1 + 0.2 * static_cast<double>(a)) * p.diameter[i];
        touched.push_back(corners[a]);
      }
    }
  };
  std::vector<double> solid(nn, 0.0);
  std::vector<Index> touched;
  deposit_nodes(local, [&](std::size_t i) { return grains.ghost_mask()[i] == 0; }, solid, touched);
  sums.sum_nodes_over_ranks(std::vector<ElementSums::Field>{{solid, 1}}, touched, everywhere);
  std::vector<double> whole(nn, 0.0);
  for (int r = 0; r < ranks; ++r) {
    std::vector<double> s(nn, 0.0);
    std::vector<Index> ignored;
    deposit_nodes(all, [&](std::size_t i) { return grains.slabs().owner(all.x[i], all.y[i], all.z[i]) == r; }, s,
                  ignored);
    for (std::size_t k = 0; k < nn; ++k) whole[k] += s[k];
  }
  // The corners of every needed element are needed nodes.
  for (Index e = 0; e < mesh.num_elements(); ++e)
    if (sums.needs_element(e))
      for (Index n : mesh.element_nodes(e)) {
        EXPECT_TRUE(sums.needs_node(n)) << "node " << n << " of needed element " << e;
      }
  std::size_t needed = 0, nonzero = 0;
  for (std::size_t k = 0; k < nn; ++k) {
    const auto n = static_cast<Index>(k);
    if (whole[k] != 0.0) ++nonzero;
    if (everywhere || sums.needs_node(n)) {
      ++needed;
      EXPECT_EQ(solid[k], whole[k]) << "node " << n;
    } else {
      EXPECT_EQ(solid[k], 0.0) << "node " << n;
    }
  }
  EXPECT_GT(nonzero, 0u);
  if (ranks > 2 && !everywhere) {
    EXPECT_LT(needed, nn) << "a rank needs part of the mesh only";
  }
  // Records of 2 doubles (node, value), for the touched nodes only, at most each to every other rank.
  double traffic[2] = {static_cast<double>(sums.bytes_sent()), static_cast<double>(touched.size())};
  grains.sum_over_ranks(traffic);
  if (ranks > 1) {
    EXPECT_GT(traffic[0], 0.0);
    EXPECT_LE(traffic[0], (ranks - 1) * traffic[1] * 2 * sizeof(double));
  }
}

TEST(ElementSums, NodesMatchBruteForceWhereNeeded) {
  check_node_sums(Vec3(0.03, 0.02, 0.1), {6, 4, 20}, false, false);
  check_node_sums(Vec3(0.03, 0.02, 0.1), {6, 4, 20}, true, false);
  check_node_sums(Vec3(0.1, 0.02, 0.03), {20, 4, 6}, true, false);
}
TEST(ElementSums, NodesEverywhereMatchBruteForceOnEveryNode) {
  check_node_sums(Vec3(0.03, 0.02, 0.1), {6, 4, 20}, false, true);
  check_node_sums(Vec3(0.03, 0.02, 0.1), {6, 4, 20}, true, true);
}

TEST(ElementSums, CutAlongZMatchesBruteForce) { check_sums(Vec3(0.03, 0.02, 0.1), {6, 4, 20}, false); }
TEST(ElementSums, CutAlongXMatchesBruteForce) { check_sums(Vec3(0.1, 0.02, 0.03), {20, 4, 6}, false); }
// Grains on and beside the rank faces summing into every cell their bounding
// box touches (the intersection porosity's reach), across the face too: the
// touched lists carry those elements, and the sums match brute force bit for bit.
TEST(ElementSums, GrainsOnTheRankFacesReachingAcrossMatchBruteForce) {
  check_sums(Vec3(0.03, 0.02, 0.1), {6, 4, 20}, true);
}
TEST(ElementSums, GrainsOnTheRankFacesCutAlongXMatchBruteForce) { check_sums(Vec3(0.1, 0.02, 0.03), {20, 4, 6}, true); }

}  // namespace
}  // namespace fdem
