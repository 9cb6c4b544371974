#pragma once
// Element loops that add into node sums, on threads, with sums that do not
// depend on the thread count: the cell layers (constant k) in two colours,
// even k then odd k. A layer's elements touch node levels k and k + 1 only,
// so two layers of one colour share no node: a colour's layers run on
// threads at once, and each node receives its terms in the same order
// (the even layers' elements ascending, then the odd layers') on any number
// of threads. The fluid's monolithic assembly (fluid_solver.cpp) colours its
// layers the same way, restricted to an MPI rank's rows.
#include <cstddef>

#include "mesh/box_mesh.hpp"

namespace fdem {

/// body(e) for every element of `mesh`, layer colour by layer colour; on
/// the OpenMP threads when `threads` (each layer on one thread, its
/// elements ascending).
template <class Body>
void for_each_element_by_layer_colour(const BoxMesh& mesh, bool threads, Body&& body) {
  const auto layers = static_cast<std::ptrdiff_t>(mesh.cells()[2]);
  const Index per_layer = 5 * static_cast<Index>(mesh.cells()[0]) * mesh.cells()[1];
  for (std::ptrdiff_t colour = 0; colour < 2; ++colour) {
    const std::ptrdiff_t count = (layers - colour + 1) / 2;  // layers colour, colour + 2, ...
#pragma omp parallel for schedule(static) if (threads)
    for (std::ptrdiff_t li = 0; li < count; ++li) {
      const Index first = static_cast<Index>(colour + 2 * li) * per_layer;
      for (Index e = first; e < first + per_layer; ++e) body(e);
    }
  }
}

}  // namespace fdem
