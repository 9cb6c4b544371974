// The plume's hard case (README.md, "The DEM step"): the paper's normal size distribution has
// a tail of small grains whose contacts are too stiff and too damped for the
// paper's DEM step of 1e-5 s. The solver must refuse it before any step, and
// accept the study's truncation (README.md, "The DEM step").
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "core/error.hpp"
#include "dem/dem_engine.hpp"
#include "scene/particle_generator.hpp"
#include "scene/scene_loader.hpp"

namespace fdem::plume {
namespace {

Scene paper_scene() {
  return load_scene(std::string(FDEM_SOURCE_DIR) + "/verification/plume/plume.yaml");
}

TEST(PlumeDemStep, PaperSizesAtPaperStep_AreRefusedNamingTheSmallestPair) {
  Scene scene = paper_scene();
  // The anchors' truncation [100, 600] um (shared/anchors/liggghts): a 100 um
  // pair has t_c = 7.5e-6 s < dt and Cn dt / m_eff = 15 (over-damped, explicit dashpot unstable).
  scene.particles.front().size.minimum = 100e-6;
  scene.contact.allow_unstable_step = false;
  try {
    DemEngine engine(generate_particles(scene), scene);
    FAIL() << "the paper's DEM step was accepted for 100 um grains";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "time.dem_step");
    EXPECT_NE(std::string(e.what()).find("smallest pair"), std::string::npos) << e.what();
  }
}

TEST(PlumeDemStep, StudySizesAtPaperStep_AreAcceptedWithoutOverride) {
  const Scene scene = paper_scene();
  ASSERT_FALSE(scene.contact.allow_unstable_step);
  ASSERT_DOUBLE_EQ(scene.time.dem_step, 1e-5);  // the paper's 100 subcycles
  EXPECT_NO_THROW(DemEngine(generate_particles(scene), scene));
}

TEST(PlumeDemStep, StudySizes_AreThePaperLatticeWithTheTruncatedNormal) {
  const Scene scene = paper_scene();
  const Particles p = generate_particles(scene);
  ASSERT_EQ(p.size(), 28224u);  // Table 4
  double lo = 1.0, hi = 0.0;
  for (double d : p.diameter) {
    lo = std::min(lo, d);
    hi = std::max(hi, d);
  }
  EXPECT_GE(lo, scene.particles.front().size.minimum);
  EXPECT_LE(hi, scene.particles.front().size.maximum);
}

}  // namespace
}  // namespace fdem::plume
