// The element loop by cell-layer colour (mesh/layer_colouring.hpp): every
// element once, and no node shared by two layers of one colour, which is
// what lets a colour's layers add into node sums on threads at once.
#include "mesh/layer_colouring.hpp"

#include <gtest/gtest.h>
#include <omp.h>

#include <array>
#include <map>
#include <vector>

using fdem::BoxMesh;
using fdem::Index;
using fdem::Vec3;

namespace {

// Visits of each element, and for each node the layers (cell k) that touched it, per colour (k parity).
void check_colouring(const std::array<int, 3>& cells) {
  const BoxMesh mesh(Vec3(0, 0, 0), Vec3(1, 1, 1), cells);
  std::vector<int> visits(static_cast<std::size_t>(mesh.num_elements()), 0);
  std::vector<Index> order;
  fdem::for_each_element_by_layer_colour(mesh, false, [&](Index e) {
    ++visits[static_cast<std::size_t>(e)];
    order.push_back(e);
  });
  for (Index e = 0; e < mesh.num_elements(); ++e) EXPECT_EQ(visits[static_cast<std::size_t>(e)], 1) << "element " << e;
  const Index per_layer = 5 * static_cast<Index>(cells[0]) * cells[1];
  // Even layers first, then odd; each layer's elements ascending.
  for (std::size_t a = 1; a < order.size(); ++a) {
    const Index k0 = order[a - 1] / per_layer, k1 = order[a] / per_layer;
    if (k0 % 2 == k1 % 2) {
      EXPECT_LT(order[a - 1], order[a]) << "within colour " << k0 % 2;
    } else {
      EXPECT_EQ(k0 % 2, 0) << "an even layer after an odd one";
    }
  }
  std::map<Index, std::map<int, std::vector<Index>>> layers_at_node;  // node -> colour -> layers
  for (Index e = 0; e < mesh.num_elements(); ++e) {
    const Index k = e / per_layer;
    for (Index node : mesh.element_nodes(e)) {
      auto& layers = layers_at_node[node][static_cast<int>(k % 2)];
      if (layers.empty() || layers.back() != k) layers.push_back(k);
    }
  }
  for (const auto& [node, by_colour] : layers_at_node)
    for (const auto& [colour, layers] : by_colour)
      EXPECT_EQ(layers.size(), 1u) << "node " << node << ": " << layers.size() << " layers of colour " << colour;
}

}  // namespace

TEST(LayerColouring, EveryElementOnceAndNoNodeInTwoLayersOfAColour) {
  for (const std::array<int, 3>& cells : {std::array<int, 3>{3, 2, 1}, std::array<int, 3>{2, 3, 2},
                                          std::array<int, 3>{4, 3, 5}, std::array<int, 3>{2, 2, 8}})
    check_colouring(cells);
}

// A layer range (an MPI rank's layers): exactly its layers' elements, in
// the order the whole mesh's loop gives them, on 1 and 2 threads, and each
// thread's workspace is its own (made in the thread that uses it).
TEST(LayerColouring, LayerRangeKeepsTheWholeMeshOrder) {
  const BoxMesh mesh(Vec3(0, 0, 0), Vec3(1, 1, 1), {3, 2, 9});
  const Index per_layer = 5 * 3 * 2;
  std::vector<Index> whole;
  fdem::for_each_element_by_layer_colour(mesh, false, [&](Index e) { whole.push_back(e); });
  const fdem::LayerRange range{2, 6};
  std::vector<Index> expected;
  for (Index e : whole)
    if (e / per_layer >= range.first_layer && e / per_layer <= range.last_layer) expected.push_back(e);
  const int saved = omp_get_max_threads();
  for (int threads : {1, 2}) {
    omp_set_num_threads(threads);
    std::vector<int> visits(static_cast<std::size_t>(mesh.num_elements()), 0);
    int wrong_thread = 0;
    fdem::for_each_element_by_layer_colour(
        mesh, range, true, [] { return omp_get_thread_num(); },
        [&](Index e, int& maker) {
          if (maker != omp_get_thread_num()) {
#pragma omp atomic
            ++wrong_thread;
          }
#pragma omp atomic
          ++visits[static_cast<std::size_t>(e)];
        });
    EXPECT_EQ(wrong_thread, 0) << threads << " threads";
    for (Index e = 0; e < mesh.num_elements(); ++e) {
      const bool in_range = e / per_layer >= range.first_layer && e / per_layer <= range.last_layer;
      EXPECT_EQ(visits[static_cast<std::size_t>(e)], in_range ? 1 : 0) << "element " << e << ", " << threads << " threads";
    }
  }
  omp_set_num_threads(saved);
  std::vector<Index> order;
  fdem::for_each_element_by_layer_colour(
      mesh, range, false, [] { return 0; }, [&](Index e, int&) { order.push_back(e); });
  EXPECT_EQ(order, expected);
}

// The threads share out the range's layers, not the whole mesh's: a rank
// holding the lower half of 10 layers (0-4) keeps both threads busy in
// each colour (shared out over all layers, its even layers 0, 2, 4 would
// all fall to thread 0, and thread 1 would get only layers of another rank).
TEST(LayerColouring, ThreadsShareOutTheRangesLayers) {
  const BoxMesh mesh(Vec3(0, 0, 0), Vec3(1, 1, 1), {2, 2, 10});
  const Index per_layer = 5 * 2 * 2;
  const int saved = omp_get_max_threads();
  omp_set_num_threads(2);
  std::array<std::array<int, 2>, 2> elements{};  // [colour][thread]
  int team = 0;
  fdem::for_each_element_by_layer_colour(
      mesh, fdem::LayerRange{0, 4}, true, [] { return omp_get_thread_num(); },
      [&](Index e, int& thread) {
#pragma omp atomic write
        team = omp_get_num_threads();
#pragma omp atomic
        ++elements[static_cast<std::size_t>((e / per_layer) % 2)][static_cast<std::size_t>(thread)];
      });
  omp_set_num_threads(saved);
  ASSERT_EQ(team, 2) << "the runtime gave no second thread";
  for (int colour = 0; colour < 2; ++colour)
    for (int thread = 0; thread < 2; ++thread)
      EXPECT_GT(elements[static_cast<std::size_t>(colour)][static_cast<std::size_t>(thread)], 0)
          << "colour " << colour << ", thread " << thread;
}
