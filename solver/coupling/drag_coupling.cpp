#include "coupling/drag_coupling.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <fmt/format.h>

#include "core/error.hpp"
#include "drag_laws/drag_kernel.hpp"

namespace fdem {

namespace {

constexpr std::size_t kBlock = DragCoupling::block_size;
using Clock = std::chrono::steady_clock;

}  // namespace

GrainDragForm grain_drag_form(FluidModel model) {
  return model == FluidModel::vans_b ? GrainDragForm::drag_over_porosity : GrainDragForm::drag;
}

DragCoupling::DragCoupling(const DragLawEntry& law, FluidProperties fluid, bool apply_to_particles,
                           bool frozen_coefficients, GrainDragForm form)
    : law_(&law), fluid_(fluid), apply_(apply_to_particles), frozen_mode_(frozen_coefficients), form_(form) {}

void DragCoupling::fill_block(std::size_t b, const BoxMesh& mesh, const ParticleMapping& mapping,
                              const Particles& particles, std::span<const double> fluid_velocity,
                              std::span<const double> porosity, DragBlock& blk, DragLanes& scale) const {
  const std::size_t n = mapping.element.size();
  const std::size_t base = b * kBlock;
  const std::size_t m = std::min(kBlock, n - base);
  alignas(64) DragLanes eps{}, d{};
  scale.fill(0.0);  // padding and grains outside the mesh: no drag
  for (std::size_t l = 0; l < kBlock; ++l) blk.ux[l] = blk.uy[l] = blk.uz[l] = 0.0;
  for (std::size_t l = 0; l < m; ++l) {
    const std::size_t i = base + l;
    const Index e = mapping.element[i];
    d[l] = particles.diameter[i];
    if (e < 0) continue;  // outside the mesh: no fluid, no drag (eps = 0 marks it)
    const auto& nodes = mesh.element_nodes(e);
    // P1 shape functions = volume coordinates (Eq. 28-31); the semi-implicit
    // exchange uses the element's mean (weights 1/4), the velocity its
    // beta_e multiplies in the fluid (header comment).
    const auto& w = mapping.weights[i];
    double u[3] = {0.0, 0.0, 0.0};
    for (std::size_t k = 0; k < 4; ++k) {
      const auto node = 3 * static_cast<std::size_t>(nodes[k]);
      const double weight = frozen_mode_ ? 0.25 : w[k];
      for (std::size_t c = 0; c < 3; ++c) u[c] += weight * fluid_velocity[node + c];
    }
    blk.ux[l] = u[0];
    blk.uy[l] = u[1];
    blk.uz[l] = u[2];
    eps[l] = porosity[static_cast<std::size_t>(e)];
    scale[l] = form_ == GrainDragForm::drag_over_porosity ? 1.0 / eps[l] : 1.0;  // Zhou et al. model B: f_d / eps
  }
  law_->fold(eps, d, fluid_, blk.folded);
  for (std::size_t l = 0; l < kBlock; ++l) blk.sum_x[l] = blk.sum_y[l] = blk.sum_z[l] = 0.0;
  for (auto& lanes : blk.memory) lanes.fill(0.0f);
}

// Once per fluid step (and again if the DEM removes particles mid-step): the
// fluid velocity at each particle, then the law's coefficients from its
// element's porosity and its diameter.
void DragCoupling::prepare(const BoxMesh& mesh, const ParticleMapping& mapping, const Particles& particles) {
  const std::size_t n = mapping.element.size();
  particles_ = n;
  blocks_.resize((n + kBlock - 1) / kBlock);
  scale_.resize(blocks_.size());
  const auto nb = static_cast<std::ptrdiff_t>(blocks_.size());
#pragma omp parallel for schedule(static) if (nb > 512)
  for (std::ptrdiff_t b = 0; b < nb; ++b)
    fill_block(static_cast<std::size_t>(b), mesh, mapping, particles, nodal_velocity_, porosity_,
               blocks_[static_cast<std::size_t>(b)], scale_[static_cast<std::size_t>(b)]);
  mean_x_.assign(n, 0.0);
  mean_y_.assign(n, 0.0);
  mean_z_.assign(n, 0.0);
  evaluations_ = 0;
}

void DragCoupling::begin_step(const BoxMesh& mesh, const ParticleMapping& mapping, const Particles& particles,
                              std::span<const double> fluid_velocity, std::span<const double> porosity) {
  mesh_ = &mesh;
  nodal_velocity_ = fluid_velocity;
  porosity_ = porosity;
  prepare(mesh, mapping, particles);
  if (frozen_mode_ && frozen_.size() != particles_)  // none frozen for these particles yet: freeze them now
    freeze_coefficients(mesh, mapping, particles, fluid_velocity, porosity);
  remapped_ = false;
  evaluation_seconds_ = 0.0;
}

void DragCoupling::freeze_coefficients(const BoxMesh& mesh, const ParticleMapping& mapping,
                                       const Particles& particles, std::span<const double> fluid_velocity,
                                       std::span<const double> porosity) {
  const std::size_t n = mapping.element.size();
  frozen_blocks_.resize((n + kBlock - 1) / kBlock);
  frozen_.assign(n, 0.0);
  const auto nb = static_cast<std::ptrdiff_t>(frozen_blocks_.size());
#pragma omp parallel for schedule(static) if (nb > 512)
  for (std::ptrdiff_t bb = 0; bb < nb; ++bb) {
    const auto b = static_cast<std::size_t>(bb);
    DragBlock blk;
    alignas(64) DragLanes scale;
    fill_block(b, mesh, mapping, particles, fluid_velocity, porosity, blk, scale);
    const std::size_t base = b * kBlock, m = std::min(kBlock, n - base);
    alignas(64) DragLanes s2{};
    for (std::size_t l = 0; l < m; ++l) {
      const double sx = blk.ux[l] - particles.vx[base + l], sy = blk.uy[l] - particles.vy[base + l],
                   sz = blk.uz[l] - particles.vz[base + l];
      s2[l] = sx * sx + sy * sy + sz * sz;
    }
    law_->coefficient(blk.folded, s2, frozen_blocks_[b]);
    for (std::size_t l = 0; l < kBlock; ++l) frozen_blocks_[b][l] *= scale[l];
    for (std::size_t l = 0; l < m; ++l) frozen_[base + l] = frozen_blocks_[b][l];
  }
}

void DragCoupling::add(const Particles& p, std::span<double> fx, std::span<double> fy, std::span<double> fz) {
  const auto t0 = Clock::now();
  if (p.size() != particles_) remap(p);
  DragSubcycle step{blocks_, particles_, p.vx, p.vy, p.vz, {}, {}, {}};
  if (apply_) {
    step.fx = fx;
    step.fy = fy;
    step.fz = fz;
  }
  if (frozen_mode_) {
    const DragLanes* frozen = frozen_blocks_.data();
    drag_subcycle_blocks(step, [frozen](std::size_t b, const DragLanes&, DragLanes& c) { c = frozen[b]; });
  } else if (form_ == GrainDragForm::drag_over_porosity) {
    // The law through its pointer (not its compiled kernel), then 1 / eps_e.
    const DragBlock* blocks = blocks_.data();
    const DragLanes* scale = scale_.data();
    const auto coefficient = law_->coefficient;
    drag_subcycle_blocks(step, [blocks, scale, coefficient](std::size_t b, const DragLanes& s2, DragLanes& c) {
      coefficient(blocks[b].folded, s2, c);
      for (std::size_t l = 0; l < kBlock; ++l) c[l] *= scale[b][l];
    });
  } else {
    law_->subcycle(step);
  }
  ++evaluations_;
  evaluation_seconds_ += std::chrono::duration<double>(Clock::now() - t0).count();
}

// The DEM removed particles mid-step: indices shifted. Map the survivors
// again (the porosity stays that of the step start) and restart the sums;
// frozen coefficients are taken afresh from the law for the survivors.
void DragCoupling::remap(const Particles& p) {
  own_mapping_.update(*mesh_, p);
  prepare(*mesh_, own_mapping_, p);
  if (frozen_mode_) freeze_coefficients(*mesh_, own_mapping_, p, nodal_velocity_, porosity_);
  remapped_ = true;
}

namespace {
// A grain's carried values, in this order: ux uy uz, k[0..3], sum_x sum_y sum_z, the form's factor, the law's
// memory[0..1], then c_i.
constexpr std::size_t kCarriedBlockValues = 13;
}  // namespace

std::vector<std::vector<double>> DragCoupling::carried_state(const Particles& p) const {
  if (mesh_ == nullptr || p.size() != particles_) return {};  // no step begun for these grains: nothing to carry
  const std::size_t n = particles_;
  std::vector<std::vector<double>> out(kCarriedBlockValues + (frozen_mode_ ? 1 : 0), std::vector<double>(n));
  for (std::size_t i = 0; i < n; ++i) {
    const DragBlock& blk = blocks_[i / kBlock];
    const std::size_t l = i % kBlock;
    const double values[kCarriedBlockValues] = {blk.ux[l],        blk.uy[l],        blk.uz[l],        blk.folded.k[0][l],
                                                blk.folded.k[1][l], blk.folded.k[2][l], blk.folded.k[3][l], blk.sum_x[l],
                                                blk.sum_y[l],     blk.sum_z[l],     scale_[i / kBlock][l],
                                                blk.memory[0][l], blk.memory[1][l]};  // floats: exact as doubles
    for (std::size_t c = 0; c < kCarriedBlockValues; ++c) out[c][i] = values[c];
    if (frozen_mode_) out[kCarriedBlockValues][i] = frozen_blocks_[i / kBlock][l];
  }
  return out;
}

void DragCoupling::grains_redistributed(const Particles& p, std::vector<std::vector<double>>&& carried,
                                        bool lost_anywhere) {
  if (mesh_ == nullptr) return;  // before the first step: begin_step prepares
  if (lost_anywhere) {  // one process sees a new count and maps the survivors again
    remap(p);
    return;
  }
  if (carried.size() != kCarriedBlockValues + (frozen_mode_ ? 1 : 0)) return;  // nothing carried: stale until begin_step
  const std::size_t n = p.size();
  particles_ = n;
  const std::size_t nb = (n + kBlock - 1) / kBlock;
  // The padding lanes as fill_block leaves them (no fluid: eps = 0, d = 0), and freeze_coefficients' c there.
  DragBlock padding{};
  alignas(64) DragLanes zero{}, padding_frozen{};
  law_->fold(zero, zero, fluid_, padding.folded);
  if (frozen_mode_) {
    law_->coefficient(padding.folded, zero, padding_frozen);
    for (std::size_t l = 0; l < kBlock; ++l) padding_frozen[l] *= zero[l];
  }
  blocks_.assign(nb, padding);
  scale_.assign(nb, zero);
  if (frozen_mode_) {
    frozen_blocks_.assign(nb, padding_frozen);
    frozen_.assign(n, 0.0);
  }
  for (std::size_t i = 0; i < n; ++i) {
    DragBlock& blk = blocks_[i / kBlock];
    const std::size_t l = i % kBlock;
    blk.ux[l] = carried[0][i];
    blk.uy[l] = carried[1][i];
    blk.uz[l] = carried[2][i];
    for (std::size_t k = 0; k < 4; ++k) blk.folded.k[k][l] = carried[3 + k][i];
    blk.sum_x[l] = carried[7][i];
    blk.sum_y[l] = carried[8][i];
    blk.sum_z[l] = carried[9][i];
    scale_[i / kBlock][l] = carried[10][i];
    blk.memory[0][l] = static_cast<float>(carried[11][i]);
    blk.memory[1][l] = static_cast<float>(carried[12][i]);
    if (frozen_mode_) {
      frozen_blocks_[i / kBlock][l] = carried[kCarriedBlockValues][i];
      frozen_[i] = carried[kCarriedBlockValues][i];
    }
  }
  mean_x_.assign(n, 0.0);
  mean_y_.assign(n, 0.0);
  mean_z_.assign(n, 0.0);
}

void DragCoupling::end_step() {
  if (evaluations_ == 0) return;
  const double inv = 1.0 / static_cast<double>(evaluations_);
  for (std::size_t i = 0; i < particles_; ++i) {
    const DragBlock& blk = blocks_[i / kBlock];
    const std::size_t l = i % kBlock;
    mean_x_[i] = blk.sum_x[l] * inv;
    mean_y_[i] = blk.sum_y[l] * inv;
    mean_z_[i] = blk.sum_z[l] * inv;
  }
}

void DragCoupling::reorder(std::span<const Index> new_to_old) {
  if (new_to_old.size() != mean_x_.size())
    throw SolverError(fmt::format("drag coupling: a reorder of {} grains for {} mean drags", new_to_old.size(),
                                  mean_x_.size()));
  std::vector<double> moved(new_to_old.size());
  for (std::vector<double>* v : {&mean_x_, &mean_y_, &mean_z_}) {
    for (std::size_t k = 0; k < moved.size(); ++k) moved[k] = (*v)[static_cast<std::size_t>(new_to_old[k])];
    v->swap(moved);
  }
}

Vec3 DragCoupling::total_mean_drag(const GrainShare& share) const {
  Vec3 total = Vec3::Zero();
  for (std::size_t i = 0; i < mean_x_.size(); ++i)
    if (share.counts(i)) total += Vec3(mean_x_[i], mean_y_[i], mean_z_[i]);
  share.sum_over_ranks(std::span<double>(total.data(), 3));
  return total;
}

}  // namespace fdem
