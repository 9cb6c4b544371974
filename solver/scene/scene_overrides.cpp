#include "scene/scene_overrides.hpp"

#include <cstddef>
#include <filesystem>
#include <string_view>

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include "core/error.hpp"
#include "scene/scene_loader.hpp"

namespace fdem {

namespace {

// The node at `key` below `root`, created when missing (maps only: a list
// index must exist).
YAML::Node node_at(YAML::Node root, const std::string& file, const SceneOverride& o) {
  YAML::Node node = root;
  std::string_view rest = o.key;
  while (!rest.empty()) {
    const std::size_t dot = rest.find('.');
    std::string_view part = rest.substr(0, dot);
    rest = dot == std::string_view::npos ? std::string_view{} : rest.substr(dot + 1);
    long index = -1;
    if (const std::size_t open = part.find('['); open != std::string_view::npos) {
      if (part.back() != ']') throw InputError(file, o.key, o.value, "override key: expected name[index]");
      index = std::stol(std::string(part.substr(open + 1, part.size() - open - 2)));
      part = part.substr(0, open);
    }
    if (!node.IsMap() && !node.IsNull()) throw InputError(file, o.key, o.value, "override key: not inside a mapping");
    YAML::Node child = node[std::string(part)];
    node.reset(child);
    if (index >= 0) {
      if (!node.IsSequence() || static_cast<std::size_t>(index) >= node.size())
        throw InputError(file, o.key, o.value, "override key: no such list item in the file");
      YAML::Node item = node[static_cast<std::size_t>(index)];
      node.reset(item);
    }
  }
  return node;
}

}  // namespace

Scene load_scene_with_overrides(const std::string& path, const std::vector<SceneOverride>& overrides) {
  if (overrides.empty()) return load_scene(path);
  std::string keys;
  for (const SceneOverride& o : overrides) keys += (keys.empty() ? "" : ", ") + o.key;
  const std::string name = fmt::format("{} with overrides {}", path, keys);
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw InputError(path, "", "", fmt::format("cannot read the scene: {}", e.what()));
  }
  for (const SceneOverride& o : overrides) {
    YAML::Node value;
    try {
      value = YAML::Load(o.value);
    } catch (const YAML::Exception& e) {
      throw InputError(name, o.key, o.value, fmt::format("override value is not YAML: {}", e.msg));
    }
    YAML::Node target = node_at(root, name, o);
    target = value;
  }
  YAML::Emitter text;
  text << root;
  return load_scene_from_string(text.c_str(), name, std::filesystem::path(path).parent_path().string());
}

}  // namespace fdem
