#pragma once
// The resolved numbers of a scene, key by key of the schema
// (scene/scene_schema.hpp): what changes the result of a step, so what a
// checkpoint's scene fingerprint holds (coupling/checkpoint_format.hpp) and a
// restart must find unchanged. The keys are the schema's, in its order: every
// leaf key the schema does not exempt (scene_schema.hpp,
// fingerprint_exemption) has a value here, so a new key cannot be left out of
// the fingerprint unnoticed.
#include <string>
#include <utility>
#include <vector>

#include "scene/scene.hpp"

namespace fdem {

/// (name, value) pairs. Names are schema paths with a vector's component
/// (`domain.lower.x`), a face's name (`fluid.boundaries.x_min.type`) spelt
/// out; enumerations are their index, flags 0 / 1, an unset optional -1,
/// a string 53 bits of its hash.
using SceneKeyValues = std::vector<std::pair<std::string, double>>;

/// The values of every fingerprinted schema key of `scene`, in schema order.
/// Throws std::logic_error naming a fingerprinted key that has no value here
/// (a key added to the schema and not to scene_key_values.cpp).
SceneKeyValues fingerprinted_values(const Scene& scene);

/// The schema paths scene_key_values.cpp gives values for (for the tests:
/// each must be a fingerprinted key of the schema).
std::vector<std::string> keys_with_values();

}  // namespace fdem
