// Particle mapping (Eq. 23-31, BoxMesh::locate_element) against a brute-force
// search over every element, and the tie rule on faces, edges and vertices.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "coupling/particle_mapping.hpp"
#include "mesh/box_mesh.hpp"

namespace fdem {
namespace {

// Brute force over every element, independent of the cell search: each
// element's volume coordinates from its own vertices (Eq. 28-31 as
// lambda = 1 - sum, lambda_a = grad N_a . (p - x_0)), precomputed in flat
// arrays with a bounding-box prefilter so 1e5 points stay cheap even in a
// sanitizer build.
class BruteForce {
 public:
  explicit BruteForce(const BoxMesh& mesh) : mesh_(mesh) {
    for (Index e = 0; e < mesh.num_elements(); ++e) {
      const auto& nodes = mesh.element_nodes(e);
      Vec3 lo = mesh.node(nodes[0]), hi = lo;
      for (Index n : nodes) {
        lo = lo.cwiseMin(mesh.node(n));
        hi = hi.cwiseMax(mesh.node(n));
      }
      const Vec3 x0 = mesh.node(nodes[0]);
      const BoxMesh::ShapeGradients& g = mesh.shape_gradients(e);
      for (int d = 0; d < 3; ++d) {
        box_.push_back(lo[d]);
        box_.push_back(hi[d]);
        origin_.push_back(x0[d]);
      }
      for (int a = 1; a < 4; ++a)
        for (int d = 0; d < 3; ++d) grad_.push_back(g(a, d));
    }
  }
  // Every element whose volume coordinates are all >= -tol.
  std::vector<Index> containing(const Vec3& p, double tol) const {
    std::vector<Index> out;
    for (std::size_t e = 0; e < static_cast<std::size_t>(mesh_.num_elements()); ++e) {
      const double* b = &box_[6 * e];
      if (p.x() < b[0] - 1e-9 || p.x() > b[1] + 1e-9 || p.y() < b[2] - 1e-9 || p.y() > b[3] + 1e-9 ||
          p.z() < b[4] - 1e-9 || p.z() > b[5] + 1e-9)
        continue;
      const double* o = &origin_[3 * e];
      const double dx = p.x() - o[0], dy = p.y() - o[1], dz = p.z() - o[2];
      const double* g = &grad_[9 * e];
      double rest = 1.0, smallest = 1.0;
      for (int a = 0; a < 3; ++a) {
        const double lambda = g[3 * a] * dx + g[3 * a + 1] * dy + g[3 * a + 2] * dz;
        rest -= lambda;
        smallest = std::min(smallest, lambda);
      }
      if (std::min(smallest, rest) >= -tol) out.push_back(static_cast<Index>(e));
    }
    return out;
  }

 private:
  const BoxMesh& mesh_;
  std::vector<double> box_, origin_, grad_;
};

TEST(Mapping, RandomPointsMatchBruteForceSearch) {
  // 1e5 uniform points in a 5 x 4 x 3 box of non-cubic cells (300 elements, both layouts).
  const BoxMesh mesh(Vec3(-0.01, 0.02, 0.0), Vec3(0.04, 0.06, 0.09), {5, 4, 3});
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> ux(-0.01, 0.04), uy(0.02, 0.06), uz(0.0, 0.09);
  // A point is "interior" when the brute force finds exactly one element with
  // all coordinates above 1e-12 (round-off of the coordinates is ~1e-16);
  // otherwise it lies within 1e-12 of a face and only containment is checked.
  const BruteForce brute(mesh);
  long interior = 0;
  for (int n = 0; n < 100000; ++n) {
    const Vec3 p(ux(rng), uy(rng), uz(rng));
    const Index found = mesh.locate_element(p);
    ASSERT_GE(found, 0);
    const auto strict = brute.containing(p, -1e-12);
    if (strict.size() == 1) {
      ++interior;
      ASSERT_EQ(found, strict[0]) << p.transpose();
    } else {
      ASSERT_GE(mesh.volume_coordinates(found, p).minCoeff(), -1e-12) << p.transpose();
    }
  }
  EXPECT_GT(interior, 99000);  // almost all random points are interior
}

TEST(Mapping, PaperMeshRandomPointsLieInTheirElement) {
  // The settling mesh (44 x 44 x 80 mm, 4 mm cells, 12100 tetrahedra): the
  // located element contains the point (coordinates >= -1e-12, round-off).
  // 2e4 points: the 1e5-point brute-force comparison is the test above.
  const BoxMesh mesh(Vec3(0, 0, 0), Vec3(0.044, 0.044, 0.080), {11, 11, 20});
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int n = 0; n < 20000; ++n) {
    const Vec3 p(0.044 * u(rng), 0.044 * u(rng), 0.080 * u(rng));
    const Index e = mesh.locate_element(p);
    ASSERT_GE(e, 0);
    ASSERT_GE(mesh.volume_coordinates(e, p).minCoeff(), -1e-12) << p.transpose();
  }
}

// The documented rule, stated independently of the implementation: the cell
// is the one "above" (index = floor(x / h), the last cell on the upper box
// faces); within it the central tetrahedron wins whenever it contains the point.
Index expected_by_tie_rule(const BoxMesh& mesh, const Vec3& p) {
  std::array<int, 3> ijk{};
  for (int d = 0; d < 3; ++d) {
    const auto c = static_cast<std::size_t>(d);
    int i = static_cast<int>(std::floor((p[d] - mesh.lower()[d]) / mesh.cell_size()[d]));
    ijk[c] = std::min(i, mesh.cells()[c] - 1);
  }
  const Index cell = mesh.cell_index(ijk[0], ijk[1], ijk[2]);
  std::vector<Index> in_cell;
  for (Index local = 0; local < 5; ++local)
    if (mesh.volume_coordinates(5 * cell + local, p).minCoeff() >= 0.0) in_cell.push_back(5 * cell + local);
  if (in_cell.empty()) return -2;
  return in_cell.front();  // the central one (local 0) first when it contains p
}

TEST(Mapping, FacesEdgesAndVerticesFollowTheTieRule) {
  // Cells of 0.25 m: node coordinates, edge midpoints and the face points
  // (a + b + 2c)/4 are exact binary fractions and the volume coordinates are
  // computed exactly, so ties are real ties, not round-off.
  const BoxMesh mesh(Vec3(0, 0, 0), Vec3(1, 1, 1), {4, 4, 4});
  long checked = 0;
  for (Index e = 0; e < mesh.num_elements(); ++e) {
    const auto& nodes = mesh.element_nodes(e);
    std::vector<Vec3> points;
    for (int a = 0; a < 4; ++a) {
      const Vec3 xa = mesh.node(nodes[static_cast<std::size_t>(a)]);
      points.push_back(xa);  // vertex
      for (int b = a + 1; b < 4; ++b) {
        const Vec3 xb = mesh.node(nodes[static_cast<std::size_t>(b)]);
        points.push_back(0.5 * (xa + xb));  // edge midpoint
        for (int c = b + 1; c < 4; ++c)     // a point inside face abc
          points.push_back(0.25 * (xa + xb + 2.0 * mesh.node(nodes[static_cast<std::size_t>(c)])));
      }
    }
    for (const Vec3& p : points) {
      const Index found = mesh.locate_element(p);
      ASSERT_EQ(found, expected_by_tie_rule(mesh, p)) << p.transpose();
      ASSERT_EQ(found, mesh.locate_element(p));  // deterministic
      ++checked;
    }
  }
  EXPECT_EQ(checked, 14 * mesh.num_elements());  // 4 vertices, 6 edges, 4 faces each
}

TEST(Mapping, OutsideTheBoxIsMinusOneAndCounted) {
  const BoxMesh mesh(Vec3(0, 0, 0), Vec3(1, 1, 1), {2, 2, 2});
  Particles p;
  p.x = {0.5, 1.5, 0.5};
  p.y = {0.5, 0.5, -1e-9};
  p.z = {0.5, 0.5, 0.5};
  ParticleMapping m;
  m.update(mesh, p);
  EXPECT_GE(m.element[0], 0);
  EXPECT_EQ(m.element[1], -1);
  EXPECT_EQ(m.element[2], -1);
  EXPECT_EQ(m.outside, 2);
  // Weights are the volume coordinates (they sum to 1, P1 partition of unity).
  const auto& w = m.weights[0];
  EXPECT_NEAR(w[0] + w[1] + w[2] + w[3], 1.0, 1e-15);
}

}  // namespace
}  // namespace fdem
