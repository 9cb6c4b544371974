#include "coupling/porosity.hpp"

#include <algorithm>

namespace fdem {

PorosityField::PorosityField(const BoxMesh& mesh, PorosityScheme scheme, double floor)
    : mesh_(&mesh), scheme_(scheme), floor_(floor), porosity_(static_cast<std::size_t>(mesh.num_elements()), 1.0) {
  if (scheme_ == PorosityScheme::centre) {
    solid_.assign(static_cast<std::size_t>(mesh.num_elements()), 0.0);
  } else {
    solid_.assign(static_cast<std::size_t>(mesh.num_nodes()), 0.0);
    nodal_volume_.assign(static_cast<std::size_t>(mesh.num_nodes()), 0.0);
    for (Index e = 0; e < mesh.num_elements(); ++e)
      for (Index n : mesh.element_nodes(e)) nodal_volume_[static_cast<std::size_t>(n)] += 0.25 * mesh.element_volume(e);
  }
}

PorosityUpdate PorosityField::update(const Particles& particles, const ParticleMapping& mapping) {
  std::fill(solid_.begin(), solid_.end(), 0.0);
  const std::size_t np = particles.size();
  const auto ne = static_cast<std::size_t>(mesh_->num_elements());
  if (scheme_ == PorosityScheme::centre) {
    for (std::size_t i = 0; i < np; ++i) {
      const Index e = mapping.element[i];
      if (e >= 0) solid_[static_cast<std::size_t>(e)] += sphere_volume(particles.diameter[i]);
    }
    for (std::size_t e = 0; e < ne; ++e) {
      const double volume = mesh_->element_volume(static_cast<Index>(e));
      porosity_[e] = (volume - solid_[e]) / volume;  // Eq. 32
    }
  } else {
    for (std::size_t i = 0; i < np; ++i) {
      const Index e = mapping.element[i];
      if (e < 0) continue;
      const double v = sphere_volume(particles.diameter[i]);
      const auto& nodes = mesh_->element_nodes(e);
      for (std::size_t a = 0; a < 4; ++a) solid_[static_cast<std::size_t>(nodes[a])] += mapping.weights[i][a] * v;
    }
    for (std::size_t e = 0; e < ne; ++e) {
      double fraction = 0.0;
      for (Index n : mesh_->element_nodes(static_cast<Index>(e)))
        fraction += solid_[static_cast<std::size_t>(n)] / nodal_volume_[static_cast<std::size_t>(n)];
      porosity_[e] = 1.0 - 0.25 * fraction;
    }
  }
  PorosityUpdate out;
  for (double& eps : porosity_) {
    out.min_porosity = std::min(out.min_porosity, eps);
    if (eps < floor_) {
      eps = floor_;
      ++out.floored_elements;
    }
  }
  return out;
}

}  // namespace fdem
