// Element porosity: the paper's centre scheme (Eq. 32) against the closed form
// of the 5-tetrahedra split, the smoother shape-function scheme, the floor.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "coupling/particle_mapping.hpp"
#include "coupling/porosity.hpp"
#include "coupling/tests/central_to_corner_crossing.hpp"
#include "coupling/tests/porosity_test_grains.hpp"

namespace fdem {
namespace {

using test_support::porosity_of_one_grain;

// Porosity of the element holding a single particle at x (centre scheme).
double centre_porosity_at(const BoxMesh& mesh, const Vec3& x, double d, Index* element = nullptr) {
  Index holding = -1;
  const PorosityField field = porosity_of_one_grain(mesh, PorosityScheme::centre, x, d, &holding);
  if (element) *element = holding;
  return field[holding];
}

TEST(Porosity, CentreSchemeAmplitudeMatchesClosedFormOfFiveTetSplit) {
  // d = 0.76 mm in cubic cells of r d. Central tetrahedron V = h^3/3, corner
  // V = h^3/6, so eps_central = 1 - 3 Vp/h^3, eps_corner = 1 - 6 Vp/h^3 and
  // peak-to-peak / mean = (pi/2 r^-3) / (1 - 3 pi/4 r^-3) with Vp/h^3 = pi/6 r^-3:
  // 6.37, 2.55, 1.28, 0.46, 0.16 % for r = 3, 4, 5, 7, 10 (paper Table 2 gives 6.2, 2.5, 1.3, 0.46, 0.16).
  const double d = 0.76e-3;
  const std::array<double, 5> ratio{3, 4, 5, 7, 10};
  const std::array<double, 5> published{6.37, 2.55, 1.28, 0.46, 0.16};
  for (std::size_t n = 0; n < ratio.size(); ++n) {
    const double r = ratio[n], h = r * d;
    const BoxMesh mesh(Vec3::Zero(), Vec3(2 * h, 2 * h, 2 * h), {2, 2, 2});
    // Cell (0,0,0) is even: central tetrahedron on vertices 0,3,5,6; the local
    // vertex 1 = (h,0,0) is a corner tetrahedron's apex.
    Index central = -1, corner = -1;
    const double eps_central = centre_porosity_at(mesh, Vec3(0.5 * h, 0.5 * h, 0.5 * h), d, &central);
    const double eps_corner = centre_porosity_at(mesh, Vec3(0.9 * h, 0.1 * h, 0.1 * h), d, &corner);
    ASSERT_EQ(central % 5, 0);
    ASSERT_NE(corner % 5, 0);
    const double amplitude_pct = 100.0 * (eps_central - eps_corner) / (0.5 * (eps_central + eps_corner));
    const double closed_form_pct = 100.0 * (pi / 2 / (r * r * r)) / (1.0 - 3.0 * pi / 4 / (r * r * r));
    EXPECT_NEAR(amplitude_pct, closed_form_pct, 1e-10) << r;   // same arithmetic up to round-off
    EXPECT_NEAR(amplitude_pct, published[n], 0.005) << r;      // published to 2 decimals
  }
}

TEST(Porosity, CentreSchemeIsEq32) {
  const BoxMesh mesh(Vec3::Zero(), Vec3(4e-3, 4e-3, 4e-3), {1, 1, 1});
  Index e = -1;
  const double eps = centre_porosity_at(mesh, Vec3(2e-3, 2e-3, 2e-3), 0.76e-3, &e);
  const double ve = mesh.element_volume(e);
  EXPECT_NEAR(eps, (ve - sphere_volume(0.76e-3)) / ve, 1e-15);
}

TEST(Porosity, ShapeFunctionSchemeConservesSolidVolume) {
  // sum_e V_e (1 - eps_e) = sum_i V_i: the nodal split and the averaging back
  // use the same weights V_e/4, so only round-off (1e-12 relative) remains.
  const BoxMesh mesh(Vec3::Zero(), Vec3(0.02, 0.02, 0.03), {5, 5, 6});
  double solid = 0.0;
  const Particles p = test_support::random_particles(500, Vec3(0.02, 0.02, 0.03), 3, &solid);
  ParticleMapping map;
  map.update(mesh, p);
  PorosityField field(mesh, PorosityScheme::shape_function, 0.1);
  const PorosityUpdate upd = field.update(p, map);
  EXPECT_EQ(upd.floored_elements, 0);
  double mapped = 0.0;
  for (Index e = 0; e < mesh.num_elements(); ++e) mapped += mesh.element_volume(e) * (1.0 - field[e]);
  EXPECT_NEAR(mapped, solid, 1e-12 * solid);
}

TEST(Porosity, ShapeFunctionSchemeHasNoJumpAcrossFaces) {
  // A particle crossing from the central to a corner tetrahedron: the centre
  // scheme jumps by the closed-form amount, the shape-function scheme's
  // porosity of the central element changes by O(step), not O(Vp/V_e).
  const double d = 0.76e-3, h = 3 * d;
  const BoxMesh mesh(Vec3::Zero(), Vec3(2 * h, 2 * h, 2 * h), {2, 2, 2});
  const auto [before, after] = test_support::central_to_corner_crossing(mesh, h);
  ASSERT_FALSE(::testing::Test::HasFailure());
  const Index central = mesh.locate_element(before);
  auto shape_eps = [&](const Vec3& x) { return porosity_of_one_grain(mesh, PorosityScheme::shape_function, x, d)[central]; };
  // Volume-coordinate change over |after - before| (~1e-19 m) is ~1e-16: allow 1e-12.
  EXPECT_NEAR(shape_eps(before), shape_eps(after), 1e-12);
  EXPECT_GT(centre_porosity_at(mesh, before, d) - centre_porosity_at(mesh, after, d), 0.05);
}

TEST(Porosity, FloorHoldsAndIsCounted) {
  // Ten 3 mm grains in one 4 mm cell's central tetrahedron: Eq. 32 gives
  // 1 - 10 * 1.414e-8 / 2.133e-8 = -5.6; the floor holds it at 0.1 and counts 1 element.
  const BoxMesh mesh(Vec3::Zero(), Vec3(4e-3, 4e-3, 4e-3), {1, 1, 1});
  Particles p;
  for (int i = 0; i < 10; ++i) {
    p.x.push_back(2e-3);
    p.y.push_back(2e-3);
    p.z.push_back(2e-3 + 1e-5 * i);
    p.diameter.push_back(3e-3);
  }
  ParticleMapping map;
  map.update(mesh, p);
  PorosityField field(mesh, PorosityScheme::centre, 0.1);
  const PorosityUpdate upd = field.update(p, map);
  EXPECT_EQ(upd.floored_elements, 1);
  EXPECT_NEAR(upd.min_porosity, 1.0 - 10 * sphere_volume(3e-3) / mesh.element_volume(0), 1e-12);
  EXPECT_EQ(field[0], 0.1);
  for (Index e = 1; e < 5; ++e) EXPECT_EQ(field[e], 1.0);
}

}  // namespace
}  // namespace fdem
