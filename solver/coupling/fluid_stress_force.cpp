#include "coupling/fluid_stress_force.hpp"

#include "core/types.hpp"

namespace fdem {

std::vector<Vec3> projected_element_gradient(const BoxMesh& mesh, std::span<const Vec3> element_gradient) {
  const auto ne = static_cast<std::size_t>(mesh.num_elements()), nn = static_cast<std::size_t>(mesh.num_nodes());
  std::vector<double> weight(nn, 0.0);
  std::vector<Vec3> nodal(nn, Vec3::Zero());
  for (std::size_t k = 0; k < ne; ++k) {
    const double v = mesh.element_volume(static_cast<Index>(k));
    for (const Index a : mesh.element_nodes(static_cast<Index>(k))) {
      weight[static_cast<std::size_t>(a)] += v;
      nodal[static_cast<std::size_t>(a)] += v * element_gradient[k];
    }
  }
  for (std::size_t a = 0; a < nn; ++a) nodal[a] /= weight[a];
  std::vector<Vec3> out(ne, Vec3::Zero());
  for (std::size_t k = 0; k < ne; ++k)
    for (const Index a : mesh.element_nodes(static_cast<Index>(k))) out[k] += 0.25 * nodal[static_cast<std::size_t>(a)];
  return out;
}

void grain_pressure_gradients(const BoxMesh& mesh, std::span<const Vec3> element_gradient, PorosityField& porosity,
                              const ParticleMapping& mapping, const Particles& particles, std::span<Vec3> out) {
  const std::vector<Vec3> projected = projected_element_gradient(mesh, element_gradient);
  porosity.grain_means(particles, mapping, projected, out);
}

void FluidStressForce::begin_step(const ParticleMapping& mapping, const Particles& particles,
                                  const FluidSolver& fluid, PorosityField& porosity) {
  const BoxMesh& mesh = fluid.mesh();
  element_gradient_.resize(static_cast<std::size_t>(mesh.num_elements()));
  for (std::size_t k = 0; k < element_gradient_.size(); ++k)
    element_gradient_[k] = fluid.pressure_gradient(static_cast<Index>(k));
  const std::size_t n = particles.size();
  grain_gradient_.resize(n);
  grain_pressure_gradients(mesh, element_gradient_, porosity, mapping, particles, grain_gradient_);
  fx_.assign(n, 0.0);
  fy_.assign(n, 0.0);
  fz_.assign(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    const double volume = sphere_volume(particles.diameter[i]);
    fx_[i] = -volume * grain_gradient_[i].x();
    fy_[i] = -volume * grain_gradient_[i].y();
    fz_[i] = -volume * grain_gradient_[i].z();
  }
}

std::vector<std::vector<double>> FluidStressForce::carried_state(const Particles& p) const {
  std::vector<std::vector<double>> out;
  if (inner_) {
    out = inner_->carried_state(p);
    if (out.empty()) return {};
  }
  if (fx_.size() != p.size()) return {};
  for (const std::vector<double>* v : {&fx_, &fy_, &fz_}) out.push_back(*v);
  return out;
}

void FluidStressForce::grains_redistributed(const Particles& p, std::vector<std::vector<double>>&& carried,
                                            bool lost_anywhere) {
  if (lost_anywhere || carried.size() < 3) {
    fx_.clear();  // stale: skipped by add() until the next begin_step
    fy_.clear();
    fz_.clear();
    if (inner_) inner_->grains_redistributed(p, lost_anywhere ? std::move(carried) : std::vector<std::vector<double>>{},
                                             lost_anywhere);
    return;
  }
  fz_ = std::move(carried.back());
  carried.pop_back();
  fy_ = std::move(carried.back());
  carried.pop_back();
  fx_ = std::move(carried.back());
  carried.pop_back();
  if (inner_) inner_->grains_redistributed(p, std::move(carried), false);
}

void FluidStressForce::add(const Particles& p, std::span<double> fx, std::span<double> fy, std::span<double> fz) {
  if (inner_) inner_->add(p, fx, fy, fz);
  if (p.size() != fx_.size()) return;
  // One array a loop: fx, fy and fz may alias for all the compiler knows,
  // which left the three-array loop scalar (drag_laws/drag_kernel.hpp).
  const std::size_t n = fx_.size();
#pragma omp simd
  for (std::size_t i = 0; i < n; ++i) fx[i] += fx_[i];
#pragma omp simd
  for (std::size_t i = 0; i < n; ++i) fy[i] += fy_[i];
#pragma omp simd
  for (std::size_t i = 0; i < n; ++i) fz[i] += fz_[i];
}

}  // namespace fdem
