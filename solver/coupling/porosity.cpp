// GCC 12 reports a false -Wmaybe-uninitialized inside its own AVX-512
// intrinsics (_mm512_extractf64x4_pd's __Y = __Y idiom) when Eigen's dynamic
// reductions (the CG's dot products) are inlined with -march=native; as in
// fluid/fluid_solver.cpp. It must precede the first Eigen include.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#include "coupling/porosity.hpp"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "coupling/sphere_tetrahedron_volume.hpp"

namespace fdem {

// The diffused scheme's operator A = M + L^2 K (lumped M) and its solver,
// built once: the mesh never changes during a run.
struct PorosityDiffusion {
  Eigen::SparseMatrix<double> matrix;
  Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper,
                           Eigen::DiagonalPreconditioner<double>>
      cg;
  Eigen::VectorXd rhs;       // M phi0 = nodal solid volume [m^3]
  Eigen::VectorXd smoothed;  // phi, the smoothed nodal solid fraction; the next solve's first guess
};

namespace {

// Relative residual of the CG solve: 31-34 iterations on 1.3k to 69k nodes at
// L = one cell (1e-12: 37-40). The operator's condition number does not grow
// with the mesh at a fixed L / h, so neither does the count. The field is then
// right to ~1e-10 relative, far below any amplitude measured (1e-4); the
// volume the residual would lose is put back by the conservation rescale.
// Every solve starts from zero, not from the previous field: a warm start
// saves about a third of the iterations but makes the field depend on the
// history, so a run resumed from a checkpoint would no longer repeat the
// straight run bit for bit.
constexpr double kCgTolerance = 1e-10;

std::unique_ptr<PorosityDiffusion> build_diffusion(const BoxMesh& mesh, const std::vector<double>& nodal_volume,
                                                   double length) {
  auto d = std::make_unique<PorosityDiffusion>();
  const Index nn = mesh.num_nodes();
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(static_cast<std::size_t>(mesh.num_elements()) * 16 + static_cast<std::size_t>(nn));
  for (Index n = 0; n < nn; ++n) entries.emplace_back(n, n, nodal_volume[static_cast<std::size_t>(n)]);
  const double l2 = length * length;
  for (Index e = 0; e < mesh.num_elements(); ++e) {
    // P1 stiffness K_e = V_e G G^T (G: rows grad N_a, constant on the tetrahedron).
    const BoxMesh::ShapeGradients& g = mesh.shape_gradients(e);
    const Eigen::Matrix4d ke = mesh.element_volume(e) * g * g.transpose();
    const auto& nodes = mesh.element_nodes(e);
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b)
        entries.emplace_back(nodes[static_cast<std::size_t>(a)], nodes[static_cast<std::size_t>(b)], l2 * ke(a, b));
  }
  d->matrix.resize(nn, nn);
  d->matrix.setFromTriplets(entries.begin(), entries.end());
  d->matrix.makeCompressed();
  d->cg.setTolerance(kCgTolerance);
  d->cg.compute(d->matrix);
  d->rhs = Eigen::VectorXd::Zero(nn);
  d->smoothed = Eigen::VectorXd::Zero(nn);
  return d;
}

}  // namespace

PorosityField::PorosityField(const BoxMesh& mesh, PorosityScheme scheme, double floor,
                             std::optional<double> smoothing_length)
    : mesh_(&mesh),
      scheme_(scheme),
      entry_(&porosity_scheme_entry(scheme)),
      floor_(floor),
      porosity_(static_cast<std::size_t>(mesh.num_elements()), 1.0) {
  if (entry_->deposit != SolidDeposit::nodes_by_weights) {
    solid_.assign(static_cast<std::size_t>(mesh.num_elements()), 0.0);
    return;
  }
  solid_.assign(static_cast<std::size_t>(mesh.num_nodes()), 0.0);
  nodal_volume_.assign(static_cast<std::size_t>(mesh.num_nodes()), 0.0);
  for (Index e = 0; e < mesh.num_elements(); ++e)
    for (Index n : mesh.element_nodes(e)) nodal_volume_[static_cast<std::size_t>(n)] += 0.25 * mesh.element_volume(e);
  if (entry_->smoothed) {
    smoothing_length_ = smoothing_length.value_or(kDefaultSmoothingCells * mesh.cell_size().maxCoeff());
    if (!(smoothing_length_ > 0.0) || !std::isfinite(smoothing_length_))
      throw std::invalid_argument("PorosityField: the smoothing length must be finite and > 0");
    diffusion_ = build_diffusion(mesh, nodal_volume_, smoothing_length_);
  }
}

PorosityField::PorosityField(const BoxMesh& mesh, const CouplingSpec& coupling)
    : PorosityField(mesh, coupling.porosity, coupling.porosity_floor, coupling.porosity_smoothing_length) {}

PorosityField::PorosityField(const BoxMesh& mesh, const CouplingSpec& coupling, const Particles& particles)
    : PorosityField(mesh, coupling.porosity, coupling.porosity_floor,
                    porosity_scheme_entry(coupling.porosity).smoothed
                        ? std::optional<double>(resolve_smoothing_length(coupling, mesh, particles).length)
                        : std::nullopt) {}

SmoothingLength resolve_smoothing_length(const CouplingSpec& coupling, const BoxMesh& mesh,
                                         const Particles& particles) {
  SmoothingLength out;
  const double cell = mesh.cell_size().maxCoeff();
  if (particles.size() == 0) {
    out.length = out.requested = out.cap = coupling.porosity_smoothing_length.value_or(cell);
    return out;
  }
  const double d_max = *std::max_element(particles.diameter.begin(), particles.diameter.end());
  out.requested = coupling.porosity_smoothing_length.value_or(
      coupling.porosity_smoothing_diameters.value_or(kDefaultSmoothingDiameters) * d_max);
  // The grains' bounding box (surfaces, not centres).
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::max()), hi = -lo;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const Vec3 p(particles.x[i], particles.y[i], particles.z[i]);
    const double r = 0.5 * particles.diameter[i];
    lo = lo.cwiseMin(p - Vec3::Constant(r));
    hi = hi.cwiseMax(p + Vec3::Constant(r));
  }
  double thinnest = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a) {
    const bool wall_to_wall = lo[a] <= mesh.lower()[a] + d_max && hi[a] >= mesh.upper()[a] - d_max;
    if (!wall_to_wall) thinnest = std::min(thinnest, hi[a] - lo[a]);
  }
  out.cap = std::max(cell, kSmoothingPerBedThickness * thinnest);
  out.length = std::min(out.requested, out.cap);
  return out;
}

PorosityField::~PorosityField() = default;
PorosityField::PorosityField(PorosityField&&) noexcept = default;
PorosityField& PorosityField::operator=(PorosityField&&) noexcept = default;

PorosityUpdate PorosityField::update(const Particles& particles, const ParticleMapping& mapping,
                                     const GrainShare& share) {
  std::fill(solid_.begin(), solid_.end(), 0.0);
  const std::size_t np = particles.size();
  const auto ne = static_cast<std::size_t>(mesh_->num_elements());
  PorosityUpdate out;
  if (entry_->deposit == SolidDeposit::element_of_centre) {
    for (std::size_t i = 0; i < np; ++i) {
      const Index e = mapping.element[i];
      if (e >= 0 && share.counts(i)) solid_[static_cast<std::size_t>(e)] += sphere_volume(particles.diameter[i]);
    }
    share.sum_over_elements(mapping.element, {{solid_, 1}});
    for (std::size_t e = 0; e < ne; ++e) {
      const double volume = mesh_->element_volume(static_cast<Index>(e));
      porosity_[e] = (volume - solid_[e]) / volume;  // Eq. 32
    }
  } else if (entry_->deposit == SolidDeposit::element_overlap) {
    add_intersection_volumes(particles, share);
    share.sum_over_elements(overlap_elements_, {{solid_, 1}});
    for (std::size_t e = 0; e < ne; ++e) {
      const double volume = mesh_->element_volume(static_cast<Index>(e));
      porosity_[e] = (volume - solid_[e]) / volume;
    }
  } else {
    // Each particle's volume to the nodes of its element with its P1 weights.
    double total_solid = 0.0;
    touched_nodes_.clear();
    for (std::size_t i = 0; i < np; ++i) {
      const Index e = mapping.element[i];
      if (e < 0 || !share.counts(i)) continue;
      const double v = sphere_volume(particles.diameter[i]);
      total_solid += v;
      const auto& nodes = mesh_->element_nodes(e);
      for (std::size_t a = 0; a < 4; ++a) solid_[static_cast<std::size_t>(nodes[a])] += mapping.weights[i][a] * v;
      touched_nodes_.insert(touched_nodes_.end(), nodes.begin(), nodes.end());
    }
    // Decomposed: complete on the corners of the elements this rank needs,
    // or (smoothed: the solve spans the mesh) on every node of every rank.
    share.sum_over_nodes(touched_nodes_, entry_->smoothed, {{solid_, 1}});
    total_solid = share.sum_over_ranks(total_solid);
    // Nodal solid fraction, in place: phi0 = solid / M (shape_function) or
    // the smoothed phi (diffused).
    if (entry_->smoothed) {
      PorosityDiffusion& d = *diffusion_;
      // (M + L^2 K) phi = M phi0, and M phi0 is the nodal solid volume.
      d.rhs = Eigen::Map<const Eigen::VectorXd>(solid_.data(), static_cast<Eigen::Index>(solid_.size()));
      if (total_solid > 0.0) {
        d.smoothed = d.cg.solve(d.rhs);
        if (d.cg.info() != Eigen::Success)
          throw std::runtime_error("PorosityField: the diffusion solve did not converge");
        out.smoothing_iterations = static_cast<int>(d.cg.iterations());
        // 1^T M phi must equal the mapped solid (K 1 = 0): remove the CG residual's share.
        const double smoothed_solid =
            Eigen::Map<const Eigen::VectorXd>(nodal_volume_.data(), d.smoothed.size()).dot(d.smoothed);
        out.conservation_correction = total_solid / smoothed_solid;
        d.smoothed *= out.conservation_correction;
      } else {
        d.smoothed.setZero();
      }
      std::copy(d.smoothed.begin(), d.smoothed.end(), solid_.begin());
    } else {
      for (std::size_t n = 0; n < solid_.size(); ++n) solid_[n] /= nodal_volume_[n];
    }
    for (std::size_t e = 0; e < ne; ++e) {
      double fraction = 0.0;
      for (Index n : mesh_->element_nodes(static_cast<Index>(e))) fraction += solid_[static_cast<std::size_t>(n)];
      porosity_[e] = 1.0 - 0.25 * fraction;  // element average of the P1 nodal field
    }
  }
  // Floored everywhere; counted by each element's owner alone (on several
  // ranks the caller adds the counts and takes the least over the ranks).
  for (std::size_t e = 0; e < ne; ++e) {
    double& eps = porosity_[e];
    const bool counted = share.owns_element(e);
    if (counted) out.min_porosity = std::min(out.min_porosity, eps);
    if (eps < floor_) {
      eps = floor_;
      if (counted) ++out.floored_elements;
    }
  }
  return out;
}

// Every grain's exact volume in every tetrahedron of the cells its bounding box touches.
template <class Visit>
void PorosityField::for_each_overlap(const Particles& particles, std::size_t i, Visit&& visit) const {
  const Vec3& lower = mesh_->lower();
  const Vec3& h = mesh_->cell_size();
  const std::array<int, 3>& n = mesh_->cells();
  const Vec3 c(particles.x[i], particles.y[i], particles.z[i]);
  const double r = 0.5 * particles.diameter[i];
  std::array<int, 3> first{}, last{};
  for (int a = 0; a < 3; ++a) {
    const double lo = std::floor((c[a] - r - lower[a]) / h[a]), hi = std::floor((c[a] + r - lower[a]) / h[a]);
    if (hi < 0.0 || lo > n[a] - 1) return;  // wholly outside the box along this axis
    first[a] = static_cast<int>(std::clamp(lo, 0.0, static_cast<double>(n[a] - 1)));
    last[a] = static_cast<int>(std::clamp(hi, 0.0, static_cast<double>(n[a] - 1)));
  }
  for (int k = first[2]; k <= last[2]; ++k)
    for (int j = first[1]; j <= last[1]; ++j)
      for (int ci = first[0]; ci <= last[0]; ++ci) {
        const Index cell = mesh_->cell_index(ci, j, k);
        for (Index e = 5 * cell; e < 5 * cell + 5; ++e) {
          const auto& nodes = mesh_->element_nodes(e);
          const std::array<Vec3, 4> v{mesh_->node(nodes[0]), mesh_->node(nodes[1]), mesh_->node(nodes[2]),
                                      mesh_->node(nodes[3])};
          visit(e, sphere_tetrahedron_volume(c, r, v));
        }
      }
}

void PorosityField::add_intersection_volumes(const Particles& particles, const GrainShare& share) {
  // The counted grains' overlaps are kept for grain_means; a grain this rank
  // does not count deposits nothing, and grain_means recomputes its overlaps.
  overlaps_.clear();
  overlap_elements_.clear();
  overlap_start_.resize(particles.size() + 1);
  overlap_start_[0] = 0;
  overlap_kept_.assign(particles.size(), 0);
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (share.counts(i)) {
      overlap_kept_[i] = 1;
      for_each_overlap(particles, i, [&](Index e, double v) {
        if (v == 0.0) return;  // a tetrahedron of a touched cell the sphere misses
        solid_[static_cast<std::size_t>(e)] += v;
        overlaps_.emplace_back(e, v);
        overlap_elements_.push_back(e);
      });
    }
    overlap_start_[i + 1] = overlaps_.size();
  }
}

void PorosityField::grain_means(const Particles& particles, const ParticleMapping& mapping,
                                std::span<const Vec3> element_field, std::span<Vec3> out) {
  const std::size_t np = particles.size();
  if (element_field.size() != static_cast<std::size_t>(mesh_->num_elements()) || out.size() != np)
    throw std::invalid_argument("PorosityField::grain_means: one value per element and one output per grain");
  std::fill(out.begin(), out.end(), Vec3::Zero());
  if (entry_->deposit == SolidDeposit::element_of_centre) {
    // s_ie = V_i in the element of its centre.
    for (std::size_t i = 0; i < np; ++i)
      if (mapping.element[i] >= 0) out[i] = element_field[static_cast<std::size_t>(mapping.element[i])];
    return;
  }
  if (entry_->deposit == SolidDeposit::element_overlap) {
    // s_ie = the sphere's volume inside e, as update() found it (recomputed
    // for a grain update() did not count, or if it saw another number of grains).
    const bool cached = overlap_start_.size() == np + 1;
    for (std::size_t i = 0; i < np; ++i) {
      Vec3 sum = Vec3::Zero();
      if (cached && overlap_kept_[i] != 0) {
        for (std::size_t k = overlap_start_[i]; k < overlap_start_[i + 1]; ++k)
          sum += overlaps_[k].second * element_field[static_cast<std::size_t>(overlaps_[k].first)];
      } else {
        for_each_overlap(particles, i, [&](Index e, double v) { sum += v * element_field[static_cast<std::size_t>(e)]; });
      }
      out[i] = sum / sphere_volume(particles.diameter[i]);
    }
    return;
  }
  // Nodes by weights: V_e (1 - eps_e) = V_e / 4 sum_{a in e} phi_a, phi =
  // S^-1 b with b_a = sum_i w_ia V_i (S = M, or M + L^2 K when smoothed, both
  // symmetric). So sum_e V_e (1 - eps_e) f_e = y^T b with y = S^-1 g,
  // g_a = sum_{e ni a} V_e f_e / 4, and grain i's share is sum_a w_ia y_a.
  const auto nn = static_cast<std::size_t>(mesh_->num_nodes());
  Eigen::MatrixX3d nodal = Eigen::MatrixX3d::Zero(static_cast<Eigen::Index>(nn), 3);
  for (Index e = 0; e < mesh_->num_elements(); ++e) {
    const Vec3 share = 0.25 * mesh_->element_volume(e) * element_field[static_cast<std::size_t>(e)];
    for (Index a : mesh_->element_nodes(e)) nodal.row(a) += share.transpose();
  }
  if (entry_->smoothed) {
    PorosityDiffusion& d = *diffusion_;
    for (Eigen::Index c = 0; c < 3; ++c) {
      const Eigen::VectorXd g = nodal.col(c);
      const Eigen::VectorXd y = d.cg.solve(g);
      if (d.cg.info() != Eigen::Success)
        throw std::runtime_error("PorosityField::grain_means: the diffusion solve did not converge");
      nodal.col(c) = y;
    }
  } else {
    for (std::size_t a = 0; a < nn; ++a) nodal.row(static_cast<Eigen::Index>(a)) /= nodal_volume_[a];
  }
  for (std::size_t i = 0; i < np; ++i) {
    const Index e = mapping.element[i];
    if (e < 0) continue;
    const auto& nodes = mesh_->element_nodes(e);
    Vec3 sum = Vec3::Zero();
    for (std::size_t a = 0; a < 4; ++a) sum += mapping.weights[i][a] * nodal.row(nodes[a]).transpose();
    out[i] = sum;
  }
}

}  // namespace fdem
