#pragma once
// Element porosity (paper Sect. 3.2), four schemes (scene.coupling.porosity; a
// row each in coupling_terms/porosity_scheme_table.cpp):
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
// diffused (smoothest): the shape_function nodal solid fraction phi0 is
//   smoothed by one implicit diffusion step on the P1 mesh,
//       (M + L^2 K) phi = M phi0,
//   M the lumped mass (nodal volumes), K the P1 stiffness (Laplacian, natural
//   boundary conditions: no flux through the box faces), L the smoothing
//   length. In a scene L is set in grain diameters
//   (coupling.porosity_smoothing_diameters, default kDefaultSmoothingDiameters
//   = 2, as Lethe's VANS solver recommends) or in metres
//   (coupling.porosity_smoothing_length), and never wider than what it
//   smooths (resolve_smoothing_length below). The element porosity
//   is 1 - the mean of its 4 smoothed nodal values (the element average of the
//   P1 field). Why it is smoother: one implicit diffusion damps a Fourier
//   mode of wavenumber k by 1 / (1 + L^2 k^2). What the shape-function scheme
//   leaves (the central and corner tetrahedra average different node
//   patches) repeats with the mesh, whose period is 2 cells (odd and even
//   layouts alternate): k = pi / h, so L = h cuts it by 1 + pi^2 = 11.
//   Measured on the offset line at cell / d = 3 (test_porosity_diffused):
//   12.8x at L = h, 1.76 / 4.0 / 7.7 / 27 / 45x at L / h = 0.25 / 0.5 /
//   0.75 / 1.5 / 2, within 15 % of 1 + (pi L / h)^2. The grain's total solid
//   is spread over about L around it.
//   Properties, each tested (tests/test_porosity_diffused.cpp):
//   - solid volume conserved: K 1 = 0 and K symmetric, so 1^T M phi =
//     1^T M phi0 = sum of the particle volumes, and sum_e V_e (1 - eps_e) =
//     sum_n M_n phi_n (each element averages its nodes with the weights V_e/4
//     that make up M). The solve is iterative (CG to 1e-10), so the left-over
//     residual is removed by rescaling phi (a factor within 1e-10 of 1,
//     measured 2e-12 on 69k nodes; PorosityUpdate::conservation_correction).
//   - no new extrema: the 5-tet split has no obtuse dihedral angle (central
//     tetrahedron 70.5 deg, corner ones 90 and 54.7 deg), so K's off-diagonal
//     entries are <= 0 (assembled on cubic cells: all < 0, at most -h/12)
//     and M + L^2 K (lumped M) is an M-matrix: phi is a convex combination
//     of the phi0 values, 0 <= phi <= max phi0, and the
//     scheme never makes an element denser than shape_function does (a
//     consistent mass would lose this, hence lumped).
//   Cost: the matrix and its Jacobi preconditioner are built once (the mesh
//   is fixed); each update is one CG solve from a zero start (deterministic,
//   so a resumed run repeats the straight one), O(nodes x iterations). The
//   generalised eigenvalues of (M + L^2 K, M) lie in [1, 1 + 14.4 L^2 / h^2]
//   (largest eigenvalue of M^-1 K is 14.4 / h^2 on cubic cells, measured by
//   power iteration on 5^3 to 20^3 cells: 15.4 at L = h), whatever the mesh
//   size, so the count does not grow with the mesh: 31-34 iterations from
//   1.3k to 69k nodes at L = h, about 0.6 us per node per update on one core
//   (vs 0.02 us for shape_function). Wall time per study run: verification/mesh_sensitivity.
//   The drag then sees the grain's solid spread over about L, i.e. a porosity
//   nearer 1 than the other schemes: the single-grain terminal velocity moves
//   toward the isolated-sphere value (numbers in the study's README).
//
// intersection (dense beds on coarse cells): each grain's solid goes to every
//   element it overlaps, by the exact volume of the sphere inside the
//   tetrahedron (coupling/sphere_tetrahedron_volume.hpp), eps_e = 1 - solid_e
//   / V_e. No smoothing length: a bed's porosity and extent are kept exactly
//   (sum_e solid_e = the grains' volume inside the box, to round-off; no
//   solid outside the grains), and a grain crossing a face moves its volume
//   continuously. Grains whose centre is outside the box still count with the
//   part of them inside it. Cost: per grain the 5 tetrahedra of each cell its
//   bounding box touches (8 cells at most while cell >= d), each 4 faces x 3
//   edges of closed-form terms: about 0.7 us per grain on the plume problem,
//   200x the centre scheme's (benchmarks/README.md, BM_Porosity).
//
// Floor (scene.coupling.porosity_floor, default 0.1): eps is clamped from
// below. The closures diverge as eps -> 0 (Ergun's viscous term grows like
// (1 - eps) / eps, Eq. 12) and Eq. 32 goes negative when mapped solid volume
// exceeds the element volume, which a coarse mesh with big grains allows
// (channel flow, cell / d = 2.4). 0.1 is far below any physical packing of
// spheres (random close packing 0.36, dense polydisperse beds about 0.25), so
// the floor only removes mapping artefacts and never touches a physical bed;
// how often it bites is counted (floored_elements).
#include <memory>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "core/particles.hpp"
#include "core/types.hpp"
#include "coupling/particle_mapping.hpp"
#include "mesh/box_mesh.hpp"
#include "parallel/grain_share.hpp"
#include "scene/scene.hpp"

namespace fdem {

struct PorosityUpdate {
  long floored_elements = 0;   // elements clamped to the floor
  double min_porosity = 1.0;   // smallest value before the floor
  int smoothing_iterations = 0;          // diffused: CG iterations of this update
  double conservation_correction = 1.0;  // diffused: factor applied to phi to restore the solid volume
};

/// Default smoothing length of the diffused scheme, in cells (largest cell
/// edge): the smallest round value that makes the offset grain's amplitudes at
/// cell / d = 3 fall below the centre scheme's at cell / d = 10 with margin
/// (measured sweep of L / h in verification/mesh_sensitivity/README.md).
inline constexpr double kDefaultSmoothingCells = 1.0;

/// Default smoothing length of the diffused scheme in a scene, in diameters of
/// the largest grain (Lethe's VANS void-fraction smoothing, about 2 d).
inline constexpr double kDefaultSmoothingDiameters = 2.0;

/// A bed of thickness H keeps at least 1 - exp(-H / (2 L)) = 95 % of its solid
/// fraction at its centre under the diffusion's 1D kernel exp(-|x| / L) / (2 L)
/// when L <= H / 6: the cap on L per thickness.
inline constexpr double kSmoothingPerBedThickness = 1.0 / 6.0;

/// The diffused scheme's smoothing length for a scene and its grains at the
/// start: requested = porosity_smoothing_length, or porosity_smoothing_diameters
/// (default 2) times the largest diameter; cap = the larger of one cell (a
/// length below the cell does not widen the P1 footprint the smoothing starts
/// from) and kSmoothingPerBedThickness times the thinnest extent of the grains'
/// bounding box along an axis they do not span from wall to wall (within one
/// diameter of both box faces); length = min(requested, cap). No grains: one cell.
struct SmoothingLength {
  double length = 0.0;     // [m] what the field uses
  double requested = 0.0;  // [m]
  double cap = 0.0;        // [m]
};
SmoothingLength resolve_smoothing_length(const CouplingSpec& coupling, const BoxMesh& mesh,
                                         const Particles& particles);

struct PorosityDiffusion;  // the diffused scheme's matrix and solver (porosity.cpp)

class PorosityField {
 public:
  /// smoothing_length [m]: the diffused scheme's L (> 0); unset: kDefaultSmoothingCells
  /// times the largest cell edge. Ignored by the other schemes.
  PorosityField(const BoxMesh& mesh, PorosityScheme scheme, double floor,
                std::optional<double> smoothing_length = std::nullopt);
  /// The scene's settings (scheme, floor, smoothing length in metres or one cell).
  PorosityField(const BoxMesh& mesh, const CouplingSpec& coupling);
  /// The scene's settings with the smoothing length resolved against its grains
  /// (resolve_smoothing_length: in diameters, capped by the bed).
  PorosityField(const BoxMesh& mesh, const CouplingSpec& coupling, const Particles& particles);
  ~PorosityField();
  PorosityField(PorosityField&&) noexcept;
  PorosityField& operator=(PorosityField&&) noexcept;

  /// Recompute from the particles and their mapping (O(particles + elements),
  /// no allocation after construction; diffused: plus one CG solve, whose
  /// work vectors Eigen allocates per solve, O(nodes)).
  /// Decomposed over MPI ranks (share): this rank's owned grains, the
  /// solid volumes then completed where this rank needs them (per element,
  /// porosity 1 elsewhere; per node, on the corners of those elements, or
  /// on every node for the diffused scheme's solve over the mesh), the
  /// least porosity and the floored count over this rank's owned elements
  /// (parallel/grain_share.hpp).
  PorosityUpdate update(const Particles& particles, const ParticleMapping& mapping, const GrainShare& share = {});

  /// The transpose of update()'s deposit, for a field f of 3-vectors given
  /// per element: out[i] = sum_e s_ie f_e / V_i, s_ie the part of grain i's
  /// volume V_i that update() put into element e's solid V_e (1 - eps_e)
  /// (for the diffused scheme after the smoothing; linear in V_i). So
  /// sum_i V_i out[i] = sum_e V_e (1 - eps_e) f_e for every f: what a grain
  /// takes with it is exactly what its solid weighs in the field (floor
  /// aside). Call after update() with the same particles and mapping; out
  /// has particles.size() entries, zero for grains that deposited nothing.
  /// Cost: one pass over grains (intersection: the overlaps again; diffused:
  /// plus three CG solves with the smoothing operator, which is symmetric).
  void grain_means(const Particles& particles, const ParticleMapping& mapping, std::span<const Vec3> element_field,
                   std::span<Vec3> out);

  std::span<const double> values() const { return porosity_; }  // per element, floored
  double operator[](Index e) const { return porosity_[static_cast<std::size_t>(e)]; }
  PorosityScheme scheme() const { return scheme_; }
  double floor() const { return floor_; }
  double smoothing_length() const { return smoothing_length_; }  // [m]; 0 unless diffused

 private:
  void add_intersection_volumes(const Particles& particles, const GrainShare& share);
  // Calls visit(element, volume) for every element grain i's sphere overlaps.
  template <class Visit>
  void for_each_overlap(const Particles& particles, std::size_t i, Visit&& visit) const;

  const BoxMesh* mesh_;
  PorosityScheme scheme_;
  const PorositySchemeEntry* entry_;  // the scheme's row: where the solid goes, whether it is smoothed
  double floor_;
  std::vector<double> porosity_;      // per element
  std::vector<double> solid_;         // per element (centre, intersection) [m^3]; per node: solid volume [m^3], then fraction
  std::vector<double> nodal_volume_;  // lumped nodal volume [m^3] (shape_function, diffused)
  // (intersection) the last update()'s non-zero overlaps (element, volume) in
  // for_each_overlap's order, grain i's in [overlap_start_[i], overlap_start_[i + 1]):
  // grain_means sums them again instead of recomputing the sphere-tetrahedron volumes.
  std::vector<std::pair<Index, double>> overlaps_;
  std::vector<Index> overlap_elements_;  // the elements of overlaps_, as the decomposed sum takes them
  std::vector<Index> touched_nodes_;     // (shape_function, diffused) the nodes the counted grains summed into
  std::vector<std::size_t> overlap_start_;
  std::vector<unsigned char> overlap_kept_;  // 1: grain i's overlaps are in overlaps_ (it was counted)
  double smoothing_length_ = 0.0;     // [m] (diffused)
  std::unique_ptr<PorosityDiffusion> diffusion_;  // (diffused) behind a pointer: the CG solver refers to the matrix
};

}  // namespace fdem
