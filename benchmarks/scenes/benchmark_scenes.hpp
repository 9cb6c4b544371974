#pragma once
// The scenes the benchmarks time: the verified study scenes
// (verification/<study>/*.yaml), each with the overrides, named here with
// their reason, that a benchmark needs. test_benchmark_scenes fails when a
// benchmarked scene differs from its verified scene by anything else.
#include <stdexcept>
#include <string>
#include <vector>

#include "scene/scene.hpp"
#include "scene/scene_overrides.hpp"

namespace fdem::bench {

struct BenchmarkScene {
  std::string name;
  std::string verified_scene;  // relative to the source tree
  std::vector<SceneOverride> overrides;
};

inline const std::vector<BenchmarkScene>& benchmark_scenes() {
  static const std::vector<BenchmarkScene> scenes{
      {"settling", "verification/settling/settling.yaml", {}},
      {"channel",
       "verification/channel/channel.yaml",
       {{"coupling.freeze_until", "0",
         "the study holds the grains still for its first 0.05 s (100 steps); a benchmark of its first steps "
         "would time no DEM"}}},
      {"plume", "verification/plume/plume.yaml", {}},
  };
  return scenes;
}

inline std::string source_path(const std::string& relative) { return std::string(FDEM_SOURCE_DIR) + "/" + relative; }

inline Scene load_benchmark_scene(const BenchmarkScene& b) {
  return load_scene_with_overrides(source_path(b.verified_scene), b.overrides);
}

inline Scene load_benchmark_scene(const std::string& name) {
  for (const BenchmarkScene& b : benchmark_scenes())
    if (b.name == name) return load_benchmark_scene(b);
  throw std::invalid_argument("no benchmark scene " + name);
}

}  // namespace fdem::bench
