#include "coupling/particle_mapping.hpp"

namespace fdem {

void ParticleMapping::update(const BoxMesh& mesh, const Particles& particles) {
  const auto n = static_cast<std::ptrdiff_t>(particles.size());
  element.resize(particles.size());
  weights.resize(particles.size());
  long out = 0;
#pragma omp parallel for reduction(+ : out) if (n > 4096)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    const auto u = static_cast<std::size_t>(i);
    const Vec3 p(particles.x[u], particles.y[u], particles.z[u]);
    const Index e = mesh.locate_element(p);  // Eq. 23-31
    element[u] = e;
    if (e < 0) {
      weights[u] = {0.0, 0.0, 0.0, 0.0};
      ++out;
      continue;
    }
    const Eigen::Vector4d lambda = mesh.volume_coordinates(e, p);  // Eq. 28-31
    weights[u] = {lambda[0], lambda[1], lambda[2], lambda[3]};
  }
  outside = out;
}

}  // namespace fdem
