#pragma once
// The scene file's schema: every key the loader accepts, with its type, its
// default and one line of documentation. `fdem help scene` prints it;
// examples/README.md documents the same keys at length. Tests hold the loader
// (scene_loader.cpp) and every refusal message to it: a key the loader
// accepts and the schema lacks, or a message naming a key the schema lacks,
// fails them (verification/scene_input/test_refusal_keys.cpp).
//
// Paths are dotted; a list's items are `[]` (`particles[].size.mean`), and
// `<face>` stands for each of the six faces under `fluid.boundaries`.
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace fdem {

struct SceneKey {
  std::string_view path;           // e.g. "contact.kn"
  std::string_view type;           // e.g. "number > 0 [N/m]", "map", "one of: bdf1, bdf2"
  std::string_view default_value;  // e.g. "0", "required", "required with fluid"
  std::string_view doc;
  bool is_map = false;             // a mapping whose keys are the paths below it
};

/// Every key, parents before their children, in the order of examples/README.md.
std::span<const SceneKey> scene_schema();

/// A leaf key whose own value is not in a checkpoint's scene fingerprint
/// (coupling/checkpoint_format.hpp): either a restart may change it
/// (`covered_by` empty: end time, output, title), or another entry of the
/// fingerprint holds what it resolves to (`covered_by` names it). Every other
/// leaf key's value is in the fingerprint (scene/scene_key_values.hpp).
struct FingerprintExemption {
  std::string_view path;        // a schema path, or a prefix ending in '.' ("output.")
  std::string_view covered_by;  // "" or the fingerprint entry that holds it
  std::string_view why;
};
std::span<const FingerprintExemption> fingerprint_exemptions();

/// The exemption of the leaf key at schema path `path`, or nullptr when its
/// value is in the fingerprint.
const FingerprintExemption* fingerprint_exemption(std::string_view path);

/// The schema path of a key as messages write it: list indices dropped
/// (`particles[2].size.min` -> `particles[].size.min`) and a face name under
/// fluid.boundaries replaced by `<face>` when it heads a further key.
std::string schema_path_of(std::string_view key);

/// The words of a key whose type is "one of: a, b, c", in that order, which
/// is the order of its enumeration in scene.hpp (word i is value i; tested
/// against the loader); empty for any other key.
std::vector<std::string_view> choice_words(std::string_view path);

/// Word `index` of choice_words(path): how `fdem check` and the run's
/// summary name a setting, as the scene file spells it.
std::string_view choice_word(std::string_view path, std::size_t index);

/// True when `key` (as messages write it) names a key of the schema.
bool is_scene_key(std::string_view key);

/// The keys directly below the map at `path` ("" is the top level), as
/// written in a scene file (`x_min`, not `<face>`).
std::vector<std::string> scene_keys_below(std::string_view path);

/// The schema as `fdem help scene` prints it.
std::string format_scene_schema();

}  // namespace fdem
