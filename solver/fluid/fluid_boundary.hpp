#pragma once
// Velocity and pressure constraints from the scene's six face conditions.
//
// Per velocity component, from weakest to strongest (a later rule overrides an
// earlier one at shared edges and corners):
//   free_slip  the face-normal component is 0 (box faces are axis aligned);
//              the tangential stress is the natural condition (zero).
//   inlet      all three components = the face's velocity on nodes with
//              z > inlet_above_m, 0 on the face's nodes at or below it (the bed);
//              with `superficial` the value is eps u (the solver divides by
//              the node's porosity for a volume-averaged model).
//   no_slip    all three components = 0.
//   outlet     nothing: the natural condition mu du/dn - p n = 0 (traction free).
// The pressure is pinned to 0 at node 0 when no face is an outlet, since only
// its gradient is then defined.
#include <cstdint>
#include <vector>

#include "core/types.hpp"
#include "mesh/box_mesh.hpp"
#include "scene/scene.hpp"

namespace fdem {

struct FluidConstraints {
  std::vector<std::uint8_t> velocity_fixed;   // 3*num_nodes: component prescribed
  std::vector<double> velocity_value;         // 3*num_nodes: the scene's value [m/s]
  std::vector<std::uint8_t> fully_prescribed; // num_nodes: all three components from no_slip/inlet
  std::vector<std::uint8_t> superficial;      // num_nodes: value is a superficial velocity (inlet superficial: true)
  Index pressure_node = -1;                   // pinned to 0, or -1 when an outlet exists
};

FluidConstraints fluid_constraints(const BoxMesh& mesh, const FluidSpec& spec);

}  // namespace fdem
