#include "coupling/source_term.hpp"

#include <algorithm>

namespace fdem {

SourceForm fluid_source_form(const Scene& scene) {
  return scene.fluid.model == FluidModel::simplified ? scene.coupling.source_form : SourceForm::conservative;
}

SourceTerm::SourceTerm(const BoxMesh& mesh, SourceForm form)
    : mesh_(&mesh),
      form_(form),
      element_force_(3 * static_cast<std::size_t>(mesh.num_elements()), 0.0),
      element_solid_(static_cast<std::size_t>(mesh.num_elements()), 0.0),
      nodal_(3 * static_cast<std::size_t>(mesh.num_nodes()), 0.0),
      nodal_volume_(static_cast<std::size_t>(mesh.num_nodes()), 0.0) {
  for (Index e = 0; e < mesh.num_elements(); ++e)
    for (Index n : mesh.element_nodes(e)) nodal_volume_[static_cast<std::size_t>(n)] += 0.25 * mesh.element_volume(e);
}

void SourceTerm::clear() {
  std::fill(nodal_.begin(), nodal_.end(), 0.0);
  total_.setZero();
}

void SourceTerm::compute(const Particles& particles, const ParticleMapping& mapping, std::span<const double> porosity,
                         std::span<const double> drag_x, std::span<const double> drag_y,
                         std::span<const double> drag_z, const GrainShare& share) {
  std::fill(element_force_.begin(), element_force_.end(), 0.0);
  std::fill(element_solid_.begin(), element_solid_.end(), 0.0);
  std::fill(nodal_.begin(), nodal_.end(), 0.0);
  // Sum of drag and of particle volume per element (Fig. 4, particle loop).
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const Index e = mapping.element[i];
    if (e < 0 || !share.counts(i)) continue;
    const auto k = static_cast<std::size_t>(e);
    element_force_[3 * k + 0] += drag_x[i];
    element_force_[3 * k + 1] += drag_y[i];
    element_force_[3 * k + 2] += drag_z[i];
    element_solid_[k] += sphere_volume(particles.diameter[i]);
  }
  share.sum_over_elements(mapping.element, {{element_force_, 3}, {element_solid_, 1}});
  // Element force on the fluid, then equal shares to the 4 nodes (Fig. 5d).
  total_.setZero();
  const auto ne = static_cast<std::size_t>(mesh_->num_elements());
  const SourceFormEntry& form = source_form_entry(form_);
  for (std::size_t k = 0; k < ne; ++k) {
    if (element_solid_[k] == 0.0) continue;
    const auto e = static_cast<Index>(k);
    const double scale = form.drag_to_fluid_force(mesh_->element_volume(e), porosity[k], element_solid_[k]);
    const Vec3 force(scale * element_force_[3 * k], scale * element_force_[3 * k + 1],
                     scale * element_force_[3 * k + 2]);
    if (share.owns_element(k)) total_ += force;  // each element once over the ranks
    for (Index n : mesh_->element_nodes(e)) {
      const auto a = static_cast<std::size_t>(n);
      for (std::size_t d = 0; d < 3; ++d) nodal_[3 * a + d] += 0.25 * force[static_cast<Eigen::Index>(d)];
    }
  }
  share.sum_over_element_owners(std::span<double>(total_.data(), 3));
  const std::size_t nn = nodal_volume_.size();
  for (std::size_t a = 0; a < nn; ++a)
    for (std::size_t d = 0; d < 3; ++d) nodal_[3 * a + d] /= nodal_volume_[a];
}

}  // namespace fdem
