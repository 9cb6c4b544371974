// Source term (Fig. 4-5, Eq. 20-22): the conservative form balances momentum
// to round-off, the paper's form gives the fluid 1/eps times the drag.
#include <gtest/gtest.h>

#include <random>

#include "coupling/particle_mapping.hpp"
#include "coupling/porosity.hpp"
#include "coupling/source_term.hpp"

namespace fdem {
namespace {

struct Cloud {
  Particles p;
  std::vector<double> fx, fy, fz;
  Vec3 drag = Vec3::Zero();
};

Cloud random_cloud(int n, const Vec3& upper, std::uint64_t seed) {
  Cloud c;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0), f(-1e-6, 1e-6);
  for (int i = 0; i < n; ++i) {
    c.p.x.push_back(upper.x() * u(rng));
    c.p.y.push_back(upper.y() * u(rng));
    c.p.z.push_back(upper.z() * u(rng));
    c.p.diameter.push_back(1e-4 + 4e-4 * u(rng));  // unequal grains
    c.fx.push_back(f(rng));
    c.fy.push_back(f(rng));
    c.fz.push_back(f(rng));
    c.drag += Vec3(c.fx.back(), c.fy.back(), c.fz.back());
  }
  return c;
}

// Integral of the nodal force density with P1 interpolation: sum_a b_a int N_a = sum_a b_a V_a.
Vec3 integral(const BoxMesh& mesh, std::span<const double> b) {
  std::vector<double> volume(static_cast<std::size_t>(mesh.num_nodes()), 0.0);
  for (Index e = 0; e < mesh.num_elements(); ++e)
    for (Index n : mesh.element_nodes(e)) volume[static_cast<std::size_t>(n)] += mesh.element_volume(e) / 4;
  Vec3 total = Vec3::Zero();
  for (std::size_t a = 0; a < volume.size(); ++a) total += volume[a] * Vec3(b[3 * a], b[3 * a + 1], b[3 * a + 2]);
  return total;
}

TEST(SourceTerm, ConservativeFormBalancesMomentumToRoundOff) {
  const Vec3 upper(0.02, 0.02, 0.04);
  const BoxMesh mesh(Vec3::Zero(), upper, {5, 5, 10});
  Cloud c = random_cloud(2000, upper, 5);
  ParticleMapping map;
  map.update(mesh, c.p);
  PorosityField eps(mesh, PorosityScheme::centre, 0.1);
  eps.update(c.p, map);
  SourceTerm source(mesh, SourceForm::conservative);
  source.compute(c.p, map, eps.values(), c.fx, c.fy, c.fz);
  // Sums of 2000 terms of 1e-6 N: round-off ~ 2000 * 1e-16 * 1e-6; allow 1e-18 N.
  EXPECT_LT((source.total_force() + c.drag).norm(), 1e-18);
  EXPECT_LT((integral(mesh, source.nodal_force_density()) + c.drag).norm(), 1e-18);
}

TEST(SourceTerm, PaperFormGivesFluidOneOverEpsTimesTheDrag) {
  // One particle alone in its element, centre porosity: V_e b_e = -f / eps_e,
  // so the imbalance |F_fluid + f| / |f| = 1/eps - 1.
  const BoxMesh mesh(Vec3::Zero(), Vec3(4e-3, 4e-3, 4e-3), {1, 1, 1});
  Particles p;
  p.x = {2e-3};
  p.y = {2e-3};
  p.z = {2e-3};
  p.diameter = {1.5e-3};
  const std::vector<double> fx{0.0}, fy{0.0}, fz{3e-6};
  ParticleMapping map;
  map.update(mesh, p);
  PorosityField eps(mesh, PorosityScheme::centre, 0.1);
  eps.update(p, map);
  const double e = eps[map.element[0]];
  SourceTerm source(mesh, SourceForm::paper);
  source.compute(p, map, eps.values(), fx, fy, fz);
  const double imbalance = (source.total_force() + Vec3(0, 0, 3e-6)).norm() / 3e-6;
  EXPECT_NEAR(imbalance, 1.0 / e - 1.0, 1e-12);
  EXPECT_GT(imbalance, 0.05);  // eps = 1 - 1.767e-9 / 2.133e-8 = 0.917: 1/eps - 1 = 0.090, a visible 9 %
  EXPECT_NEAR(integral(mesh, source.nodal_force_density()).z(), source.total_force().z(), 1e-18);
}

TEST(SourceTerm, PaperFormVolumeWeightedAverageKeepsOneOverEpsForUnequalGrains) {
  // Two grains of different size in the same element: the volume-weighted
  // average of beta_i (u - v_i) gives the fluid exactly -(f1 + f2) / eps.
  const BoxMesh mesh(Vec3::Zero(), Vec3(4e-3, 4e-3, 4e-3), {1, 1, 1});
  Particles p;
  p.x = {2e-3, 2.1e-3};
  p.y = {2e-3, 2.0e-3};
  p.z = {2e-3, 1.9e-3};
  p.diameter = {0.3e-3, 0.9e-3};
  const std::vector<double> fx{1e-6, -4e-6}, fy{0.0, 0.0}, fz{2e-6, 5e-6};
  ParticleMapping map;
  map.update(mesh, p);
  ASSERT_EQ(map.element[0], map.element[1]);
  PorosityField eps(mesh, PorosityScheme::centre, 0.1);
  eps.update(p, map);
  const double e = eps[map.element[0]];
  SourceTerm source(mesh, SourceForm::paper);
  source.compute(p, map, eps.values(), fx, fy, fz);
  const Vec3 expected = -Vec3(-3e-6, 0.0, 7e-6) / e;
  EXPECT_LT((source.total_force() - expected).norm(), 1e-12 * expected.norm());
}

TEST(SourceTerm, ClearGivesZeroBodyForce) {
  const BoxMesh mesh(Vec3::Zero(), Vec3(1, 1, 1), {2, 2, 2});
  SourceTerm source(mesh, SourceForm::conservative);
  source.clear();
  for (double b : source.nodal_force_density()) EXPECT_EQ(b, 0.0);
  EXPECT_EQ(source.total_force().norm(), 0.0);
}

}  // namespace
}  // namespace fdem
