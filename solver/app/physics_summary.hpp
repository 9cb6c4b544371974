#pragma once
// The physics a scene switches on, as `fdem run` prints it at the start: the
// effects, the fluid model, and only when the fluid is coupled to the grains
// the drag law, the porosity scheme and the exchange (source term). A dry
// scene names no drag law.
#include <string>
#include <utility>
#include <vector>

#include "scene/scene.hpp"

namespace fdem {

/// (topic, description) pairs: effects, fluid, then with coupling: coupling,
/// drag, porosity, and when the grains act on the fluid: exchange.
std::vector<std::pair<std::string, std::string>> active_physics(const Scene& scene);

}  // namespace fdem
