#pragma once
// Element loops that add into node sums, on threads, with sums that do not
// depend on the thread count: the cell layers (constant k) in two colours,
// even k then odd k. A layer's elements touch node levels k and k + 1 only,
// so two layers of one colour share no node: a colour's layers run on
// threads at once, and each node receives its terms in the same order
// (the even layers' elements ascending, then the odd layers') on any number
// of threads. Both fluid schemes assemble through here: the monolithic one
// on an MPI rank's layers, the projection scheme on all.
#include <algorithm>
#include <cstddef>

#include "mesh/box_mesh.hpp"

namespace fdem {

/// Whether a thread team pays for the layer-coloured loops over `mesh`:
/// above 1024 cells a colour; below, a team's start (two a loop, one a
/// colour) costs about what it saves.
inline bool layer_colours_worth_threads(const BoxMesh& mesh) { return mesh.num_cells() > 2 * 1024; }

/// Cell layers first_layer .. last_layer (inclusive) of a mesh.
struct LayerRange {
  Index first_layer = 0;
  Index last_layer = -1;
  static LayerRange all(const BoxMesh& mesh) { return {0, static_cast<Index>(mesh.cells()[2]) - 1}; }
};

/// body(e, workspace) for every element of the layers in `range`, layer
/// colour by layer colour; on the OpenMP threads when `threads` (each layer
/// on one thread, its elements ascending; a thread's workspace from
/// make_workspace(), made once a colour). Leaving out the layers outside
/// `range` changes no in-range node's order of terms, so a rank's rows sum
/// as one process's do; the threads share out the range's layers only.
template <class MakeWorkspace, class Body>
void for_each_element_by_layer_colour(const BoxMesh& mesh, LayerRange range, bool threads,
                                      MakeWorkspace&& make_workspace, Body&& body) {
  const Index first = std::max<Index>(range.first_layer, 0);
  const Index last = std::min<Index>(range.last_layer, static_cast<Index>(mesh.cells()[2]) - 1);
  const Index per_layer = 5 * static_cast<Index>(mesh.cells()[0]) * mesh.cells()[1];
  for (Index colour = 0; colour < 2; ++colour) {
    const Index start = first + ((first - colour) & 1);  // the range's first layer of this colour
    const std::ptrdiff_t count = start <= last ? (last - start) / 2 + 1 : 0;  // layers start, start + 2, ...
#pragma omp parallel if (threads)
    {
      auto workspace = make_workspace();
#pragma omp for schedule(static)
      for (std::ptrdiff_t li = 0; li < count; ++li) {
        const auto layer = static_cast<Index>(start + 2 * li);
        for (Index e = layer * per_layer; e < (layer + 1) * per_layer; ++e) body(e, workspace);
      }
    }
  }
}

/// body(e) for every element of `mesh`, as above.
template <class Body>
void for_each_element_by_layer_colour(const BoxMesh& mesh, bool threads, Body&& body) {
  struct NoWorkspace {};
  for_each_element_by_layer_colour(
      mesh, LayerRange::all(mesh), threads, [] { return NoWorkspace{}; },
      [&body](Index e, NoWorkspace&) { body(e); });
}

}  // namespace fdem
