// Each benchmarked scene is its verified study scene
// (verification/<study>/*.yaml) changed only where benchmark_scenes.hpp
// names an override. Compared: the scene's key numbers as a checkpoint
// records them (coupling/checkpoint_format.hpp: domain, mesh, effects, fluid,
// contact, steps, coupling, the generated particles bit for bit) and the
// keys it leaves out that change what a run does (end time,
// allow_unstable_step).
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "benchmark_scenes.hpp"
#include "coupling/checkpoint_format.hpp"
#include "scene/particle_generator.hpp"
#include "scene/scene_loader.hpp"

namespace fdem::bench {
namespace {

std::set<std::string> differing_keys(const Scene& a, const Scene& b) {
  const checkpoint::SceneFingerprint fa = checkpoint::scene_fingerprint(a, a.time.subcycles, generate_particles(a));
  const checkpoint::SceneFingerprint fb = checkpoint::scene_fingerprint(b, b.time.subcycles, generate_particles(b));
  std::set<std::string> keys;
  EXPECT_EQ(fa.entries.size(), fb.entries.size());
  for (std::size_t i = 0; i < std::min(fa.entries.size(), fb.entries.size()); ++i)
    if (fa.entries[i] != fb.entries[i]) keys.insert(fa.entries[i].first);
  if (fa.particle_hash != fb.particle_hash) keys.insert("particles");
  if (a.time.end_time != b.time.end_time) keys.insert("time.end");
  if (a.contact.allow_unstable_step != b.contact.allow_unstable_step) keys.insert("contact.allow_unstable_step");
  return keys;
}

// `key` (a fingerprint entry such as mesh.cells.x) lies under the override's
// key (mesh.cells); a change to the particle sets shows as "particles".
bool under(const std::string& key, const SceneOverride& o) {
  if (key == o.key || key.starts_with(o.key + ".")) return true;
  return (key == "particles" || key == "particles.count") && o.key.starts_with("particles");
}

class BenchmarkScenes : public ::testing::TestWithParam<BenchmarkScene> {};

TEST_P(BenchmarkScenes, DifferFromTheirVerifiedSceneOnlyByTheirNamedOverrides) {
  const BenchmarkScene& b = GetParam();
  const std::set<std::string> keys = differing_keys(load_scene(source_path(b.verified_scene)), load_benchmark_scene(b));
  for (const std::string& key : keys) {
    bool named = false;
    for (const SceneOverride& o : b.overrides) named = named || under(key, o);
    EXPECT_TRUE(named) << b.name << ": " << key << " differs from " << b.verified_scene << " but no override names it";
  }
  for (const SceneOverride& o : b.overrides) {
    bool changes = false;
    for (const std::string& key : keys) changes = changes || under(key, o);
    EXPECT_TRUE(changes) << b.name << ": the override of " << o.key << " changes nothing";
    EXPECT_FALSE(o.reason.empty()) << b.name << ": the override of " << o.key << " gives no reason";
  }
}

INSTANTIATE_TEST_SUITE_P(Studies, BenchmarkScenes, ::testing::ValuesIn(benchmark_scenes()),
                         [](const auto& param_info) { return param_info.param.name; });

// The comparison sees a change nobody named: the settling scene with a
// stiffer wall spring and another fluid step differs in exactly those keys.
TEST(BenchmarkSceneComparison, SeesAChangeNoOverrideNames) {
  const std::string settling = source_path("verification/settling/settling.yaml");
  const Scene changed = load_scene_with_overrides(
      settling, {{"contact.kn", "100", "test"}, {"time.fluid_step", "0.005", "test"}});
  const std::set<std::string> keys = differing_keys(load_scene(settling), changed);
  EXPECT_EQ(keys, (std::set<std::string>{"contact.kn", "time.fluid_step", "time.subcycles"}));
}

}  // namespace
}  // namespace fdem::bench
