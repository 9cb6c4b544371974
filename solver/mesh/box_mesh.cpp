#include "mesh/box_mesh.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <stdexcept>

namespace fdem {

namespace {

// Local vertex v = a + 2b + 4c of the unit cell.
Vec3 local_offset(int v) { return Vec3(v & 1, (v >> 1) & 1, (v >> 2) & 1); }

constexpr std::array<int, 4> central_even{0, 3, 5, 6};
constexpr std::array<int, 4> central_odd{1, 2, 4, 7};

// Tetrahedron `local` (0 central, 1+m corner across facet m) of a layout, as
// local cell vertices. A corner tetrahedron is the central one with vertex m
// replaced by its antipode 7-m: the only cell vertex beyond facet m. The
// central order is the positively oriented one, so that volume coordinate m
// of the stored central tetrahedron names corner 1+m.
std::array<int, 4> local_tet(bool even, int local) {
  std::array<int, 4> t = even ? central_even : central_odd;
  if (even) std::swap(t[2], t[3]);  // {0,3,6,5} and {1,2,4,7} are positively oriented
  if (local > 0) {
    const auto m = static_cast<std::size_t>(local - 1);
    t[m] = 7 - t[m];
  }
  return t;
}

double signed_volume(const std::array<Vec3, 4>& x) {  // Eq. 27
  return (x[1] - x[0]).dot((x[2] - x[0]).cross(x[3] - x[0])) / 6.0;
}

}  // namespace

BoxMesh::BoxMesh(const Vec3& lower, const Vec3& upper, const std::array<int, 3>& cells)
    : lower_(lower), upper_(upper), cells_(cells) {
  for (int d = 0; d < 3; ++d) {
    if (cells_[static_cast<std::size_t>(d)] < 1) throw std::invalid_argument("BoxMesh: cell count must be >= 1");
    if (!(upper_[d] > lower_[d])) throw std::invalid_argument("BoxMesh: upper corner must exceed lower corner");
    cell_size_[d] = (upper_[d] - lower_[d]) / cells_[static_cast<std::size_t>(d)];
  }

  // Ten shapes; a vertex swap makes every stored tetrahedron positively oriented.
  std::array<std::array<int, 4>, 10> local_order{};
  for (int layout = 0; layout < 2; ++layout) {
    for (int local = 0; local < 5; ++local) {
      std::array<int, 4> t = local_tet(layout == 0, local);
      std::array<Vec3, 4> x;
      for (std::size_t a = 0; a < 4; ++a) x[a] = local_offset(t[a]).cwiseProduct(cell_size_);
      if (signed_volume(x) < 0) {
        std::swap(t[2], t[3]);
        std::swap(x[2], x[3]);
      }
      Eigen::Matrix3d jacobian;
      for (int a = 0; a < 3; ++a) jacobian.col(a) = x[static_cast<std::size_t>(a) + 1] - x[0];
      const Eigen::Matrix3d inverse = jacobian.inverse();
      Shape& s = shape_[static_cast<std::size_t>(layout * 5 + local)];
      s.volume = signed_volume(x);
      s.gradients.bottomRows<3>() = inverse;
      s.gradients.row(0) = -inverse.colwise().sum();
      local_order[static_cast<std::size_t>(layout * 5 + local)] = t;
    }
  }

  elements_.resize(static_cast<std::size_t>(num_elements()));
  element_shape_.resize(static_cast<std::size_t>(num_elements()));
  for (int k = 0; k < cells_[2]; ++k)
    for (int j = 0; j < cells_[1]; ++j)
      for (int i = 0; i < cells_[0]; ++i) {
        const Index cell = cell_index(i, j, k);
        const int layout = ((i + j + k) % 2 == 0) ? 0 : 1;
        for (int local = 0; local < 5; ++local) {
          auto& nodes = elements_[static_cast<std::size_t>(5 * cell + local)];
          element_shape_[static_cast<std::size_t>(5 * cell + local)] = static_cast<std::uint8_t>(layout * 5 + local);
          const auto& t = local_order[static_cast<std::size_t>(layout * 5 + local)];
          for (std::size_t a = 0; a < 4; ++a)
            nodes[a] = node_index(i + (t[a] & 1), j + ((t[a] >> 1) & 1), k + ((t[a] >> 2) & 1));
        }
      }
}

Vec3 BoxMesh::node(Index n) const {
  const int nx1 = cells_[0] + 1, ny1 = cells_[1] + 1;
  const int i = n % nx1, j = (n / nx1) % ny1, k = n / (nx1 * ny1);
  return lower_ + Vec3(i, j, k).cwiseProduct(cell_size_);
}

std::array<int, 3> BoxMesh::cell_ijk(Index cell) const {
  return {cell % cells_[0], (cell / cells_[0]) % cells_[1], cell / (cells_[0] * cells_[1])};
}

Vec3 BoxMesh::element_centroid(Index e) const {
  Vec3 c = Vec3::Zero();
  for (Index n : element_nodes(e)) c += node(n);
  return 0.25 * c;
}

Eigen::Vector4d BoxMesh::volume_coordinates(Index e, const Vec3& p) const {
  const Vec3 d = p - node(element_nodes(e)[0]);
  Eigen::Vector4d lambda = shape_gradients(e) * d;
  lambda[0] += 1.0;
  return lambda;
}

Index BoxMesh::locate_cell(const Vec3& p) const {
  std::array<int, 3> ijk{};
  for (int d = 0; d < 3; ++d) {
    if (!(p[d] >= lower_[d] && p[d] <= upper_[d])) return -1;  // also rejects NaN
    const int n = cells_[static_cast<std::size_t>(d)];
    const int i = static_cast<int>((p[d] - lower_[d]) / cell_size_[d]);  // Eq. 23-25, truncation
    ijk[static_cast<std::size_t>(d)] = i < n ? i : n - 1;
  }
  return cell_index(ijk[0], ijk[1], ijk[2]);  // Eq. 26
}

Index BoxMesh::locate_element(const Vec3& p) const {
  const Index cell = locate_cell(p);
  if (cell < 0) return -1;
  const Index central = 5 * cell;
  const Eigen::Vector4d lambda = volume_coordinates(central, p);
  Eigen::Index m = 0;
  const double smallest = lambda.minCoeff(&m);
  if (smallest >= 0.0) return central;
  return central + 1 + static_cast<Index>(m);
}

std::vector<Index> BoxMesh::face_nodes(BoxFace face) const {
  const int f = static_cast<int>(face);
  const int axis = f / 2;
  const int fixed = (f % 2 == 0) ? 0 : cells_[static_cast<std::size_t>(axis)];
  std::vector<Index> out;
  for (int k = 0; k <= cells_[2]; ++k)
    for (int j = 0; j <= cells_[1]; ++j)
      for (int i = 0; i <= cells_[0]; ++i) {
        const std::array<int, 3> ijk{i, j, k};
        if (ijk[static_cast<std::size_t>(axis)] == fixed) out.push_back(node_index(i, j, k));
      }
  return out;
}

}  // namespace fdem
