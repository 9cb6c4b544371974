#include "coupling/momentum_exchange.hpp"

#include <algorithm>

namespace fdem {

SemiImplicitExchange::SemiImplicitExchange(const BoxMesh& mesh, SourceForm form)
    : mesh_(&mesh),
      form_(form),
      beta_(static_cast<std::size_t>(mesh.num_elements()), 0.0),
      velocity_(3 * static_cast<std::size_t>(mesh.num_elements()), 0.0) {}

void SemiImplicitExchange::compute(const Particles& particles, const ParticleMapping& mapping,
                                   std::span<const double> coefficients, std::span<const double> porosity,
                                   const GrainShare& share) {
  clear();
  // Sums per element: sum c_i in beta_, sum c_i v_i in velocity_.
  for (std::size_t i = 0; i < mapping.element.size(); ++i) {
    const Index e = mapping.element[i];
    if (e < 0 || !share.counts(i)) continue;  // outside the mesh: no fluid, no drag
    const auto k = static_cast<std::size_t>(e);
    const double c = coefficients[i];
    beta_[k] += c;
    velocity_[3 * k] += c * particles.vx[i];
    velocity_[3 * k + 1] += c * particles.vy[i];
    velocity_[3 * k + 2] += c * particles.vz[i];
  }
  share.sum_over_elements(mapping.element, {{beta_, 1}, {velocity_, 3}});
  const SourceFormEntry& form = source_form_entry(form_);
  for (std::size_t k = 0; k < beta_.size(); ++k) {
    const double sum = beta_[k];
    if (sum == 0.0) continue;
    for (std::size_t c = 0; c < 3; ++c) velocity_[3 * k + c] /= sum;
    beta_[k] = form.exchange_coefficient(sum / mesh_->element_volume(static_cast<Index>(k)), porosity[k]);
  }
}

void SemiImplicitExchange::clear() {
  std::fill(beta_.begin(), beta_.end(), 0.0);
  std::fill(velocity_.begin(), velocity_.end(), 0.0);
}

Vec3 SemiImplicitExchange::force_on_fluid(std::span<const double> nodal_velocity, const GrainShare& share) const {
  Vec3 total = Vec3::Zero();
  for (std::size_t k = 0; k < beta_.size(); ++k) {
    if (beta_[k] == 0.0 || !share.owns_element(k)) continue;  // each element once over the ranks
    const auto& nodes = mesh_->element_nodes(static_cast<Index>(k));
    Vec3 mean = Vec3::Zero();
    for (const Index a : nodes)
      for (std::size_t c = 0; c < 3; ++c) mean[static_cast<Index>(c)] += 0.25 * nodal_velocity[3 * static_cast<std::size_t>(a) + c];
    const Vec3 v(velocity_[3 * k], velocity_[3 * k + 1], velocity_[3 * k + 2]);
    total += mesh_->element_volume(static_cast<Index>(k)) * beta_[k] * (v - mean);
  }
  share.sum_over_element_owners(std::span<double>(total.data(), 3));
  return total;
}

}  // namespace fdem
