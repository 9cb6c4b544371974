#pragma once
// The particle source term on the fluid (paper Sect. 3, Fig. 4-5, Eq. 20, 22).
//
// Per element e, over the particles i mapped to it, with f_i the drag on
// particle i averaged over the fluid step and V_i its volume:
//   per-particle source (Eq. 20): F_fp,i = beta_i (u - v_i) = (1 - eps_e) f_i / V_i
//   element average ("source term average on element", Fig. 4), volume
//   weighted so that unequal grains conserve momentum:
//       F_fp,e = sum_i V_i F_fp,i / sum_i V_i = (1 - eps_e) sum_i f_i / sum_i V_i
//   (an unweighted mean would give a small grain the weight of a big one).
// Force density on the fluid in element e (scene.coupling.source_form; the
// closures of coupling_terms/source_form_table.cpp):
//   paper (Eq. 22):    b_e = -F_fp,e / eps_e, applied over the whole element.
//       With the centre porosity (1 - eps_e) V_e = sum_i V_i, so the fluid
//       receives V_e b_e = -sum_i f_i / eps_e: 1/eps_e times the drag, an
//       imbalance of (1/eps_e - 1) (negligible for eps ~ 1, a factor 2.5 in a
//       bed at eps = 0.4).
//   conservative:      b_e = -sum_i f_i / V_e: the fluid receives exactly
//       minus the drag on the particles (Newton's third law), whatever the
//       porosity scheme or floor.
// The volume-averaged models take the conservative form whatever the scene
// says (fluid_source_form): Zhou et al. (2010) couple the fluid to exactly
// minus the grains' force of each model (model A: the drag, whose grains feel
// -V_p grad p beside it; model B: the drag / eps, coupling/drag_coupling.hpp),
// and the paper's F/eps on top of either would count 1/eps twice or where it
// does not belong. The scene key is the simplified model's choice.
// Nodal distribution (Fig. 5d): an element's force V_e b_e goes to its 4
// nodes in equal parts (the P1 weights of a uniform density, int N_a = V_e/4)
// and each node's force is divided by its lumped volume (sum of V_e/4 over
// its elements). The result is a nodal force density whose P1 interpolant
// integrates to exactly the sum of the element forces.
#include <span>
#include <vector>

#include "core/particles.hpp"
#include "core/types.hpp"
#include "coupling/particle_mapping.hpp"
#include "mesh/box_mesh.hpp"
#include "parallel/grain_share.hpp"
#include "scene/scene.hpp"

namespace fdem {

/// The form the fluid receives: scene.coupling.source_form with the
/// simplified model, conservative with vans_a / vans_b (header comment).
SourceForm fluid_source_form(const Scene& scene);

class SourceTerm {
 public:
  SourceTerm(const BoxMesh& mesh, SourceForm form);

  /// Build the nodal body force density from per-particle drag forces [N]
  /// (SoA, particle order of `mapping`), the element porosity (floored) and
  /// the particle volumes. O(particles + elements), no allocation.
  /// Decomposed over MPI ranks (share): this rank's owned grains, the
  /// element sums then completed where this rank needs them
  /// (parallel/grain_share.hpp; 0 elsewhere, and the nodal field right at
  /// the nodes whose elements it needs all), total_force() each element's
  /// owner's share added over the ranks.
  void compute(const Particles& particles, const ParticleMapping& mapping, std::span<const double> porosity,
               std::span<const double> drag_x, std::span<const double> drag_y, std::span<const double> drag_z,
               const GrainShare& share = {});
  /// Zero body force (coupling that does not reach the fluid, frozen start).
  void clear();

  std::span<const double> nodal_force_density() const { return nodal_; }  // 3*num_nodes [N/m^3]
  /// Integral of the body force over the domain [N] (= sum of element forces).
  Vec3 total_force() const { return total_; }
  SourceForm form() const { return form_; }

 private:
  const BoxMesh* mesh_;
  SourceForm form_;
  std::vector<double> element_force_;   // 3 per element [N]: V_e b_e
  std::vector<double> element_solid_;   // sum of particle volumes per element [m^3]
  std::vector<double> nodal_;           // 3 per node [N/m^3]
  std::vector<double> nodal_volume_;    // lumped nodal volume [m^3]
  Vec3 total_ = Vec3::Zero();
};

}  // namespace fdem
