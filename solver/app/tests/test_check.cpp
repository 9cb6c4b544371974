// fdem check: the derived numbers of a scene, and the refusal of an unstable
// DEM step after the table is printed.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "app/check_command.hpp"
#include "core/error.hpp"
#include "scene/particle_generator.hpp"
#include "scene/scene_loader.hpp"

namespace fdem {
namespace {

std::string check_output(const Scene& scene, bool* refused = nullptr) {
  std::FILE* out = std::tmpfile();
  const Particles particles = generate_particles(scene);
  try {
    print_scene_check(scene, particles, out);
    if (refused != nullptr) *refused = false;
  } catch (const InputError&) {
    if (refused != nullptr) *refused = true;
  }
  std::rewind(out);
  std::string text(1 << 16, '\0');
  text.resize(std::fread(text.data(), 1, text.size(), out));
  std::fclose(out);
  return text;
}

const std::string kStudies = std::string(FDEM_SOURCE_DIR) + "/verification/";

TEST(FdemCheck, SettlingPrintsMeshParticlesStepsAndRatios) {
  const std::string text = check_output(load_scene(kStudies + "settling/settling.yaml"));
  EXPECT_NE(text.find("2420 cells, 12100 elements (tetrahedra), 3024 nodes"), std::string::npos) << text;
  EXPECT_NE(text.find("1 in 1 set(s)"), std::string::npos) << text;
  EXPECT_NE(text.find("1000 DEM steps of 1e-05 s per fluid step"), std::string::npos) << text;
  // 4 mm cells / 0.76 mm grain = 5.26.
  EXPECT_NE(text.find("min cell size / max diameter = 5.26"), std::string::npos) << text;
  EXPECT_NE(text.find("dem_step / stable bound"), std::string::npos) << text;
  EXPECT_NE(text.find("smallest on wall"), std::string::npos) << text;
  EXPECT_NE(text.find("memory"), std::string::npos) << text;
}

TEST(FdemCheck, UnstableStepIsRefusedAfterTheTableIsPrinted) {
  Scene scene = load_scene(kStudies + "channel/channel.yaml");
  scene.contact.normal_stiffness = 1e5;  // the paper's Kn, Cn at its DEM step
  scene.contact.restitution.reset();
  scene.contact.normal_damping = 0.026;
  bool refused = false;
  const std::string text = check_output(scene, &refused);
  EXPECT_TRUE(refused);
  EXPECT_NE(text.find("UNSTABLE"), std::string::npos) << text;
  EXPECT_NE(text.find("memory"), std::string::npos) << text;  // everything printed before the refusal
  scene.contact.allow_unstable_step = true;
  EXPECT_NE(check_output(scene, &refused).find("allowed by contact.allow_unstable_step"), std::string::npos);
  EXPECT_FALSE(refused);
}

TEST(FdemCheck, DrySceneNamesNoDragLawCoupledSceneDoes) {
  const std::string kExamples = std::string(FDEM_SOURCE_DIR) + "/examples/";
  const std::string dry = check_output(load_scene(kExamples + "dry_drop.yaml"));
  EXPECT_NE(dry.find("effects    fluid off, coupling off"), std::string::npos) << dry;
  EXPECT_EQ(dry.find("drag"), std::string::npos) << dry;
  const std::string settling = check_output(load_scene(kStudies + "settling/settling.yaml"));
  EXPECT_NE(settling.find("drag       ergun_wen_yu: "), std::string::npos) << settling;
}

TEST(FdemCheck, MemoryEstimateScalesWithCellsAndParticles) {
  Scene scene = load_scene(kStudies + "settling/settling.yaml");
  const MemoryEstimate base = estimate_memory(scene, 1000);
  EXPECT_GT(base.fluid_bytes, 0.0);
  EXPECT_DOUBLE_EQ(estimate_memory(scene, 2000).particles_bytes, 2.0 * base.particles_bytes);
  scene.cells = {22, 22, 40};  // 8x the cells: the fluid part grows about 8x
  EXPECT_NEAR(estimate_memory(scene, 1000).fluid_bytes / base.fluid_bytes, 8.0, 1.0);
  scene.effects.fluid = false;
  EXPECT_DOUBLE_EQ(estimate_memory(scene, 1000).fluid_bytes, 0.0);  // a dry scene builds no mesh
}

}  // namespace
}  // namespace fdem
