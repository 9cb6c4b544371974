#include "fluid/fluid_boundary.hpp"

namespace fdem {

FluidConstraints fluid_constraints(const BoxMesh& mesh, const FluidSpec& spec) {
  const auto n = static_cast<std::size_t>(mesh.num_nodes());
  FluidConstraints c;
  c.velocity_fixed.assign(3 * n, 0);
  c.velocity_value.assign(3 * n, 0.0);
  c.fully_prescribed.assign(n, 0);
  c.superficial.assign(n, 0);

  auto prescribe_all = [&](Index node, const Vec3& value) {
    const auto s = static_cast<std::size_t>(node);
    for (std::size_t d = 0; d < 3; ++d) {
      c.velocity_fixed[3 * s + d] = 1;
      c.velocity_value[3 * s + d] = value[static_cast<Eigen::Index>(d)];
    }
    c.fully_prescribed[s] = 1;
  };

  // Strength order: free_slip < inlet < no_slip (see the header).
  for (FaceCondition pass : {FaceCondition::free_slip, FaceCondition::inlet, FaceCondition::no_slip}) {
    for (int f = 0; f < box_face_count; ++f) {
      const FaceBoundary& face = spec.faces[static_cast<std::size_t>(f)];
      if (face.condition != pass) continue;
      const auto nodes = mesh.face_nodes(static_cast<BoxFace>(f));
      for (Index node : nodes) {
        const auto s = static_cast<std::size_t>(node);
        switch (pass) {
          case FaceCondition::free_slip: {
            const auto axis = static_cast<std::size_t>(f / 2);
            c.velocity_fixed[3 * s + axis] = 1;
            c.velocity_value[3 * s + axis] = 0.0;
            break;
          }
          case FaceCondition::inlet:
            prescribe_all(node, mesh.node(node).z() > face.inlet_above_m ? face.velocity : Vec3::Zero());
            c.superficial[s] = face.superficial ? 1 : 0;
            break;
          default:
            prescribe_all(node, Vec3::Zero());
            c.superficial[s] = 0;
        }
      }
    }
  }
  bool has_outlet = false;
  for (const auto& face : spec.faces) has_outlet = has_outlet || face.condition == FaceCondition::outlet;
  c.pressure_node = has_outlet ? -1 : 0;
  return c;
}

}  // namespace fdem
