// The engine refuses an unstable DEM step before any step is taken.
#include <gtest/gtest.h>

#include <string>

#include "core/error.hpp"
#include "dem/dem_engine.hpp"
#include "dem_scene.hpp"
#include "scene/tests/paper_channel_contact.hpp"

namespace fdem {
namespace {

Scene channel_scene() {
  // The paper's channel flow: Kn 1e5, Cn 0.026, d 0.2-0.3 mm, rho 2170, dt 1e-5 (= 15 t_c).
  Scene s = verification::dry_scene(0.012, 1e5, 1e-5, true, true);
  s.contact = scene_test::paper_channel_contact();
  return s;
}

Particles two_grains() {
  Particles p;
  p.add(0.003, 0.003, 0.003, 0.2e-3, 2170.0);
  p.add(0.006, 0.003, 0.003, 0.3e-3, 2170.0);
  return p;
}

TEST(UnstableStep, PaperChannelParametersAreRefusedWithBoundAndKey) {
  try {
    DemEngine dem(two_grains(), channel_scene());
    FAIL() << "dt = 15 t_c must be refused";
  } catch (const InputError& e) {
    scene_test::expect_paper_channel_step_refused(e);
  }
}

TEST(UnstableStep, AllowUnstableStepRunsAnyway) {
  Scene s = channel_scene();
  s.contact.allow_unstable_step = true;
  DemEngine dem(two_grains(), s);
  dem.step();
  EXPECT_DOUBLE_EQ(dem.time(), 1e-5);
}

TEST(UnstableStep, StableStepForTheSameGrainsIsAccepted) {
  Scene s = channel_scene();
  s.time.dem_step = 1e-7;
  EXPECT_NO_THROW(DemEngine(two_grains(), s));
}

}  // namespace
}  // namespace fdem
