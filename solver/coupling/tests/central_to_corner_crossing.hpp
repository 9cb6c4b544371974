#pragma once
// Test support: the two points on either side of the face between a cell's
// central tetrahedron and a corner one, found by bisection along the line
// from the centre of cell (0,0,0) (an even cell, cell size h) toward its
// local vertex 1 = (h, 0, 0): `before` lies in the central tetrahedron,
// `after` in the corner one, about 1e-19 m apart.
#include <gtest/gtest.h>

#include "core/types.hpp"
#include "mesh/box_mesh.hpp"

namespace fdem::test_support {

struct FaceCrossing {
  Vec3 before;  // in the central tetrahedron (local index 0)
  Vec3 after;   // in a corner tetrahedron
};

inline FaceCrossing central_to_corner_crossing(const BoxMesh& mesh, double h) {
  const Vec3 a(0.5 * h, 0.5 * h, 0.5 * h), b(0.9 * h, 0.1 * h, 0.1 * h);
  double lo = 0.0, hi = 1.0;
  for (int it = 0; it < 60; ++it) {
    const double mid = 0.5 * (lo + hi);
    (mesh.locate_element(a + mid * (b - a)) % 5 == 0 ? lo : hi) = mid;
  }
  const FaceCrossing c{a + lo * (b - a), a + hi * (b - a)};
  EXPECT_EQ(mesh.locate_element(c.before) % 5, 0);
  EXPECT_NE(mesh.locate_element(c.after) % 5, 0);
  return c;
}

}  // namespace fdem::test_support
