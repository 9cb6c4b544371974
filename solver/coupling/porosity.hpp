#pragma once
// Element porosity (paper Sect. 3.2), two schemes (scene.coupling.porosity):
//
// centre (the paper's, Eq. 32): eps_e = (V_e - sum_i pi d_i^3 / 6) / V_e over
//   the particles whose centre lies in element e. A particle counts wholly in
//   one element, so porosity jumps when it crosses a face, by a factor 2 in
//   solid fraction between the central tetrahedron (V = h^3/3) and a corner
//   one (h^3/6): peak-to-peak over mean = (pi/2 r^-3) / (1 - 3 pi/4 r^-3) for
//   cell size r d, i.e. 6.37, 2.55, 1.28, 0.46, 0.16 % for r = 3, 4, 5, 7, 10
//   (paper Table 2).
//
// shape_function (smoother): each particle's volume is spread to the 4 nodes
//   of its element with its P1 weights (volume coordinates), nodal solid
//   fraction = nodal solid volume / nodal volume (lumped: sum of V_e/4 over the
//   elements sharing the node), and the element porosity is 1 - the mean of
//   its 4 nodal solid fractions. The weights vary continuously with the
//   position, so porosity has no jump when a particle crosses a face, and the
//   total solid volume sum_e V_e (1 - eps_e) = sum_i V_i is conserved exactly
//   (each node's solid is averaged back with the weights V_e/4 it was divided
//   by). Cost: one more pass over elements; the footprint is the element's
//   node patch (about 2 cells), wider than the centre scheme's.
//
// Floor (scene.coupling.porosity_floor, default 0.1): eps is clamped from
// below. The closures diverge as eps -> 0 (Ergun's viscous term grows like
// (1 - eps) / eps, Eq. 12) and Eq. 32 goes negative when mapped solid volume
// exceeds the element volume, which a coarse mesh with big grains allows
// (channel flow, cell / d = 2.4). 0.1 is far below any physical packing of
// spheres (random close packing 0.36, dense polydisperse beds about 0.25), so
// the floor only removes mapping artefacts and never touches a physical bed;
// how often it bites is counted (floored_elements).
#include <span>
#include <vector>

#include "core/types.hpp"
#include "coupling/particle_mapping.hpp"
#include "dem/particles.hpp"
#include "mesh/box_mesh.hpp"
#include "scene/scene.hpp"

namespace fdem {

struct PorosityUpdate {
  long floored_elements = 0;   // elements clamped to the floor
  double min_porosity = 1.0;   // smallest value before the floor
};

class PorosityField {
 public:
  PorosityField(const BoxMesh& mesh, PorosityScheme scheme, double floor);

  /// Recompute from the particles and their mapping (O(particles + elements),
  /// no allocation after construction).
  PorosityUpdate update(const Particles& particles, const ParticleMapping& mapping);

  std::span<const double> values() const { return porosity_; }  // per element, floored
  double operator[](Index e) const { return porosity_[static_cast<std::size_t>(e)]; }
  PorosityScheme scheme() const { return scheme_; }
  double floor() const { return floor_; }

 private:
  const BoxMesh* mesh_;
  PorosityScheme scheme_;
  double floor_;
  std::vector<double> porosity_;      // per element
  std::vector<double> solid_;         // per element (centre) or per node (shape_function) [m^3]
  std::vector<double> nodal_volume_;  // lumped nodal volume [m^3] (shape_function only)
};

}  // namespace fdem
