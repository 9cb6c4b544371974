#pragma once
// Structured box mesh of hexahedral cells, each split into 5 tetrahedra
// (paper Sect. 3.1, Fig. 6-10): one central tetrahedron (1/3 of the cell) and
// four corner tetrahedra (1/6 each).
//
// Layouts. Local cell vertex v = a + 2b + 4c for the corner at offset (a,b,c).
// The "even" layout's central tetrahedron joins the vertices with a+b+c even,
// the "odd" layout's those with a+b+c odd. A cell (i,j,k) takes the even layout
// when i+j+k is even. Then every central tetrahedron joins global nodes with
// I+J+K even, so both cells sharing a face cut it along the same diagonal and
// the mesh is conforming. (The paper picks the layout from the parity of the
// cell identifier of Eq. 26; that equals the parity of i+j+k only when nx and
// nx*ny are odd, so we use i+j+k.)
//
// Numbering. Cells and nodes follow Eq. 23-26 with 0-based indices:
// cell = i + nx*(j + ny*k), node = I + (nx+1)*(J + (ny+1)*K). Element
// e = 5*cell + local; local 0 is the central tetrahedron and local 1+m is the
// corner tetrahedron across the central one's facet opposite its vertex m, so
// the volume-coordinate test of Eq. 27-31 names the element directly.
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "core/types.hpp"

namespace fdem {

/// The six box faces, in the order used for boundary conditions everywhere.
enum class BoxFace { x_min = 0, x_max, y_min, y_max, z_min, z_max };
inline constexpr int box_face_count = 6;

class BoxMesh {
 public:
  using ShapeGradients = Eigen::Matrix<double, 4, 3>;  // row a = grad N_a, constant on a P1 tetrahedron

  /// lower/upper corners [m] and cell counts per direction (each >= 1).
  BoxMesh(const Vec3& lower, const Vec3& upper, const std::array<int, 3>& cells);

  const Vec3& lower() const { return lower_; }
  const Vec3& upper() const { return upper_; }
  const Vec3& cell_size() const { return cell_size_; }
  const std::array<int, 3>& cells() const { return cells_; }

  Index num_cells() const { return static_cast<Index>(cells_[0]) * cells_[1] * cells_[2]; }
  Index num_elements() const { return 5 * num_cells(); }
  Index num_nodes() const { return static_cast<Index>(cells_[0] + 1) * (cells_[1] + 1) * (cells_[2] + 1); }

  Index node_index(int i, int j, int k) const { return i + (cells_[0] + 1) * (j + (cells_[1] + 1) * k); }
  Index cell_index(int i, int j, int k) const { return i + cells_[0] * (j + cells_[1] * k); }
  Vec3 node(Index n) const;
  std::array<int, 3> cell_ijk(Index cell) const;

  const std::array<Index, 4>& element_nodes(Index e) const { return elements_[static_cast<std::size_t>(e)]; }
  double element_volume(Index e) const { return shape_[shape_of(e)].volume; }
  const ShapeGradients& shape_gradients(Index e) const { return shape_[shape_of(e)].gradients; }
  Vec3 element_centroid(Index e) const;

  /// Eq. 28-31: volume coordinates (P1 shape function values) of p in element e.
  Eigen::Vector4d volume_coordinates(Index e, const Vec3& p) const;

  /// Eq. 23-26: the cell holding p, or -1 outside the box. A point on a cell
  /// face belongs to the cell above it (truncation); on the box's upper faces
  /// it belongs to the last cell.
  Index locate_cell(const Vec3& p) const;

  /// Eq. 27-31: the element holding p, or -1 outside the box. Four tests
  /// against the central tetrahedron: all volume coordinates >= 0 means the
  /// central one (so its own faces, edges and vertices belong to it);
  /// otherwise the most negative coordinate names the corner element, the
  /// lowest local index winning a tie.
  Index locate_element(const Vec3& p) const;

  /// Nodes on one box face (edges and corners appear on every face they touch).
  std::vector<Index> face_nodes(BoxFace face) const;

 private:
  struct Shape {
    ShapeGradients gradients;
    double volume = 0.0;
  };
  // The mesh is translation invariant: 2 layouts x 5 tetrahedra = 10 shapes.
  // Looked up per element (a byte each): every assembly loop asks per
  // element, and deriving it (two divisions and the cell's parity) cost 4 %
  // of the plume's fluid step (perf, 2026-12-07).
  std::size_t shape_of(Index e) const { return element_shape_[static_cast<std::size_t>(e)]; }

  Vec3 lower_, upper_, cell_size_;
  std::array<int, 3> cells_;
  std::vector<std::array<Index, 4>> elements_;
  std::vector<std::uint8_t> element_shape_;  // element -> its entry of shape_
  std::array<Shape, 10> shape_{};
};

}  // namespace fdem
