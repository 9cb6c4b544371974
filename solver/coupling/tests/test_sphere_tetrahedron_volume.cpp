// The exact ball-tetrahedron intersection volume (coupling/sphere_tetrahedron_volume.hpp)
// against Monte-Carlo on random configurations and against closed forms:
// whole ball, whole tetrahedron, disjoint, and the ball cut by a box face
// (sphere minus a cap) summed over the five tetrahedra of every cell.
#include "coupling/sphere_tetrahedron_volume.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include <Eigen/Dense>

#include "mesh/box_mesh.hpp"

namespace fdem {
namespace {

double ball_volume(double r) { return 4.0 / 3.0 * pi * r * r * r; }

std::array<Vec3, 4> element_vertices(const BoxMesh& mesh, Index e) {
  const auto& n = mesh.element_nodes(e);
  return {mesh.node(n[0]), mesh.node(n[1]), mesh.node(n[2]), mesh.node(n[3])};
}

double over_all_elements(const BoxMesh& mesh, const Vec3& c, double r) {
  double sum = 0.0;
  for (Index e = 0; e < mesh.num_elements(); ++e) sum += sphere_tetrahedron_volume(c, r, element_vertices(mesh, e));
  return sum;
}

// Random tetrahedra in [-1, 1]^3, balls of radius 0.2-1 centred in [-0.7, 0.7]^3
// (every kind of cut: caps, wedges, corners, tetrahedra inside the ball).
// Monte-Carlo with 4e5 uniform points in the ball's bounding cube: the
// estimate's standard deviation is sigma = 8 R^3 sqrt(p (1 - p) / N); the
// exact volume must lie within 5 sigma of it in every case (a wrong term in
// Eq. 2-4 of the header shifts the volume by far more than sigma, 1e-3 of the
// cube; 5 sigma: a false alarm in 30 cases has odds below 2e-5).
TEST(SphereTetrahedronVolume, MatchesMonteCarloOnRandomConfigurations) {
  std::mt19937_64 rng(2016);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  constexpr long kSamples = 400000;
  double worst_sigmas = 0.0;
  int cut_cases = 0;
  for (int c = 0; c < 30; ++c) {
    std::array<Vec3, 4> v;
    for (Vec3& x : v) x = Vec3(u(rng), u(rng), u(rng));
    const Vec3 centre = 0.7 * Vec3(u(rng), u(rng), u(rng));
    const double r = 0.2 + 0.4 * (u(rng) + 1.0);
    const double exact = sphere_tetrahedron_volume(centre, r, v);
    Eigen::Matrix3d edges;
    edges << v[1] - v[0], v[2] - v[0], v[3] - v[0];
    const Eigen::Matrix3d to_local = edges.inverse();
    long hits = 0;
    for (long k = 0; k < kSamples; ++k) {
      const Vec3 p = centre + r * Vec3(u(rng), u(rng), u(rng));
      if ((p - centre).squaredNorm() > r * r) continue;
      const Vec3 l = to_local * (p - v[0]);
      if (l.minCoeff() >= 0.0 && l.sum() <= 1.0) ++hits;
    }
    const double cube = 8.0 * r * r * r, fraction = static_cast<double>(hits) / kSamples;
    const double estimate = cube * fraction;
    const double sigma = cube * std::sqrt(std::max(fraction * (1.0 - fraction), 1.0 / kSamples) / kSamples);
    worst_sigmas = std::max(worst_sigmas, std::abs(exact - estimate) / sigma);
    if (exact > 0.0 && exact < ball_volume(r) * (1.0 - 1e-12) && exact < std::abs(edges.determinant()) / 6.0)
      ++cut_cases;
    EXPECT_NEAR(exact, estimate, 5.0 * sigma) << "case " << c;
  }
  std::printf("30 random cases (%d cut), worst |exact - Monte-Carlo| = %.2f sigma\n", cut_cases, worst_sigmas);
  EXPECT_GE(cut_cases, 15);  // most cases cut both the ball and the tetrahedron
}

TEST(SphereTetrahedronVolume, ClosedFormLimits) {
  const std::array<Vec3, 4> tet{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  // Ball inside: its own volume.
  EXPECT_DOUBLE_EQ(sphere_tetrahedron_volume(Vec3(0.2, 0.2, 0.2), 0.05, tet), ball_volume(0.05));
  // Tetrahedron inside a ball that holds it (no face is beyond R, so every
  // term of Eq. 4 runs): the tetrahedron's volume 1/6, to round-off.
  EXPECT_NEAR(sphere_tetrahedron_volume(Vec3(0.25, 0.25, 0.25), 2.0, tet), 1.0 / 6.0, 1e-14);
  // Disjoint.
  EXPECT_EQ(sphere_tetrahedron_volume(Vec3(3, 3, 3), 1.0, tet), 0.0);
  // Either orientation of the vertices.
  const std::array<Vec3, 4> flipped{tet[1], tet[0], tet[2], tet[3]};
  EXPECT_NEAR(sphere_tetrahedron_volume(Vec3(0.1, 0.3, 0.0), 0.4, tet),
              sphere_tetrahedron_volume(Vec3(0.1, 0.3, 0.0), 0.4, flipped), 1e-16);
  // Degenerate tetrahedron.
  EXPECT_EQ(sphere_tetrahedron_volume(Vec3(0, 0, 0), 1.0, {tet[0], tet[1], tet[2], Vec3(0.3, 0.3, 0)}), 0.0);
}

// The five tetrahedra of each cell tile it, so the volumes over a box mesh sum
// to the ball inside the box: the whole ball anywhere inside (random centres,
// cutting many elements), and the ball minus a cap of height a where a box
// face cuts it, pi a^2 (3R - a) / 3. Round-off only: 1e-12 relative.
TEST(SphereTetrahedronVolume, TetrahedraOfABoxMeshSumToTheBallInsideTheBox) {
  const BoxMesh mesh(Vec3::Zero(), Vec3(3, 3, 3), {3, 3, 3});
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int c = 0; c < 20; ++c) {
    const double r = 0.2 + 0.7 * u(rng);
    const Vec3 centre = Vec3::Constant(r) + (3.0 - 2.0 * r) * Vec3(u(rng), u(rng), u(rng));
    EXPECT_NEAR(over_all_elements(mesh, centre, r) / ball_volume(r), 1.0, 1e-12) << "case " << c;
  }
  const double r = 0.8;
  for (double depth : {0.1, 0.5, 0.8, 1.3}) {  // how far the ball pokes out through x = 0
    const Vec3 centre(r - depth, 1.37, 1.61);
    const double cap = pi * depth * depth * (3.0 * r - depth) / 3.0;
    EXPECT_NEAR(over_all_elements(mesh, centre, r) / (ball_volume(r) - cap), 1.0, 1e-12) << "depth " << depth;
  }
}

}  // namespace
}  // namespace fdem
