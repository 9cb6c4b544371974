#pragma once
// Exact volume of a sphere (ball) intersected with a tetrahedron, in closed
// form: the solid a grain puts into each element of the `intersection`
// porosity scheme (coupling/porosity.hpp).
//
// Derivation (written here because it is ours; Strobl, Formella & Poeschel
// 2016, J. Comput. Phys. 311, reach the same volume by another route).
// Ball B of centre c and radius R, tetrahedron T with faces f, outward unit
// normals n_f and signed heights h_f = (x_f - c) . n_f (x_f on f; h_f > 0
// when c is on T's side of f). T's indicator is the signed sum of the
// pyramids from c over its faces, so
//
//   V(B n T) = sum_f (h_f / 3) I_f,   I_f = int_f k(r) dA,   k = min(1, R^3 / rho^3),     (1)
//
// rho = sqrt(h_f^2 + r^2) the distance from c of the face point at distance r
// from the foot q_f = c + h_f n_f (a ray from c through that point leaves the
// ball at R or meets f at rho: the pyramid's volume element is
// (h_f / 3) min(rho, R)^3 / rho^3 dA). The face is the signed sum of the
// triangles (q_f, a, b) over its edges a -> b, each the difference of two
// right triangles with the right angle at the foot m of q_f on the edge's
// line (s = |q_f m|, t measured along the edge from m), so I_f is a sum of
//
//   G(t) = int_0^atan(t/s) g(phi) dphi,  g(phi) = int_0^{s sec phi} k(r) r dr,            (2)
//
// which is elementary: with H = |h_f|, r0^2 = R^2 - H^2 and
// J(phi) = int_0^phi dphi' / sqrt(H^2 + s^2 sec^2 phi')
//        = asin(H sin phi / sqrt(H^2 + s^2)) / H,
//   R <= H:  G = R^3 (Phi / H - J(Phi))                                                   (3)
//   R >  H:  G = (s / 2) min(t, sqrt(r0^2 - s^2))                  [inside the disc r0]
//              + (Phi - phi1) (r0^2 / 2 + R^2) - R^3 (J(Phi) - J(phi1)),                   (4)
// Phi = atan(t / s), phi1 = min(Phi, acos(s / r0)) (0 when s >= r0).
// Checks (tests/test_sphere_tetrahedron_volume.cpp): R -> infinity gives
// sum_f h_f A_f / 3 = V(T); against Monte-Carlo on random configurations; the
// five tetrahedra of a cell sum to the ball inside the cell.
#include <array>

#include "core/types.hpp"

namespace fdem {

/// Volume [m^3] of the ball (centre, radius > 0) inside the tetrahedron with
/// the given vertices (either orientation; a degenerate one gives 0).
double sphere_tetrahedron_volume(const Vec3& centre, double radius, const std::array<Vec3, 4>& vertices);

}  // namespace fdem
