// The active physics `fdem run` prints at the start: what a scene switches
// on, and the drag law, porosity scheme and exchange only where the fluid and
// the grains are coupled.
#include <gtest/gtest.h>

#include <map>
#include <string>

#include "app/physics_summary.hpp"
#include "scene/scene_loader.hpp"

namespace fdem {
namespace {

const std::string kExamples = std::string(FDEM_SOURCE_DIR) + "/examples/";

std::map<std::string, std::string> physics_of(const Scene& scene) {
  std::map<std::string, std::string> out;
  for (const auto& [topic, what] : active_physics(scene)) out[topic] = what;
  return out;
}

TEST(ActivePhysics, DrySceneNamesEffectsAndNoFluidDragOrPorosity) {
  const auto p = physics_of(load_scene(kExamples + "dry_drop.yaml"));
  EXPECT_EQ(p.at("effects"), "gravity, normal contact (linear spring-dashpot, Eq. 6), walls");
  EXPECT_EQ(p.at("fluid"), "none (dry DEM)");
  EXPECT_EQ(p.size(), 2u);  // no coupling, drag, porosity or exchange
}

TEST(ActivePhysics, TwoWaySceneNamesDragPorosityAndExchange) {
  const auto p = physics_of(load_scene(std::string(FDEM_SOURCE_DIR) + "/verification/settling/settling.yaml"));
  EXPECT_EQ(p.at("effects"), "gravity, buoyancy, normal contact (linear spring-dashpot, Eq. 6), walls");
  EXPECT_EQ(p.at("fluid").rfind("incompressible Navier-Stokes, drag / eps as body force (Eq. 21-22), P1/P1", 0), 0u)
      << p.at("fluid");
  EXPECT_NE(p.at("fluid").find("BDF2"), std::string::npos) << p.at("fluid");
  EXPECT_EQ(p.at("coupling"), "two_way");
  EXPECT_EQ(p.at("drag").rfind("ergun_wen_yu (", 0), 0u) << p.at("drag");  // the law's name, then its source line
  EXPECT_EQ(p.at("porosity"), "centre (Eq. 32), floor 0.1");
  EXPECT_EQ(p.at("exchange"), "explicit (last step's drag), source term F/eps per element volume (Eq. 22)");
}

TEST(ActivePhysics, FluidModelIsNamed) {
  Scene scene = load_scene(std::string(FDEM_SOURCE_DIR) + "/verification/settling/settling.yaml");
  scene.fluid.model = FluidModel::vans_a;
  scene.fluid.porosity_time_derivative = true;
  EXPECT_EQ(physics_of(scene).at("fluid").rfind("volume-averaged Navier-Stokes set II (vans_a, Eq. 18-19) with d(eps)/dt", 0),
            0u)
      << physics_of(scene).at("fluid");
}

TEST(ActivePhysics, VolumeAveragedModelsNameTheirCoupling) {
  Scene scene = load_scene(std::string(FDEM_SOURCE_DIR) + "/verification/settling/settling.yaml");
  scene.fluid.model = FluidModel::vans_b;  // the scene's source_form paper is the simplified model's only
  EXPECT_EQ(physics_of(scene).at("exchange"),
            "explicit (last step's drag), conservative source term (exactly minus the grains' force), grains feel "
            "drag / eps (Zhou et al. 2010 model B)");
  scene.fluid.model = FluidModel::vans_a;
  EXPECT_EQ(physics_of(scene).at("exchange"),
            "explicit (last step's drag), conservative source term (exactly minus the grains' force)");
}

TEST(ActivePhysics, FluidToParticleHasDragButNoExchange) {
  Scene scene = load_scene(std::string(FDEM_SOURCE_DIR) + "/verification/settling/settling.yaml");
  scene.effects.coupling = CouplingMode::fluid_to_particle;
  scene.effects.drag = "stokes";
  const auto p = physics_of(scene);
  EXPECT_EQ(p.at("drag").rfind("stokes (", 0), 0u) << p.at("drag");  // the law's name, then its source line
  EXPECT_EQ(p.count("exchange"), 0u);  // the grains do not act on the fluid
  scene.effects.coupling = CouplingMode::off;
  EXPECT_EQ(physics_of(scene).count("drag"), 0u);
}

}  // namespace
}  // namespace fdem
