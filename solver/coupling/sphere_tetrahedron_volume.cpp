#include "coupling/sphere_tetrahedron_volume.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "core/types.hpp"

namespace fdem {
namespace {

// Eq. (2)-(4) of the header: the integral of k over the right triangle with
// legs s (foot to edge line) and |t| (along the edge), signed like t.
double right_triangle_integral(double radius, double height, double s, double t) {
  const double sign = t < 0.0 ? -1.0 : 1.0;
  t = std::abs(t);
  const double phi = std::atan2(t, s);
  const double a = std::sqrt(height * height + s * s);
  // J(phi) from sin(phi); at H = 0 its limit sin(phi) / s.
  auto j = [&](double sin_phi) { return height > 0.0 ? std::asin(height * sin_phi / a) / height : sin_phi / a; };
  const double sin_phi = t / std::sqrt(s * s + t * t);
  const double r3 = radius * radius * radius;
  if (radius <= height) return sign * r3 * (phi / height - j(sin_phi));  // Eq. (3)
  const double r0_sq = radius * radius - height * height;
  double inner = 0.0, phi1 = 0.0, sin_phi1 = 0.0;
  if (s * s < r0_sq) {
    const double half_chord = std::sqrt(r0_sq - s * s);  // the disc r0 meets the edge line at m +- half_chord
    const double t1 = std::min(t, half_chord);
    inner = 0.5 * s * t1;
    phi1 = std::atan2(t1, s);
    sin_phi1 = t1 / std::sqrt(s * s + t1 * t1);
  }
  return sign * (inner + (phi - phi1) * (0.5 * r0_sq + radius * radius) - r3 * (j(sin_phi) - j(sin_phi1)));  // Eq. (4)
}

}  // namespace

double sphere_tetrahedron_volume(const Vec3& centre, double radius, const std::array<Vec3, 4>& vertices) {
  // Faces opposite each vertex, with outward unit normals and signed heights.
  struct Face {
    std::array<Vec3, 3> corner;  // counter-clockwise seen from outside
    Vec3 normal;
    double height;
  };
  std::array<Face, 4> faces;
  bool whole_ball = true;
  for (std::size_t i = 0; i < 4; ++i) {
    std::array<Vec3, 3> f{vertices[(i + 1) % 4], vertices[(i + 2) % 4], vertices[(i + 3) % 4]};
    Vec3 n = (f[1] - f[0]).cross(f[2] - f[0]);
    const double norm = n.norm();
    if (!(norm > 0.0)) return 0.0;  // degenerate face: zero volume
    n /= norm;
    if (n.dot(vertices[i] - f[0]) > 0.0) {
      n = -n;
      std::swap(f[1], f[2]);
    }
    const double height = (f[0] - centre).dot(n);
    if (height <= -radius) return 0.0;  // the ball lies wholly outside this face's half-space
    whole_ball = whole_ball && height >= radius;
    faces[i] = Face{f, n, height};
  }
  if (whole_ball) return sphere_volume(2.0 * radius);
  double volume = 0.0;
  for (const Face& f : faces) {
    if (f.height == 0.0) continue;  // the pyramid over this face is flat
    const Vec3 foot = centre + f.height * f.normal;
    const double h = std::abs(f.height);
    double integral = 0.0;  // I_f of Eq. (1)
    for (std::size_t k = 0; k < 3; ++k) {
      const Vec3 a = f.corner[k] - foot, b = f.corner[(k + 1) % 3] - foot;
      const Vec3 edge = b - a;
      const Vec3 e = edge / edge.norm();
      const double ta = a.dot(e), tb = b.dot(e);
      const Vec3 to_line = a - ta * e;  // foot -> m
      const double s = to_line.norm();
      if (s <= 1e-15 * edge.norm()) continue;  // foot on the edge's line: the triangle (foot, a, b) is flat
      const double orientation = to_line.cross(e).dot(f.normal) > 0.0 ? 1.0 : -1.0;
      integral += orientation * (right_triangle_integral(radius, h, s, tb) - right_triangle_integral(radius, h, s, ta));
    }
    volume += f.height / 3.0 * integral;
  }
  return std::clamp(volume, 0.0, sphere_volume(2.0 * radius));
}

}  // namespace fdem
