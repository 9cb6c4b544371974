#pragma once
// Particle mapping (paper Sect. 3.1, Eq. 23-31): the element holding each
// particle centre and its volume coordinates there (the P1 shape function
// values used to interpolate the fluid velocity and to spread volume/force).
// The cell and element search is BoxMesh::locate_element (four tests per
// particle against the central tetrahedron); its tie rule is documented there:
// a point on a cell face belongs to the cell above it (the last cell on the
// box's upper faces), and a point on the central tetrahedron's boundary
// belongs to the central tetrahedron.
#include <array>
#include <span>
#include <vector>

#include "core/particles.hpp"
#include "core/types.hpp"
#include "mesh/box_mesh.hpp"

namespace fdem {

struct ParticleMapping {
  std::vector<Index> element;                   // -1: centre outside the mesh
  std::vector<std::array<double, 4>> weights;   // volume coordinates in `element` (zero when outside)
  long outside = 0;                             // particles outside the mesh at the latest update

  /// Locate every particle (O(particles), no allocation once sized).
  void update(const BoxMesh& mesh, const Particles& particles);
};

}  // namespace fdem
