// Particle generator: counts, positions (lattice against the LIGGGHTS anchors'
// gen_scenes.py formula and rows), truncation bounds, no overlaps, masses,
// determinism under a seed.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/error.hpp"
#include "scene/particle_generator.hpp"
#include "scene/scene_loader.hpp"

namespace fdem {
namespace {

std::string dry_scene(const std::string& sets) {
  return "effects: {fluid: false}\n"
         "domain: {lower: [0, 0, 0], upper: [0.1, 0.1, 0.25]}\n"
         "contact: {kn: 100, cn: 8.5e-4}\n"
         "time: {dem_step: 1.0e-5, end: 1.0e-3}\n"
         "particles:\n" +
         sets;
}

// The anchors' scene P: 28 x 28 x 36 sites in a 20 x 20 x 40 mm block at
// (40, 40, 180) mm, d = 309 um (P_mono).
const char* kPlumeBlock =
    "  - {name: salt, placement: lattice, region: {lower: [0.040, 0.040, 0.180], upper: [0.060, 0.060, 0.220]},\n"
    "     lattice: [28, 28, 36], size: 309.0e-6, density: 2170}\n";

TEST(ParticleGenerator, LatticeCountIsTheProductOfSiteCounts) {
  const Particles p = generate_particles(load_scene_from_string(dry_scene(kPlumeBlock), "p.yaml"));
  EXPECT_EQ(p.size(), 28u * 28u * 36u);  // 28224, as the paper's plume
  EXPECT_EQ(p.diameter.size(), p.size());
  EXPECT_EQ(p.mass.size(), p.size());
  EXPECT_EQ(p.fx.size(), p.size());
  EXPECT_TRUE(p.wx.empty());  // rotation arrays are the DEM engine's to size
}

TEST(ParticleGenerator, LatticeMatchesAnchorsOrderAndPositions) {
  const Particles p = generate_particles(load_scene_from_string(dry_scene(kPlumeBlock), "p.yaml"));
  // Formula of gen_scenes.py scene_P: x fastest, then y, then z; site = lower + (i + 0.5) * L / n.
  const double dx = 0.020 / 28, dz = 0.040 / 36;
  for (int k : {0, 17, 35}) {
    for (int j : {0, 5, 27}) {
      for (int i : {0, 13, 27}) {
        const std::size_t n = static_cast<std::size_t>(i + 28 * (j + 28 * k));
        // 1e-15 m: a few ulps of 0.2 m; the formula is evaluated the same way.
        EXPECT_NEAR(p.x[n], 0.040 + (i + 0.5) * dx, 1e-15);
        EXPECT_NEAR(p.y[n], 0.040 + (j + 0.5) * dx, 1e-15);
        EXPECT_NEAR(p.z[n], 0.180 + (k + 0.5) * dz, 1e-15);
      }
    }
  }
  // Rows of /work/shared/anchors/liggghts/gen/P_mono_init.csv (ids 1, 2, 29, 785, 28224),
  // printed there with 13 significant digits: 1e-13 m tolerance covers the rounding.
  const struct { std::size_t id; double x, y, z; } rows[] = {
      {1, 4.035714285714e-02, 4.035714285714e-02, 1.805555555556e-01},
      {2, 4.107142857143e-02, 4.035714285714e-02, 1.805555555556e-01},
      {29, 4.035714285714e-02, 4.107142857143e-02, 1.805555555556e-01},
      {785, 4.035714285714e-02, 4.035714285714e-02, 1.816666666667e-01},
      {28224, 5.964285714286e-02, 5.964285714286e-02, 2.194444444444e-01}};
  for (const auto& r : rows) {
    EXPECT_NEAR(p.x[r.id - 1], r.x, 1e-13) << "id " << r.id;
    EXPECT_NEAR(p.y[r.id - 1], r.y, 1e-13) << "id " << r.id;
    EXPECT_NEAR(p.z[r.id - 1], r.z, 1e-13) << "id " << r.id;
  }
}

TEST(ParticleGenerator, MassIsDensityTimesSphereVolume) {
  const Particles p = generate_particles(load_scene_from_string(dry_scene(kPlumeBlock), "p.yaml"));
  const double expected = 2170.0 * pi / 6.0 * std::pow(309.0e-6, 3);
  EXPECT_NEAR(p.mass[0], expected, 1e-15 * expected);  // same formula, round-off only
}

const char* kNormalSet =
    "  - {name: salt, placement: lattice, region: {lower: [0.040, 0.040, 0.180], upper: [0.060, 0.060, 0.220]},\n"
    "     lattice: [28, 28, 36], size: {distribution: normal, mean: 309.0e-6, sd: 114.0e-6, min: 100.0e-6,\n"
    "     max: 600.0e-6}, density: 2170, seed: 20240601}\n";

TEST(ParticleGenerator, TruncatedNormalRespectsItsBounds) {
  const Particles p = generate_particles(load_scene_from_string(dry_scene(kNormalSet), "p.yaml"));
  for (double d : p.diameter) {
    ASSERT_GE(d, 100.0e-6);
    ASSERT_LE(d, 600.0e-6);
  }
}

TEST(ParticleGenerator, TruncatedNormalMeanMatchesTheTruncatedDistribution) {
  const Particles p = generate_particles(load_scene_from_string(dry_scene(kNormalSet), "p.yaml"));
  // Mean of N(mu, sd) truncated to [a, b]: mu + sd (phi(alpha) - phi(beta)) / (Phi(beta) - Phi(alpha)).
  const double mu = 309e-6, sd = 114e-6;
  const double alpha = (100e-6 - mu) / sd, beta = (600e-6 - mu) / sd;
  auto phi = [](double x) { return std::exp(-0.5 * x * x) / std::sqrt(2.0 * pi); };
  auto Phi = [](double x) { return 0.5 * (1.0 + std::erf(x / std::sqrt(2.0))); };
  const double mean = mu + sd * (phi(alpha) - phi(beta)) / (Phi(beta) - Phi(alpha));
  double sample = 0.0;
  for (double d : p.diameter) sample += d;
  sample /= static_cast<double>(p.size());
  // Standard error sd / sqrt(28224) = 0.68 um; 5 standard errors can fail only by a bug.
  EXPECT_NEAR(sample, mean, 5.0 * sd / std::sqrt(28224.0));
}

TEST(ParticleGenerator, SameSeedSameParticlesOtherSeedOthers) {
  const Scene scene = load_scene_from_string(dry_scene(kNormalSet), "p.yaml");
  const Particles a = generate_particles(scene);
  const Particles b = generate_particles(scene);
  EXPECT_EQ(a.diameter, b.diameter);  // bit for bit
  Scene other = scene;
  other.particles[0].seed = 7;
  EXPECT_NE(generate_particles(other).diameter, a.diameter);
}

TEST(ParticleGenerator, UniformSizesStayInsideTheirBounds) {
  const Particles p = generate_particles(load_scene_from_string(
      dry_scene("  - {placement: lattice, region: {lower: [0, 0, 0], upper: [0.012, 0.0018, 0.0096]},\n"
                "     lattice: [32, 5, 30], size: {distribution: uniform, min: 0.2e-3, max: 0.3e-3}, density: 2170}\n"),
      "b.yaml"));
  ASSERT_EQ(p.size(), 4800u);  // the paper's channel bed count
  double lo = 1, hi = 0;
  for (double d : p.diameter) {
    lo = std::min(lo, d);
    hi = std::max(hi, d);
  }
  EXPECT_GE(lo, 0.2e-3);
  EXPECT_LT(hi, 0.3e-3);
  // 4800 uniform draws reach within 1 % of each end of the range (miss chance 0.99^4800).
  EXPECT_LT(lo, 0.201e-3);
  EXPECT_GT(hi, 0.299e-3);
}

TEST(ParticleGenerator, RandomPlacementInsideRegionWithoutOverlap) {
  const Scene scene = load_scene_from_string(
      dry_scene("  - {placement: random, region: {lower: [0.01, 0.02, 0.03], upper: [0.03, 0.04, 0.05]}, count: 500,\n"
                "     size: {distribution: uniform, min: 1.0e-3, max: 2.0e-3}, density: 2500, seed: 3}\n"),
      "r.yaml");
  const Particles p = generate_particles(scene);
  ASSERT_EQ(p.size(), 500u);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double r = 0.5 * p.diameter[i];
    ASSERT_GE(p.x[i] - r, 0.01);
    ASSERT_LE(p.x[i] + r, 0.03);
    ASSERT_GE(p.z[i] - r, 0.03);
    ASSERT_LE(p.z[i] + r, 0.05);
    for (std::size_t j = 0; j < i; ++j) {  // brute force against the hash grid
      const double dist = std::hypot(p.x[i] - p.x[j], p.y[i] - p.y[j], p.z[i] - p.z[j]);
      ASSERT_GE(dist, 0.5 * (p.diameter[i] + p.diameter[j])) << i << " overlaps " << j;
    }
  }
  EXPECT_EQ(generate_particles(scene).x, p.x);  // deterministic
}

TEST(ParticleGenerator, RandomPlacementThatCannotFitIsAnInputError) {
  // 45 % solid by volume: above random sequential addition's jamming limit (~38 %).
  const int count = static_cast<int>(0.45 * 1e-6 / sphere_volume(1e-3));
  const std::string set = "  - {placement: random, region: {lower: [0, 0, 0], upper: [0.01, 0.01, 0.01]}, count: " +
                          std::to_string(count) + ", size: 1.0e-3, density: 2500}\n";
  const Scene scene = load_scene_from_string(dry_scene(set), "full.yaml");
  try {
    (void)generate_particles(scene);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "particles[0].count");
    EXPECT_NE(std::string(e.what()).find("found room for only"), std::string::npos);
  }
}

TEST(ParticleGenerator, CsvReadsAnchorFormatWithOptionalVelocity) {
  const auto dir = std::filesystem::temp_directory_path() / "fdem_test_generator_csv";
  std::filesystem::create_directories(dir);
  {
    std::ofstream out(dir / "two.csv");
    out << "id,d,rho,x,y,z\n1,2.5e-4,2170,0.01,0.02,0.03\n2,3.0e-4,2650,0.02,0.02,0.03\n";
    std::ofstream v(dir / "moving.csv");
    v << "id,d,rho,x,y,z,vx,vy,vz\n1,2.5e-4,2170,0.01,0.02,0.03,0.1,0.2,-0.3\n";
  }
  const Scene scene = load_scene_from_string(
      dry_scene("  - {name: a, placement: csv, file: two.csv, velocity: [0, 0, -1]}\n"
                "  - {name: b, placement: csv, file: moving.csv}\n"),
      "csv.yaml", dir.string());
  const Particles p = generate_particles(scene);
  ASSERT_EQ(p.size(), 3u);
  EXPECT_DOUBLE_EQ(p.diameter[1], 3.0e-4);
  EXPECT_DOUBLE_EQ(p.mass[1], 2650.0 * sphere_volume(3.0e-4));
  EXPECT_DOUBLE_EQ(p.vz[0], -1.0);  // no velocity columns: the set's velocity
  EXPECT_DOUBLE_EQ(p.vx[2], 0.1);   // velocity columns win
  EXPECT_DOUBLE_EQ(p.vz[2], -0.3);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace fdem
