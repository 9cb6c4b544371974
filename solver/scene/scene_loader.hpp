#pragma once
// Reads a scene file (YAML) into fdem::Scene and validates it completely, so a
// bad scene is refused before anything runs. Every refusal is one
// fdem::InputError naming the file, the key (dotted path, e.g.
// `fluid.viscosity`, `particles[1].size.sd`), its line and the value.
// The schema, with every key, unit and default, is in examples/README.md.
#include <string>

#include "scene/scene.hpp"

namespace fdem {

/// Loads and validates the scene at `path` (relative paths inside it, such as
/// a csv particle file, are taken relative to the scene file's folder).
Scene load_scene(const std::string& path);

/// The same from text already in memory; `file_name` names it in messages and
/// `base_dir` resolves relative paths. Used by tests and the fuzzer.
Scene load_scene_from_string(const std::string& text, const std::string& file_name,
                             const std::string& base_dir = ".");

/// Largest diameter a size distribution can produce [m].
double largest_diameter(const SizeDistribution& size);
/// Smallest diameter a size distribution can produce [m].
double smallest_diameter(const SizeDistribution& size);

}  // namespace fdem
