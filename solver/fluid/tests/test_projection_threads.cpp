// The projection scheme (fluid/projection_scheme.hpp) on threads: its element
// loops run by layer colour (mesh/layer_colouring.hpp) and its three
// predictor solves at once, so a step must give the same bits on one thread
// and on two. A shared node written by two threads of one colour, or a
// solve that read another component's vectors, would show here as a
// differing or run-to-run varying field.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "fluid/fluid_solver.hpp"

namespace fdem {
namespace {

struct Field {
  std::vector<double> velocity, pressure;
};

// A closed water box of 14 x 14 x 12 cells (2352: above the 2048 cells from
// which the scheme's loops take threads), a blob of downward force in its
// upper half, three BDF steps of the plume's 1 ms.
Field three_steps(int threads) {
  const int before = omp_get_max_threads();
  omp_set_num_threads(threads);
  const BoxMesh mesh(Vec3(0, 0, 0), Vec3(0.1, 0.1, 0.1), {14, 14, 12});
  Scene scene;  // water, no-slip walls, BDF2
  scene.fluid.scheme = FluidScheme::projection;
  FluidSolver fluid(mesh, scene);
  std::vector<double> force(3 * static_cast<std::size_t>(mesh.num_nodes()), 0.0);
  for (Index a = 0; a < mesh.num_nodes(); ++a)
    if ((mesh.node(a) - Vec3(0.05, 0.05, 0.07)).norm() < 0.02) force[3 * static_cast<std::size_t>(a) + 2] = -500.0;
  fluid.set_body_force(force);
  for (int s = 0; s < 3; ++s) fluid.step(1e-3);
  omp_set_num_threads(before);
  return {{fluid.velocity().begin(), fluid.velocity().end()}, {fluid.pressure().begin(), fluid.pressure().end()}};
}

// How many entries differ in any bit (the vectors' lengths must agree), and the largest difference.
void expect_same_bits(const std::vector<double>& a, const std::vector<double>& b, const char* what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  std::size_t differing = 0;
  double largest = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i] != b[i]) {
      ++differing;
      largest = std::max(largest, std::abs(a[i] - b[i]));
    }
  EXPECT_EQ(differing, 0u) << what << ": " << differing << " of " << a.size()
                           << " entries differ between 1 and 2 threads, by up to " << largest;
}

TEST(ProjectionThreads, TwoThreadsGiveOneThreadsBits) {
  const Field one = three_steps(1);
  const Field two = three_steps(2);
  double speed = 0.0;
  for (double u : one.velocity) speed = std::max(speed, std::abs(u));
  EXPECT_GT(speed, 1e-4);  // the blob drives a flow (~1 mm/s after 3 ms): not a trivially equal rest state
  expect_same_bits(one.velocity, two.velocity, "velocity");
  expect_same_bits(one.pressure, two.pressure, "pressure");
}

}  // namespace
}  // namespace fdem
