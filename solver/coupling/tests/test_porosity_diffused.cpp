// The diffused porosity scheme (coupling/porosity.hpp): the shape-function
// nodal solid fraction smoothed by one implicit diffusion, (M + L^2 K) phi = M phi0.
// Claims: solid volume conserved by the diffusion itself; no new extrema;
// continuous across element faces; the offset grain's porosity amplitude
// falls with L and at the default L at cell / d = 3 is below the paper's
// centre scheme at cell / d = 10; the scene key is read and bad values refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "core/error.hpp"
#include "coupling/particle_mapping.hpp"
#include "coupling/porosity.hpp"
#include "scene/scene_loader.hpp"
#include "coupling/tests/central_to_corner_crossing.hpp"
#include "coupling/tests/porosity_test_grains.hpp"

namespace fdem {
namespace {

constexpr double kGrain = 0.76e-3;  // the mesh-sensitivity grain [m] (paper Sect. 4.2)

using test_support::one_particle;

using test_support::random_particles;

// n random grains (d 0.2-0.8 mm) in a 20 x 20 x 30 mm box of 5 x 5 x 6 cells, mapped.
struct RandomBed {
  Vec3 upper{0.02, 0.02, 0.03};
  BoxMesh mesh{Vec3::Zero(), upper, {5, 5, 6}};
  double solid = 0.0;  // total grain volume [m^3]
  Particles p;
  ParticleMapping map;
  RandomBed(int n, unsigned seed) : p(random_particles(n, upper, seed, &solid)) { map.update(mesh, p); }
};

// Kinematic version of the study's offset start: the grain moved down the
// vertical line at (0.25, 0.25) of the middle cell of a 5 x 5 column (the
// line alternates between central and corner tetrahedra), through two whole
// cells in 200 steps (h / 100: a smooth extremum is caught to
// 1 - cos(pi / 100) = 5e-4 of the amplitude); returns (max - min) / mean of
// the porosity of the element holding it, in percent. No fluid: the
// porosity field alone.
double offset_line_amplitude_pct(double ratio, PorosityScheme scheme, std::optional<double> length = std::nullopt) {
  const double h = ratio * kGrain;
  const BoxMesh mesh(Vec3::Zero(), Vec3(5 * h, 5 * h, 8 * h), {5, 5, 8});
  PorosityField field(mesh, scheme, 0.1, length);
  ParticleMapping map;
  double lo = INFINITY, hi = -INFINITY, sum = 0.0;
  const int steps = 200;
  for (int s = 0; s < steps; ++s) {
    const double z = 5.5 * h - 2.0 * h * s / steps;
    const Particles p = one_particle(Vec3(2.25 * h, 2.25 * h, z), kGrain);
    map.update(mesh, p);
    field.update(p, map);
    const double eps = field[map.element[0]];
    lo = std::min(lo, eps);
    hi = std::max(hi, eps);
    sum += eps;
  }
  return 100.0 * (hi - lo) / (sum / steps);
}

TEST(PorosityDiffused, DiffusionConservesSolidVolume) {
  // 1^T (M + L^2 K) = 1^T M (K 1 = 0, K symmetric, natural boundary
  // conditions), so the diffusion keeps sum M phi; the scheme's rescale only
  // removes the CG residual: its factor must be 1 to the solve's tolerance
  // (1e-10 relative residual; measured 1e-14 here, 2e-12 on 69k nodes).
  // After it, sum_e V_e (1 - eps_e) = sum_i V_i to round-off (1e-12 relative).
  const RandomBed bed(500, 3);
  const BoxMesh& mesh = bed.mesh;
  const Particles& p = bed.p;
  const ParticleMapping& map = bed.map;
  const double solid = bed.solid;
  PorosityField field(mesh, PorosityScheme::diffused, 0.1);
  const PorosityUpdate upd = field.update(p, map);
  EXPECT_EQ(upd.floored_elements, 0);
  EXPECT_GT(upd.smoothing_iterations, 0);
  EXPECT_NEAR(upd.conservation_correction, 1.0, 1e-10);
  double mapped = 0.0;
  for (Index e = 0; e < mesh.num_elements(); ++e) mapped += mesh.element_volume(e) * (1.0 - field[e]);
  EXPECT_NEAR(mapped, solid, 1e-12 * solid);
}

TEST(PorosityDiffused, SmoothedFieldHasNoNewExtrema) {
  // M + L^2 K is an M-matrix on the 5-tet split (no obtuse dihedral angle):
  // phi is a convex combination of phi0, so 0 <= phi <= max phi0 and every
  // element porosity lies in [1 - max phi0, 1]. The CG stops at a relative
  // residual of 1e-10, so phi is right to about cond x 1e-10 x |phi| with
  // cond <= 1 + 14.4 (L / h)^2 = 59 at L = 2h and |phi| < 0.1: allow 1e-9.
  // A larger L must spread the solid further: the densest element gets lighter.
  const RandomBed bed(60, 7);
  const BoxMesh& mesh = bed.mesh;
  const Particles& p = bed.p;
  const ParticleMapping& map = bed.map;
  // phi0 by hand: the P1 split of each volume over the lumped nodal volumes.
  std::vector<double> nodal_solid(static_cast<std::size_t>(mesh.num_nodes()), 0.0), nodal_volume(nodal_solid);
  for (Index e = 0; e < mesh.num_elements(); ++e)
    for (Index n : mesh.element_nodes(e)) nodal_volume[static_cast<std::size_t>(n)] += 0.25 * mesh.element_volume(e);
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t a = 0; a < 4; ++a)
      nodal_solid[static_cast<std::size_t>(mesh.element_nodes(map.element[i])[a])] +=
          map.weights[i][a] * sphere_volume(p.diameter[i]);
  double max_phi0 = 0.0;
  for (std::size_t n = 0; n < nodal_solid.size(); ++n) max_phi0 = std::max(max_phi0, nodal_solid[n] / nodal_volume[n]);
  double previous_min = 0.0;
  for (double cells : {0.5, 1.0, 2.0}) {
    PorosityField field(mesh, PorosityScheme::diffused, 0.1, cells * mesh.cell_size().maxCoeff());
    const PorosityUpdate upd = field.update(p, map);
    EXPECT_EQ(upd.floored_elements, 0);
    for (Index e = 0; e < mesh.num_elements(); ++e) {
      EXPECT_LE(field[e], 1.0 + 1e-9) << "L = " << cells << " cells, element " << e;
      EXPECT_GE(field[e], 1.0 - max_phi0 - 1e-9) << "L = " << cells << " cells, element " << e;
    }
    EXPECT_GT(upd.min_porosity, previous_min) << "L = " << cells << " cells";
    previous_min = upd.min_porosity;
  }
}

TEST(PorosityDiffused, NoJumpAcrossFaces) {
  // As the shape-function scheme: the P1 weights are continuous in the grain's
  // position and the diffusion is linear, so moving the grain across the
  // central/corner face by ~1e-19 m changes every element's porosity by
  // round-off plus what the CG's 1e-10 relative residual leaves in phi
  // (phi < 0.02 here: 1e-10 x 0.02 x cond < 1e-10; allow 1e-10, far below
  // the centre scheme's jump of 0.05 at the same face).
  const double h = 3 * kGrain;
  // Cell (0,0,0) is even: local vertex 1 = (h,0,0) is a corner tetrahedron's apex.
  const BoxMesh mesh(Vec3::Zero(), Vec3(2 * h, 2 * h, 2 * h), {2, 2, 2});
  const auto [before, after] = test_support::central_to_corner_crossing(mesh, h);
  ASSERT_FALSE(::testing::Test::HasFailure());
  auto field_at = [&](const Vec3& x) {
    const PorosityField field = test_support::porosity_of_one_grain(mesh, PorosityScheme::diffused, x, kGrain);
    return std::vector<double>(field.values().begin(), field.values().end());
  };
  const std::vector<double> u = field_at(before), v = field_at(after);
  for (std::size_t e = 0; e < u.size(); ++e) EXPECT_NEAR(u[e], v[e], 1e-10) << e;
}

TEST(PorosityDiffused, OffsetLineAmplitudeFallsWithLengthAndAtRatio3BeatsCentreSchemeAtRatio10) {
  // The measured sweep behind kDefaultSmoothingCells (printed for the README).
  // The gate: at the default L, ratio 3's amplitude below the centre scheme's
  // at ratio 10 (closed form 0.1575 %, measured here too) with a factor 2 of
  // margin, so the dynamic study (where the grain also drifts) keeps it.
  const double centre10 = offset_line_amplitude_pct(10.0, PorosityScheme::centre);
  const double shape3 = offset_line_amplitude_pct(3.0, PorosityScheme::shape_function);
  std::printf("ratio 3, offset line: centre %.4f %%, shape_function %.4f %%; centre at ratio 10: %.4f %%\n",
              offset_line_amplitude_pct(3.0, PorosityScheme::centre), shape3, centre10);
  EXPECT_NEAR(centre10, 0.1575, 0.002);  // closed form 3q/(1 - 4.5q); 200 samples hit both tetrahedra
  double previous = shape3;
  const double h3 = 3.0 * kGrain;
  for (double cells : {0.25, 0.5, 0.75, 1.0, 1.5, 2.0}) {
    const double amp = offset_line_amplitude_pct(3.0, PorosityScheme::diffused, cells * h3);
    std::printf("ratio 3, offset line: diffused L = %.2f cells: %.4f %%\n", cells, amp);
    EXPECT_LT(amp, previous) << "L = " << cells << " cells";
    previous = amp;
  }
  const double at_default = offset_line_amplitude_pct(3.0, PorosityScheme::diffused);
  EXPECT_LT(at_default, 0.5 * centre10);
}

TEST(PorosityDiffused, DefaultLengthIsOneCellAndBadLengthRefused) {
  const BoxMesh mesh(Vec3::Zero(), Vec3(0.004, 0.004, 0.006), {2, 2, 2});
  EXPECT_DOUBLE_EQ(PorosityField(mesh, PorosityScheme::diffused, 0.1).smoothing_length(),
                   kDefaultSmoothingCells * 0.003);  // largest edge: 6 mm / 2 cells
  EXPECT_DOUBLE_EQ(PorosityField(mesh, PorosityScheme::diffused, 0.1, 1e-3).smoothing_length(), 1e-3);
  EXPECT_DOUBLE_EQ(PorosityField(mesh, PorosityScheme::centre, 0.1, 1e-3).smoothing_length(), 0.0);
  EXPECT_THROW(PorosityField(mesh, PorosityScheme::diffused, 0.1, 0.0), std::invalid_argument);
  EXPECT_THROW(PorosityField(mesh, PorosityScheme::diffused, 0.1, -1e-3), std::invalid_argument);
  CouplingSpec c;
  c.porosity = PorosityScheme::diffused;
  c.porosity_smoothing_length = 2e-3;
  EXPECT_DOUBLE_EQ(PorosityField(mesh, c).smoothing_length(), 2e-3);
}

TEST(PorosityDiffused, NoParticlesGivesPorosityOne) {
  const BoxMesh mesh(Vec3::Zero(), Vec3(0.004, 0.004, 0.004), {2, 2, 2});
  PorosityField field(mesh, PorosityScheme::diffused, 0.1);
  ParticleMapping map;
  const Particles none;
  map.update(mesh, none);
  const PorosityUpdate upd = field.update(none, map);
  for (double eps : field.values()) EXPECT_EQ(eps, 1.0);
  EXPECT_EQ(upd.smoothing_iterations, 0);
}

std::string scene_with_coupling(const std::string& coupling) {
  return R"(
title: diffused
domain: {lower: [0, 0, 0], upper: [0.012, 0.012, 0.012]}
mesh: {cells: [3, 3, 3]}
fluid: {density: 1000, viscosity: 1.0e-3}
particles:
  - {name: grain, placement: single, position: [0.006, 0.006, 0.006], size: 7.6e-4, density: 2650}
contact: {kn: 100, restitution: 0.5}
time: {fluid_step: 0.01, dem_step: 1.0e-5, end: 0.1}
coupling: )" + coupling + "\n";
}

TEST(PorosityDiffused, SceneKeyReadAndNonPositiveLengthRefusedNamingFileKeyValue) {
  const Scene s = load_scene_from_string(
      scene_with_coupling("{porosity: diffused, porosity_smoothing_length: 2.5e-3}"), "diffused.yaml");
  EXPECT_EQ(s.coupling.porosity, PorosityScheme::diffused);
  ASSERT_TRUE(s.coupling.porosity_smoothing_length.has_value());
  EXPECT_DOUBLE_EQ(*s.coupling.porosity_smoothing_length, 2.5e-3);
  EXPECT_FALSE(load_scene_from_string(scene_with_coupling("{porosity: diffused}"), "diffused.yaml")
                   .coupling.porosity_smoothing_length.has_value());
  for (const char* bad : {"0", "-1.0e-3"}) {
    try {
      (void)load_scene_from_string(
          scene_with_coupling(std::string("{porosity: diffused, porosity_smoothing_length: ") + bad + "}"), "bad.yaml");
      FAIL() << "length " << bad << " accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), "bad.yaml");
      EXPECT_EQ(e.key(), "coupling.porosity_smoothing_length");
      EXPECT_EQ(e.value(), bad);
    }
  }
}

TEST(PorosityDiffused, SmoothingInDiametersReadAndRefusedWhenBadOrGivenWithTheLength) {
  const Scene s = load_scene_from_string(
      scene_with_coupling("{porosity: diffused, porosity_smoothing_diameters: 3}"), "diffused.yaml");
  ASSERT_TRUE(s.coupling.porosity_smoothing_diameters.has_value());
  EXPECT_DOUBLE_EQ(*s.coupling.porosity_smoothing_diameters, 3.0);
  const Scene i = load_scene_from_string(scene_with_coupling("{porosity: intersection}"), "i.yaml");
  EXPECT_EQ(i.coupling.porosity, PorosityScheme::intersection);
  for (const char* bad : {"{porosity: diffused, porosity_smoothing_diameters: 0}",
                          "{porosity: diffused, porosity_smoothing_diameters: 2, porosity_smoothing_length: 1.0e-3}"}) {
    try {
      (void)load_scene_from_string(scene_with_coupling(bad), "bad.yaml");
      FAIL() << bad << " accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), "bad.yaml");
      EXPECT_EQ(e.key(), "coupling.porosity_smoothing_diameters");
    }
  }
}

}  // namespace
}  // namespace fdem
