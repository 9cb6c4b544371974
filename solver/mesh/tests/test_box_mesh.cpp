#include "mesh/box_mesh.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>

using fdem::BoxMesh;
using fdem::Index;
using fdem::Vec3;

namespace {
BoxMesh sample_mesh() { return BoxMesh(Vec3(-0.01, 0.0, 0.02), Vec3(0.034, 0.044, 0.1), {4, 3, 5}); }
}  // namespace

TEST(BoxMesh, VolumesArePositiveAndSumToTheBox) {
  const BoxMesh mesh = sample_mesh();
  double total = 0.0;
  const double cell = mesh.cell_size().prod();
  for (Index e = 0; e < mesh.num_elements(); ++e) {
    const double v = mesh.element_volume(e);
    ASSERT_GT(v, 0.0) << "element " << e;
    // central tetrahedron = 1/3 of the cell, corners = 1/6 (closed form of the 5-tet split)
    EXPECT_NEAR(v / cell, e % 5 == 0 ? 1.0 / 3.0 : 1.0 / 6.0, 1e-12);
    total += v;
  }
  const double box = (mesh.upper() - mesh.lower()).prod();
  EXPECT_NEAR(total, box, 1e-12 * box);
}

TEST(BoxMesh, InteriorFacesAreSharedByExactlyTwoElements) {
  const BoxMesh mesh = sample_mesh();
  std::map<std::array<Index, 3>, int> faces;
  for (Index e = 0; e < mesh.num_elements(); ++e) {
    const auto& n = mesh.element_nodes(e);
    for (int skip = 0; skip < 4; ++skip) {
      std::array<Index, 3> f{};
      int c = 0;
      for (int a = 0; a < 4; ++a)
        if (a != skip) f[static_cast<std::size_t>(c++)] = n[static_cast<std::size_t>(a)];
      std::sort(f.begin(), f.end());
      ++faces[f];
    }
  }
  // Boundary faces: each box face of an a x b cell grid carries 2ab triangles.
  const auto [nx, ny, nz] = mesh.cells();
  const int boundary_expected = 2 * 2 * (nx * ny + ny * nz + nx * nz);
  int boundary = 0;
  for (const auto& [f, count] : faces) {
    ASSERT_LE(count, 2);
    if (count == 1) ++boundary;
  }
  EXPECT_EQ(boundary, boundary_expected);
}

TEST(BoxMesh, ShapeFunctionsArePartitionOfUnityAndNodal) {
  const BoxMesh mesh = sample_mesh();
  for (Index e = 0; e < mesh.num_elements(); e += 7) {
    const auto& nodes = mesh.element_nodes(e);
    for (int a = 0; a < 4; ++a) {
      const Eigen::Vector4d l = mesh.volume_coordinates(e, mesh.node(nodes[static_cast<std::size_t>(a)]));
      for (int b = 0; b < 4; ++b) EXPECT_NEAR(l[b], a == b ? 1.0 : 0.0, 1e-12);
    }
    EXPECT_NEAR(mesh.shape_gradients(e).colwise().sum().norm(), 0.0, 1e-9);
  }
}

TEST(BoxMesh, LocateElementAgreesWithBruteForceOnRandomPoints) {
  const BoxMesh mesh = sample_mesh();
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int n = 0; n < 20000; ++n) {
    const Vec3 p = mesh.lower() + Vec3(u(rng), u(rng), u(rng)).cwiseProduct(mesh.upper() - mesh.lower());
    const Index e = mesh.locate_element(p);
    ASSERT_GE(e, 0);
    // Brute force: p must have all volume coordinates >= 0 in e (to round-off).
    EXPECT_GE(mesh.volume_coordinates(e, p).minCoeff(), -1e-12) << "point " << n;
  }
}

TEST(BoxMesh, PointsOutsideTheBoxAreNotLocated) {
  const BoxMesh mesh = sample_mesh();
  EXPECT_EQ(mesh.locate_element(mesh.lower() - Vec3(1e-9, 0, 0)), -1);
  EXPECT_EQ(mesh.locate_element(mesh.upper() + Vec3(0, 0, 1e-9)), -1);
  EXPECT_EQ(mesh.locate_element(Vec3(std::nan(""), 0.0, 0.05)), -1);
  EXPECT_GE(mesh.locate_element(mesh.upper()), 0);  // the upper corner belongs to the last cell
}

TEST(BoxMesh, FaceNodeCountsMatchTheGrid) {
  const BoxMesh mesh = sample_mesh();
  const auto [nx, ny, nz] = mesh.cells();
  EXPECT_EQ(mesh.face_nodes(fdem::BoxFace::x_min).size(), static_cast<std::size_t>((ny + 1) * (nz + 1)));
  EXPECT_EQ(mesh.face_nodes(fdem::BoxFace::z_max).size(), static_cast<std::size_t>((nx + 1) * (ny + 1)));
  for (Index n : mesh.face_nodes(fdem::BoxFace::y_max)) EXPECT_DOUBLE_EQ(mesh.node(n).y(), mesh.upper().y());
}
