#pragma once
// A scene file with named changes. Each override sets one key of the file
// (the dotted path the loader's messages use: `time.fluid_step`,
// `particles[0].size`) to a YAML value before the file is validated, so the
// changed scene passes every check of the loader, a misspelt key is refused
// like one in the file, and the change is written where it is made.
// Benchmarks and sweeps run the verified study scenes
// (verification/<study>/*.yaml) this way.
#include <string>
#include <vector>

#include "scene/scene.hpp"

namespace fdem {

struct SceneOverride {
  std::string key;     // dotted path; a list item as name[index]
  std::string value;   // YAML: 0.002, [0.012, 0.012, 0.024], {distribution: uniform, min: 2e-4, max: 3e-4}
  std::string reason;  // why the run differs from the file
};

/// Loads `path` with `overrides` applied in order (a key the file lacks is
/// added). Messages name the file as "<path> with overrides <keys>".
Scene load_scene_with_overrides(const std::string& path, const std::vector<SceneOverride>& overrides);

}  // namespace fdem
