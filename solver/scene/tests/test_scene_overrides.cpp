// Overrides change exactly the keys they name, pass the loader's checks like
// the file's own keys, and a misspelt one is refused.
#include <gtest/gtest.h>

#include <string>

#include "core/error.hpp"
#include "scene/scene_loader.hpp"
#include "scene/scene_overrides.hpp"

// A namespace of its own: the executable compiles its files as one unit.
namespace fdem::scene_overrides_test {
namespace {

const std::string kSettling = std::string(FDEM_SOURCE_DIR) + "/verification/settling/settling.yaml";

TEST(SceneOverrides, ChangeTheNamedKeysAndNothingElse) {
  const Scene file = load_scene(kSettling);
  const Scene changed = load_scene_with_overrides(
      kSettling, {{"time.fluid_step", "0.005", "test"}, {"particles[0].size", "2.5e-4", "test"},
                  {"mesh.cells", "[3, 3, 5]", "test"}, {"contact.allow_unstable_step", "true", "a key the file lacks"}});
  EXPECT_EQ(changed.time.fluid_step, 0.005);
  EXPECT_EQ(changed.time.subcycles, 500);  // derived again from the new fluid step
  EXPECT_EQ(changed.particles[0].size.diameter, 2.5e-4);
  EXPECT_EQ(changed.cells, (std::array<int, 3>{3, 3, 5}));
  EXPECT_TRUE(changed.contact.allow_unstable_step);
  EXPECT_FALSE(file.contact.allow_unstable_step);
  EXPECT_EQ(changed.time.dem_step, file.time.dem_step);
  EXPECT_EQ(changed.fluid.viscosity, file.fluid.viscosity);
  EXPECT_EQ(changed.particles[0].position, file.particles[0].position);
  EXPECT_EQ(changed.domain.upper, file.domain.upper);
}

TEST(SceneOverrides, AreValidatedLikeTheFile) {
  try {
    load_scene_with_overrides(kSettling, {{"fluid.viscosty", "1e-3", "typo"}});
    FAIL() << "a misspelt override key was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "fluid.viscosty");
    EXPECT_NE(std::string(e.what()).find("with overrides fluid.viscosty"), std::string::npos) << e.what();
  }
  EXPECT_THROW(load_scene_with_overrides(kSettling, {{"time.subcycles", "7", "breaks subcycles x dem_step"}}),
               InputError);
  EXPECT_THROW(load_scene_with_overrides(kSettling, {{"particles[3].size", "1e-3", "no such set"}}), InputError);
}

}  // namespace
}  // namespace fdem::scene_overrides_test
