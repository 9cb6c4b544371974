// DEM engine: effect-specialised kernels behind one class (see dem_engine.hpp).
#include "dem/dem_engine.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <istream>
#include <limits>
#include <ostream>
#include <stdexcept>
#include <utility>

#include <omp.h>

#include "core/binary_stream.hpp"
#include "core/error.hpp"
#include "dem/cell_order.hpp"
#include "dem/contact_law.hpp"
#include "dem/neighbour_list.hpp"
#include "dem/near_pairs.hpp"
#include "dem/near_wall_grains.hpp"
#include "dem/pair_lanes.hpp"
#include "parallel/grain_exchange.hpp"
#include "scene/stability.hpp"
#include "scene/time_steps.hpp"

namespace fdem {

namespace {
using PhaseClock = std::chrono::steady_clock;
double seconds_since(PhaseClock::time_point start) {
  return std::chrono::duration<double>(PhaseClock::now() - start).count();
}
}  // namespace

/// State shared by every specialisation; the effect-specific work is in
/// KernelFor<...>::step_impl and ::forces.
class DemEngine::Kernel {
 public:
  Kernel(Particles particles, const Scene& scene) : p_(std::move(particles)), domain_(scene.domain) {
    const Effects& e = scene.effects;
    dt_ = scene.time.dem_step;
    if (!(dt_ > 0.0))
      throw InputError(scene.source_file, "time.dem_step", fmt::format("{:g}", dt_), "the DEM step must be positive");
    const std::size_t n = p_.size();
    if (p_.mass.size() != n || p_.diameter.size() != n || p_.vx.size() != n)
      throw std::invalid_argument("DemEngine: particle arrays of unequal length");
    for (std::size_t i = 0; i < n; ++i)
      if (!(p_.diameter[i] > 0.0) || !(p_.mass[i] > 0.0))
        throw InputError(scene.source_file, "particles", fmt::format("particle {} d={:g} m={:g}", i, p_.diameter[i], p_.mass[i]),
                         "every particle needs a positive diameter and mass");
    p_.fx.assign(n, 0.0);
    p_.fy.assign(n, 0.0);
    p_.fz.assign(n, 0.0);
    if (p_.id.size() != n) {
      p_.id.resize(n);
      for (std::size_t i = 0; i < n; ++i) p_.id[i] = static_cast<Index>(i);
    }
    rotation_ = e.rotation;
    if (rotation_) {
      for (auto* v : {&p_.wx, &p_.wy, &p_.wz}) v->resize(n, 0.0);
      for (auto* v : {&p_.tx, &p_.ty, &p_.tz}) v->assign(n, 0.0);
      if (p_.inertia.size() != n) {
        p_.inertia.resize(n);
        for (std::size_t i = 0; i < n; ++i) p_.inertia[i] = 0.1 * p_.mass[i] * p_.diameter[i] * p_.diameter[i];  // solid sphere
      }
    }
    // Eq. 4-5: gravity m g and buoyancy -rho_f V g, folded into one factor
    // (1 - rho_f V / m) per particle; buoyancy only where there is a fluid.
    gravity_ = e.gravity ? scene.gravity : Vec3::Zero();
    buoyancy_density_ = (e.buoyancy && e.fluid) ? scene.fluid.density : 0.0;
    body_factor_.resize(n);
    for (std::size_t i = 0; i < n; ++i)
      body_factor_[i] = 1.0 - buoyancy_density_ * sphere_volume(p_.diameter[i]) / p_.mass[i];

    normal_contact_ = e.normal_contact;
    tangential_ = e.tangential_contact && e.normal_contact;
    walls_ = e.walls;
    law_ = contact_law_of(scene.contact);

    // Refuse an unstable step before any step is taken (the bound the
    // scene's time steps were resolved under, scene/time_steps.hpp).
    if (n > 0) require_stable_dem_step(scene, mass_range(p_), dt_);
    double d_max = 0.0;
    for (double d : p_.diameter) d_max = std::max(d_max, d);
    skin_ = 0.5 * d_max;
  }
  virtual ~Kernel() = default;
  Kernel(const Kernel&) = delete;
  Kernel& operator=(const Kernel&) = delete;

  void step() {
    whole_current_ = exchange_ == nullptr;  // decomposed: whole_ is this step's only after a collect()
    if (frozen_) {
      time_ += dt_;
      ++steps_;
      return;
    }
    if (forces_stale_) {  // F^n for the first kick (start, after moves or a new external force)
      settle();  // a pending second kick uses the F^n it was computed with
      refresh_neighbours(true);
      compute_forces();
      forces_stale_ = false;
    }
    step_impl();
    time_ += dt_;
    ++steps_;
  }

  /// Completes a deferred second kick, so the particles hold v^{n+1}
  /// (step_impl defers it into the next step's pass; anything that reads or
  /// changes the particles from outside calls this first).
  virtual void settle() = 0;
  /// DemEngine::sort_in_cell_order: fills order_ (empty when the grains are
  /// in cell order already) and moves every per-grain array along.
  virtual void sort_grains() = 0;
  virtual DemDiagnostics diagnostics() const = 0;
  virtual void save_state(std::ostream& out) const = 0;
  virtual void load_state(std::istream& in) = 0;

  // DemEngine::decompose (dem_engine.hpp). The cutoff's diameter is the
  // largest of the whole set, which every rank holds now.
  void decompose(std::unique_ptr<GrainExchange> exchange, bool owners_stay_in_slabs) {
    settle();
    owners_stay_in_slabs_ = owners_stay_in_slabs;
    cutoff_diameter_ = 0.0;
    for (double d : p_.diameter) cutoff_diameter_ = std::max(cutoff_diameter_, d);
    exchange->set_cutoff(cutoff_diameter_ + skin_);  // refuses slabs thinner than it, before any step
    whole_diagnostics_ = diagnostics();
    whole_ = p_;
    whole_current_ = true;
    decomposed_from_ = p_.size();
    exchange_ = std::move(exchange);
    forces_stale_ = true;  // the first step redistributes and rebuilds
  }

  // DemEngine::collect: every rank's owned grains, and the diagnostics summed.
  void collect() {
    if (!exchange_) return;
    settle();
    whole_ = exchange_->gather_owned(p_);
    whole_current_ = true;
    collect_diagnostics();
  }

  // DemEngine::collect_diagnostics: the diagnostics summed over the ranks (7 numbers).
  void collect_diagnostics() {
    if (!exchange_) return;
    settle();
    DemDiagnostics d = diagnostics_of_owned();
    double sums[6] = {static_cast<double>(d.particles), static_cast<double>(d.contacts),
                      static_cast<double>(d.wall_contacts), d.kinetic_energy_j,
                      static_cast<double>(d.particles_removed), static_cast<double>(d.neighbour_entries)};
    exchange_->sum_over_ranks(sums);
    exchange_->max_over_ranks({&d.max_overlap_over_diameter, 1});
    d.particles = static_cast<std::size_t>(sums[0]);
    d.contacts = static_cast<std::size_t>(sums[1]);
    d.wall_contacts = static_cast<std::size_t>(sums[2]);
    d.kinetic_energy_j = sums[3];  // summed per rank, then over ranks: not one process's order
    d.particles_removed = static_cast<std::size_t>(sums[4]);
    d.neighbour_entries = static_cast<std::size_t>(sums[5]);
    whole_diagnostics_ = d;
  }

  Particles p_;
  Box domain_;
  double dt_ = 0.0, time_ = 0.0, skin_ = 0.0;
  std::size_t steps_ = 0, removed_ = 0;
  bool rotation_ = false, walls_ = true, normal_contact_ = true;
  bool frozen_ = false, forces_stale_ = true;
  bool pending_kick_ = false;  // velocities are v^{n+1/2}; the second kick with F^{n+1} is still to apply
  Vec3 gravity_ = Vec3::Zero();
  double buoyancy_density_ = 0.0;
  GrainArray body_factor_;
  ContactLaw law_;
  NeighbourList list_;
  ExternalForce* external_ = nullptr;
  DemPhaseSeconds phases_;
  bool tangential_ = false;
  // Decomposed over MPI ranks (decompose()); empty in one process.
  std::unique_ptr<GrainExchange> exchange_;
  bool owners_stay_in_slabs_ = false;  // decompose: migrate at half a skin of absolute displacement
  double cutoff_diameter_ = 0.0;        // largest diameter of the whole set [m]
  std::size_t decomposed_from_ = 0;     // grains of the whole set at decompose()
  Particles whole_;                     // collect(): every rank's grains, ascending id
  bool whole_current_ = true;           // whole_ gathered since the last step (always in one process)
  std::vector<std::vector<double>> carried_;  // rebuild_list: the external force's per-grain state in transit
  DemDiagnostics whole_diagnostics_;    // collect(): summed over the ranks

  // Eq. 4-5's factor 1 - rho_f V / m of the constructor, for grains that
  // arrived or left (the same expression, so the same bits).
  static GrainArray body_factors(const Particles& p, double buoyancy_density) {
    GrainArray out(p.size());
    for (std::size_t i = 0; i < p.size(); ++i)
      out[i] = 1.0 - buoyancy_density * sphere_volume(p.diameter[i]) / p.mass[i];
    return out;
  }
  // diagnostics() over this rank's owned grains (each contact once over the ranks).
  virtual DemDiagnostics diagnostics_of_owned() const = 0;
  std::vector<Index> order_;  // the last sort's permutation, new index -> old index
  std::size_t sorts_ = 0;
  DemEngine::GrainSortPolicy sort_policy_;

 protected:
  virtual void step_impl() = 0;
  virtual void compute_forces() = 0;
  virtual void refresh_neighbours(bool force) = 0;
};

namespace {

constexpr int kWalls = NearWallGrains::faces;  // x_min, x_max, y_min, y_max, z_min, z_max
// Below this many particles a parallel region costs more than it saves (and
// on an oversubscribed machine a barrier can cost a whole time slice).
constexpr std::ptrdiff_t kParallelMin = 2500;
// wall_scan's candidate test is a gather and ~40 instructions a grain
// (callgrind, scene B's 1489 candidates: ~60k a step, ~15 us), a fork/join
// a few us: worth threads from fewer grains than a streaming pass.
constexpr std::ptrdiff_t kParallelMinWallScan = 1000;

template <bool Tangential, bool Rotation, bool Walls, class NormalLaw>
class KernelFor final : public DemEngine::Kernel {
 public:
  using Kernel::Kernel;

  void refresh_neighbours(bool force) override {
    const auto start = PhaseClock::now();
    rebuild_list(force);
    phases_.neighbour_build += seconds_since(start);
  }

  void rebuild_list(bool force) {
    // Decomposed: ghosts dropped before the lost-grain test (a ghost is
    // its owner's to lose), migration and new ghosts after it.
    // The external force's per-grain state travels with the grains
    // (ExternalForce::carried_state), on every rank or on none. First the
    // slab boundaries follow the grains (GrainExchange::rebalance), so the
    // slip history's routing and the migration below use the same ones.
    if (exchange_) {
      exchange_->rebalance(p_);
      carried_.clear();
      if (external_ != nullptr) carried_ = external_->carried_state(p_);
      for (const std::vector<double>& v : carried_)
        if (v.size() != p_.size()) carried_.clear();
      if (exchange_->any_rank(carried_.empty())) carried_.clear();
      if constexpr (Tangential) carry_slip_history();
      exchange_->drop_ghosts(p_, carried_);
      body_factor_ = body_factors(p_, buoyancy_density_);
      if constexpr (Tangential) wall_slip_.assign(kWalls * p_.size(), Vec3::Zero());  // in carried_ meanwhile
    }
    const bool lost = remove_lost_particles();
    if (exchange_) {
      exchange_->set_cutoff(cutoff_diameter_ + skin_);
      exchange_->migrate_and_gather_ghosts(p_, carried_);
      body_factor_ = body_factors(p_, buoyancy_density_);
      if constexpr (Tangential) restore_wall_slips();
      if (external_ != nullptr) {
        const bool lost_anywhere = exchange_->any_rank(lost);
        external_->grains_redistributed(p_, std::move(carried_), lost_anywhere);
      }
      carried_.clear();
    }
    refresh_factors();
    if (normal_contact_ && (force || lost || exchange_ || list_.needs_rebuild(p_))) build_list();
    old_to_new_base_.clear();
  }

  // A new list at the current positions. With tangential contact the slip
  // history of every pair that stays in the list moves to its new entry,
  // through old_to_new_base_ when grains were removed or reordered since
  // the old list was built.
  void build_list() {
    if constexpr (Tangential) {
      if (exchange_) {
        build_list_with_routed_slips();
        return;
      }
      const std::vector<Index> old_offsets = list_.offsets(), old_indices = list_.indices();
      const std::vector<Vec3> old_slip = std::move(slip_);
      list_.build(p_, skin_);
      slip_.assign(list_.entries(), Vec3::Zero());
      if (!old_offsets.empty()) {
        const auto n = static_cast<std::ptrdiff_t>(p_.size());
#pragma omp parallel for schedule(static) if (n > kParallelMin)
        for (std::ptrdiff_t si = 0; si < n; ++si) {
          const auto i = static_cast<std::size_t>(si);
          const auto oi = static_cast<std::size_t>(old_index(i));
          if (oi + 1 >= old_offsets.size()) continue;
          const auto ob = old_indices.begin() + old_offsets[oi], oe = old_indices.begin() + old_offsets[oi + 1];
          for (Index k = list_.offsets()[i]; k < list_.offsets()[i + 1]; ++k) {
            const Index oj = old_index(static_cast<std::size_t>(list_.indices()[static_cast<std::size_t>(k)]));
            const auto it = std::lower_bound(ob, oe, oj);
            if (it != oe && *it == oj)
              slip_[static_cast<std::size_t>(k)] = old_slip[static_cast<std::size_t>(it - old_indices.begin())];
          }
        }
      }
    } else {
      list_.build(p_, skin_);
      near_.invalidate();
      near_walls_.invalidate();
    }
  }

  // Decomposed over MPI ranks, the slip history travels with the grains
  // (the tangential spring of Eq. 8 is a state of each contact): at a
  // redistribution each rank takes the live slips of its owned grains' rows,
  // one record (id_i, id_j, slip) per list entry (i, j), and sends each
  // where grain i goes (GrainExchange::route_with_grains); the wall slips,
  // six per grain, travel as carried arrays. Only owned rows matter: a
  // grain's force is summed from its own row, and a ghost's is discarded.
  // After the list is rebuilt, each owned row's entry (i, j) takes the slip
  // of record (id_i, id_j): the pair in contact is in both lists (within the
  // cutoff of each other), and a pair out of contact holds +0 in one
  // process too, so every owned row holds one process's slips bit for bit.
  static constexpr std::size_t kSlipRecord = 5;  // id_i, id_j, slip x y z
  void carry_slip_history() {
    const std::size_t n = p_.size();
    const std::span<const std::uint8_t> ghost = exchange_->ghost_mask();
    const bool distributed = exchange_->distributed() && ghost.size() == n;
    std::vector<std::size_t> grain;
    std::vector<double> records;
    if (list_.offsets().size() == n + 1 && slip_.size() == list_.entries()) {
      for (std::size_t i = 0; i < n; ++i) {
        if (distributed && ghost[i] != 0) continue;
        for (Index k = list_.offsets()[i]; k < list_.offsets()[i + 1]; ++k) {
          const Vec3& s = slip_[static_cast<std::size_t>(k)];
          if (all_positive_zero(s)) continue;
          const auto j = static_cast<std::size_t>(list_.indices()[static_cast<std::size_t>(k)]);
          grain.push_back(i);
          records.insert(records.end(), {static_cast<double>(p_.id[i]), static_cast<double>(p_.id[j]), s.x(), s.y(),
                                         s.z()});  // ids exact: 32-bit
        }
      }
    }
    routed_slips_ = exchange_->route_with_grains(p_, grain, records, kSlipRecord);
    // The wall slips as 3 x 6 carried arrays, after the external force's.
    for (std::size_t w = 0; w < kWalls; ++w)
      for (int c = 0; c < 3; ++c) {
        std::vector<double> v(n);
        for (std::size_t i = 0; i < n; ++i) v[i] = wall_slip_[kWalls * i + w][c];
        carried_.push_back(std::move(v));
      }
  }
  void restore_wall_slips() {
    const std::size_t n = p_.size(), first = carried_.size() - 3 * kWalls;
    wall_slip_.assign(kWalls * n, Vec3::Zero());
    for (std::size_t w = 0; w < kWalls; ++w)
      for (int c = 0; c < 3; ++c) {
        const std::vector<double>& v = carried_[first + 3 * w + static_cast<std::size_t>(c)];
        for (std::size_t i = 0; i < n; ++i) wall_slip_[kWalls * i + w][c] = v[i];
      }
    carried_.resize(first);
  }
  void build_list_with_routed_slips() {
    list_.build(p_, skin_);
    slip_.assign(list_.entries(), Vec3::Zero());
    const std::size_t count = routed_slips_.size() / kSlipRecord;
    std::vector<std::size_t> order(count);
    for (std::size_t r = 0; r < count; ++r) order[r] = r;
    const auto key = [&](std::size_t r) {
      return std::pair<double, double>(routed_slips_[kSlipRecord * r], routed_slips_[kSlipRecord * r + 1]);
    };
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return key(a) < key(b); });
    const std::span<const std::uint8_t> ghost = exchange_->ghost_mask();
    const std::size_t n = p_.size();
    for (std::size_t i = 0; i < n; ++i) {
      if (i < ghost.size() && ghost[i] != 0) continue;
      for (Index k = list_.offsets()[i]; k < list_.offsets()[i + 1]; ++k) {
        const auto j = static_cast<std::size_t>(list_.indices()[static_cast<std::size_t>(k)]);
        const std::pair<double, double> wanted(static_cast<double>(p_.id[i]), static_cast<double>(p_.id[j]));
        const auto at = std::lower_bound(order.begin(), order.end(), wanted,
                                         [&](std::size_t r, const std::pair<double, double>& w) { return key(r) < w; });
        if (at == order.end() || key(*at) != wanted) continue;
        const double* s = &routed_slips_[kSlipRecord * *at + 2];
        slip_[static_cast<std::size_t>(k)] = Vec3(s[0], s[1], s[2]);
      }
    }
    routed_slips_.clear();
  }

  // DemEngine::sort_in_cell_order. Every per-grain array moves with its
  // grain (a pending second kick is applied first: it reads F^n by index);
  // the list is rebuilt at the new indices, slips carried over; the
  // factors of the fused pass are recomputed (bit for bit, per grain).
  void sort_grains() override {
    const auto start = PhaseClock::now();
    order_.clear();
    if (exchange_) return;  // decomposed: see DemEngine::sort_due
    settle();
    double d_max = 0.0;
    for (double d : p_.diameter) d_max = std::max(d_max, d);
    order_ = cell_order(p_, d_max + skin_);
    bool in_order = true;
    for (std::size_t k = 0; k < order_.size() && in_order; ++k) in_order = order_[k] == static_cast<Index>(k);
    if (in_order) {
      order_.clear();  // nothing moved
      phases_.sorting += seconds_since(start);
      return;
    }
    const std::size_t n = p_.size();
    GrainArray scratch(n);
    auto permute = [&](GrainArray& v) {
      if (v.size() != n) return;  // an effect's array that is off (rotation)
      for (std::size_t k = 0; k < n; ++k) scratch[k] = v[static_cast<std::size_t>(order_[k])];
      v.swap(scratch);
    };
    for (auto* v : {&p_.x, &p_.y, &p_.z, &p_.vx, &p_.vy, &p_.vz, &p_.fx, &p_.fy, &p_.fz, &p_.diameter, &p_.mass,
                    &p_.wx, &p_.wy, &p_.wz, &p_.tx, &p_.ty, &p_.tz, &p_.inertia, &body_factor_})
      permute(*v);
    std::vector<Index> ids(n);
    for (std::size_t k = 0; k < n; ++k) ids[k] = p_.id[static_cast<std::size_t>(order_[k])];
    p_.id.swap(ids);
    if constexpr (Tangential) {
      std::vector<Vec3> walls(wall_slip_.size());
      for (std::size_t k = 0; k < n; ++k)
        for (std::size_t w = 0; w < kWalls; ++w)
          walls[kWalls * k + w] = wall_slip_[kWalls * static_cast<std::size_t>(order_[k]) + w];
      wall_slip_.swap(walls);
    }
    // Not rebuild_list: a grain outside the box stays until the next step's
    // rebuild removes it, so the permutation the owner gets is the whole one.
    refresh_factors();
    old_to_new_base_ = order_;
    if (normal_contact_) build_list();
    old_to_new_base_.clear();
    ++sorts_;
    phases_.sorting += seconds_since(start);
  }

  DemDiagnostics diagnostics() const override {
    if (exchange_) return whole_diagnostics_with_phases();
    return diagnostics_of_owned();
  }

  DemDiagnostics whole_diagnostics_with_phases() const {
    DemDiagnostics d = whole_diagnostics_;
    d.steps = steps_;
    d.neighbour_rebuilds = list_.builds();
    d.phases = phases_;  // this rank's
    return d;
  }

  DemDiagnostics diagnostics_of_owned() const override {
    DemDiagnostics d;
    const std::span<const std::uint8_t> ghost =
        exchange_ ? exchange_->ghost_mask() : std::span<const std::uint8_t>{};
    d.steps = steps_;
    d.particles = p_.size();
    d.particles_removed = removed_;
    d.neighbour_rebuilds = list_.builds();
    d.neighbour_entries = list_.entries();
    d.grain_sorts = sorts_;
    d.phases = phases_;
    const std::size_t n = p_.size();
    if (!ghost.empty()) d.particles = exchange_->owned_count();
    for (std::size_t i = 0; i < n; ++i) {
      if (!ghost.empty() && ghost[i] != 0) continue;  // its owner counts it
      d.kinetic_energy_j += 0.5 * p_.mass[i] * (p_.vx[i] * p_.vx[i] + p_.vy[i] * p_.vy[i] + p_.vz[i] * p_.vz[i]);
      if constexpr (Rotation)
        d.kinetic_energy_j += 0.5 * p_.inertia[i] * (p_.wx[i] * p_.wx[i] + p_.wy[i] * p_.wy[i] + p_.wz[i] * p_.wz[i]);
      if (normal_contact_ && list_.offsets().size() == n + 1) {
        for (Index j : list_.neighbours(i)) {
          const auto uj = static_cast<std::size_t>(j);
          if (uj <= i) continue;
          const double ratio = overlap_over_smaller_diameter(i, uj);
          if (ratio > 0.0) {
            ++d.contacts;
            d.max_overlap_over_diameter = std::max(d.max_overlap_over_diameter, ratio);
          }
        }
      }
      if (Walls && normal_contact_) {
        for (int w = 0; w < kWalls; ++w) {
          const double overlap = 0.5 * p_.diameter[i] - wall_distance(i, w);
          if (overlap > 0.0) {
            ++d.wall_contacts;
            d.max_overlap_over_diameter = std::max(d.max_overlap_over_diameter, overlap / p_.diameter[i]);
          }
        }
      }
    }
    return d;
  }

 protected:
  void step_impl() override {
    auto start = PhaseClock::now();
    const auto n = static_cast<std::ptrdiff_t>(p_.size());
    const double half_dt = 0.5 * dt_;
    // 1. One streaming pass (kick_drift): the previous step's second kick
    //    when it is still pending, the first kick and the drift, the
    //    displacement and lost-grain tests, the body force of F^{n+1} and
    //    the wall mask at x^{n+1}. With a list and a box, and no slip
    //    history or other rank, the lost-grain and wall tests run after
    //    the pass on the few grains that can be near a wall (wall_scan).
    const bool have_list = list_.reference_x().size() == p_.size();
    const Vec3 lo = domain_.lower, hi = domain_.upper;
    const bool domain_set = hi.x() > lo.x() && hi.y() > lo.y() && hi.z() > lo.z();
    const bool lean = !Tangential && have_list && domain_set && !exchange_;
    // The drift velocities' extremes (six min/max a grain, +28 % of scene
    // P's pass) only while the near-pair set needs them (near_pairs.hpp).
    const bool extremes = !Tangential && !exchange_ && near_.tracks_drift();
    DriftSummary drift = pending_kick_ ? (lean ? kick_drift_of<true, false>(have_list, extremes)
                                               : kick_drift_of<true, true>(have_list, extremes))
                                       : (lean ? kick_drift_of<false, false>(have_list, extremes)
                                               : kick_drift_of<false, true>(have_list, extremes));
    near_wall_list_ = lean;
    if (lean) wall_scan(drift);
    pending_kick_ = false;
    if constexpr (Rotation) kick_angular(half_dt);
    if (exchange_) drift = exchange_ghosts(drift, have_list);
    // Decomposed under a coupling, the test is each grain's own
    // displacement, not the grains' relative one: the coupling's sums are
    // banded by fixed slab faces, so a cloud (or a lone grain) moving as one
    // past half the skin must migrate though its list still holds
    // (DemEngine::decompose's owners_stay_in_slabs).
    const bool moved_past_skin =
        owners_stay_in_slabs_ ? 4.0 * drift.max_disp2 > list_.skin() * list_.skin()
                              : (n > 0 || exchange_) &&
                                    NeighbourList::skin_exceeded(list_.skin(), drift.max_disp2, drift.spread[0],
                                                                 drift.spread[1], drift.spread[2]);
    const bool rebuild = !have_list || (domain_set && drift.outside > 0) || moved_past_skin;
    phases_.integration += seconds_since(start);
    // 2. Neighbours (rebuilt only past the skin), then F^{n+1}(x^{n+1}, v^{n+1/2}).
    //    A rebuild that removed lost grains invalidates the fused body
    //    force and wall mask (compact() moved them with the grains, but the
    //    mask was not compacted): compute_forces redoes both then.
    const std::size_t removed_before = removed_;
    if (rebuild) refresh_neighbours(true);
    // A redistribution moved grains between ranks: the fused pass's body
    // force and wall mask are of the old arrays.
    // How far any two grains can have moved apart or together in this
    // step's drift (unknown when decomposed: the ghosts moved with their
    // owners' velocities).
    constexpr double unknown = std::numeric_limits<double>::infinity();
    const double approach = exchange_ ? unknown : relative_drift_bound(drift);
    displacement_bound_ = exchange_ ? unknown : rebuild ? 0.0 : relative_displacement_bound(drift);
    compute_forces_after(removed_ == removed_before && !(exchange_ && rebuild), drift.near_walls, approach);
    // 3. Second kick, v^{n+1} = v^{n+1/2} + dt/2 F^{n+1}/m: deferred into the
    //    next step's pass (same operations, same bits, one pass fewer), or
    //    applied by settle() before anyone reads the particles.
    start = PhaseClock::now();
    pending_kick_ = true;
    if constexpr (Rotation) kick_angular(half_dt);
    phases_.integration += seconds_since(start);
  }

  struct DriftSummary {
    double max_disp2 = 0.0;
    double spread[3] = {0.0, 0.0, 0.0};
    double lowest[3] = {0.0, 0.0, 0.0};   // min over grains of the displacement, per axis
    double highest[3] = {0.0, 0.0, 0.0};  // max, per axis
    double sum_disp2 = 0.0;  // without WallTests: non-finite when a grain is (the extremes skip NaN)
    // max - min over grains of the drift velocity v^{n+1/2}, per axis (not
    // computed: infinite, so nothing is inferred from it)
    double velocity_spread[3] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
                                 std::numeric_limits<double>::infinity()};
    std::size_t outside = 0;
    std::size_t near_walls = 0;  // particles within a radius of a wall plane
  };

  // A bound on |d_i - d_j| for every pair, d the displacements since the
  // list build: twice the largest |d|, or the norm of the per-axis spreads
  // (neighbour_list.hpp, the rebuild test), whichever is smaller; free,
  // from the rebuild test's extremes. Non-finite when a grain is.
  static double relative_displacement_bound(const DriftSummary& drift) {
    const double spread2 =
        drift.spread[0] * drift.spread[0] + drift.spread[1] * drift.spread[1] + drift.spread[2] * drift.spread[2];
    return std::min(2.0 * std::sqrt(drift.max_disp2), std::sqrt(spread2));
  }

  // A bound on how much this step's drift x += dt v brought any two grains
  // closer: |dt (v_i - v_j)| <= dt |per-axis spreads of v|, plus the
  // rounding of the two position updates (each within an ulp of a
  // coordinate; the coordinates stay within the build's scale and a skin,
  // so 2^-48 of that is ample). Non-finite (unknown) without the spreads.
  double relative_drift_bound(const DriftSummary& drift) const {
    const double s0 = drift.velocity_spread[0], s1 = drift.velocity_spread[1], s2 = drift.velocity_spread[2];
    const double coordinate_scale = near_.build_scale() + list_.skin();
    return dt_ * std::sqrt(s0 * s0 + s1 * s1 + s2 * s2) * (1.0 + 1e-12) + 0x1p-48 * coordinate_scale;
  }

  // Decomposed, after the drift: the ghosts take their owners' x^{n+1},
  // v^{n+1/2} (and w), and the rebuild test gets the displacements of every
  // rank's owned grains, which are one process's grains: the maxima and
  // minima are exact, so every rank takes the rebuild one process would.
  // near_walls stays this rank's (it only skips this rank's wall pass).
  DriftSummary exchange_ghosts(const DriftSummary& local, bool have_list) {
    exchange_->update_ghosts(p_);
    const std::span<const std::uint8_t> ghost = exchange_->ghost_mask();
    const Vec3 lo = domain_.lower, hi = domain_.upper;
    constexpr double inf = std::numeric_limits<double>::infinity();
    // max |d|^2, max d per axis, max -d per axis, outside count
    double summary[8] = {0.0, -inf, -inf, -inf, -inf, -inf, -inf, 0.0};
    for (std::size_t i = 0; i < p_.size(); ++i) {
      if (ghost[i] != 0) continue;
      const double xi = p_.x[i], yi = p_.y[i], zi = p_.z[i];
      const double dx = have_list ? xi - list_.reference_x()[i] : 0.0;
      const double dy = have_list ? yi - list_.reference_y()[i] : 0.0;
      const double dz = have_list ? zi - list_.reference_z()[i] : 0.0;
      summary[0] = std::max(summary[0], dx * dx + dy * dy + dz * dz);
      summary[1] = std::max(summary[1], dx);
      summary[2] = std::max(summary[2], dy);
      summary[3] = std::max(summary[3], dz);
      summary[4] = std::max(summary[4], -dx);
      summary[5] = std::max(summary[5], -dy);
      summary[6] = std::max(summary[6], -dz);
      const bool inside = (xi >= lo.x()) & (xi <= hi.x()) & (yi >= lo.y()) & (yi <= hi.y()) & (zi >= lo.z()) &
                          (zi <= hi.z());
      summary[7] += inside ? 0.0 : 1.0;
    }
    exchange_->max_over_ranks(summary);
    DriftSummary out;
    out.max_disp2 = summary[0];
    for (int a = 0; a < 3; ++a) out.spread[a] = summary[1 + a] - (-summary[4 + a]);
    out.outside = summary[7] > 0.0 ? 1 : 0;
    out.near_walls = local.near_walls;
    return out;
  }

  // The fused pass of step_impl. With PendingKick the previous step's
  // second kick comes first, v^n = v^{n-1/2} + a F^n, then the first kick
  // v^{n+1/2} = v^n + a F^n, as two separate roundings, exactly the two
  // loops it replaces (a = dt/2 / m, precomputed bit for bit). Without
  // WallTests the outside count and the wall mask are left to wall_scan.
  template <bool PendingKick, bool WallTests>
  DriftSummary kick_drift_of(bool have_list, bool velocity_extremes) {
    return velocity_extremes ? kick_drift<PendingKick, WallTests, true>(have_list)
                             : kick_drift<PendingKick, WallTests, false>(have_list);
  }
  // The grains [begin, end) this thread of a parallel region integrates:
  // the rows of its share in the last threaded pair pass (shares_), whose
  // forces it alone summed, so they are in its cache, not the other
  // core's (scene B on 2 threads 1.04-1.09x, paired step quantiles,
  // 2026-12-07); else equal blocks (a static schedule's). Not with an
  // external force, which adds to the forces in its own equal blocks (the
  // drag: the plume's integration 0.97-0.99x on the pair split), nor when
  // a share holds more than 1.25 equal blocks' grains (the split is by
  // pair work; B's is 0.85 / 1.15).
  std::pair<std::ptrdiff_t, std::ptrdiff_t> grain_block(std::ptrdiff_t n) const {
    const auto threads = static_cast<std::ptrdiff_t>(omp_get_num_threads());
    const auto t = static_cast<std::ptrdiff_t>(omp_get_thread_num());
    const std::span<const Index> rows = shares_.first_rows();
    if (external_ == nullptr && shares_.balanced() && rows.size() == static_cast<std::size_t>(threads) + 1 &&
        rows.back() == n)
      return {rows[static_cast<std::size_t>(t)], rows[static_cast<std::size_t>(t) + 1]};
    return {n * t / threads, n * (t + 1) / threads};
  }
  // VelocityExtremes: also the per-axis extremes of v^{n+1/2} (velocity_spread).
  template <bool PendingKick, bool WallTests, bool VelocityExtremes>
  DriftSummary kick_drift(bool have_list) {
    const auto n = static_cast<std::ptrdiff_t>(p_.size());
    const double dt = dt_;
    // Without a list (normal contact off) measure against zeros: unused, and
    // never aliasing the positions written below.
    if (!have_list) no_reference_.assign(p_.size(), 0.0);
    const double* __restrict x0 = have_list ? list_.reference_x().data() : no_reference_.data();
    const double* __restrict y0 = have_list ? list_.reference_y().data() : no_reference_.data();
    const double* __restrict z0 = have_list ? list_.reference_z().data() : no_reference_.data();
    constexpr double inf = std::numeric_limits<double>::infinity();
    double max_disp2 = 0.0, lo_dx = inf, lo_dy = inf, lo_dz = inf, hi_dx = -inf, hi_dy = -inf, hi_dz = -inf;
    double lo_vx = inf, lo_vy = inf, lo_vz = inf, hi_vx = -inf, hi_vy = -inf, hi_vz = -inf;
    std::size_t outside = 0, near_walls = 0;
    double sum_disp2 = 0.0;
    // Raw restrict pointers: the arrays never alias, and saying so lets the
    // compiler vectorise this streaming loop (it is most of a free-fall step).
    double* __restrict x = p_.x.data();
    double* __restrict y = p_.y.data();
    double* __restrict z = p_.z.data();
    double* __restrict vx = p_.vx.data();
    double* __restrict vy = p_.vy.data();
    double* __restrict vz = p_.vz.data();
    double* __restrict fx = p_.fx.data();
    double* __restrict fy = p_.fy.data();
    double* __restrict fz = p_.fz.data();
    const double* __restrict kick = kick_factor_.data();
    const double* __restrict body = body_mass_.data();
    const double* __restrict d = p_.diameter.data();
    std::uint8_t* __restrict touch = wall_touch_.data();
    const double gx = gravity_.x(), gy = gravity_.y(), gz = gravity_.z();
    const BoxFaces box(domain_);
#pragma omp parallel if (n > kParallelMin) reduction(+ : outside, near_walls, sum_disp2) \
    reduction(max : max_disp2, hi_dx, hi_dy, hi_dz, hi_vx, hi_vy, hi_vz) reduction(min : lo_dx, lo_dy, lo_dz, lo_vx, lo_vy, lo_vz)
    {
      const auto [begin, end] = grain_block(n);
#pragma omp simd reduction(+ : outside, near_walls, sum_disp2) \
      reduction(max : max_disp2, hi_dx, hi_dy, hi_dz, hi_vx, hi_vy, hi_vz) reduction(min : lo_dx, lo_dy, lo_dz, lo_vx, lo_vy, lo_vz)
      for (std::ptrdiff_t i = begin; i < end; ++i) {
        const double a = kick[i];
        double vxi = vx[i], vyi = vy[i], vzi = vz[i];
        const double fxi = fx[i], fyi = fy[i], fzi = fz[i];
        if constexpr (PendingKick) {
          vxi = vxi + a * fxi;
          vyi = vyi + a * fyi;
          vzi = vzi + a * fzi;
        }
        vxi = vxi + a * fxi;
        vyi = vyi + a * fyi;
        vzi = vzi + a * fzi;
        vx[i] = vxi;
        vy[i] = vyi;
        vz[i] = vzi;
        if constexpr (VelocityExtremes) {
          lo_vx = std::min(lo_vx, vxi); hi_vx = std::max(hi_vx, vxi);
          lo_vy = std::min(lo_vy, vyi); hi_vy = std::max(hi_vy, vyi);
          lo_vz = std::min(lo_vz, vzi); hi_vz = std::max(hi_vz, vzi);
        }
        const double xi = x[i] + dt * vxi, yi = y[i] + dt * vyi, zi = z[i] + dt * vzi;
        x[i] = xi;
        y[i] = yi;
        z[i] = zi;
        const double dx = xi - x0[i], dy = yi - y0[i], dz = zi - z0[i];
        const double disp2 = dx * dx + dy * dy + dz * dz;
        max_disp2 = std::max(max_disp2, disp2);
        if constexpr (!WallTests) sum_disp2 += disp2;
        lo_dx = std::min(lo_dx, dx); hi_dx = std::max(hi_dx, dx);
        lo_dy = std::min(lo_dy, dy); hi_dy = std::max(hi_dy, dy);
        lo_dz = std::min(lo_dz, dz); hi_dz = std::max(hi_dz, dz);
        // F^{n+1} starts with the body force (Eq. 4-5), as compute_forces' first pass.
        const double bm = body[i];
        fx[i] = bm * gx;
        fy[i] = bm * gy;
        fz[i] = bm * gz;
        if constexpr (WallTests) {
          outside += box.contains(xi, yi, zi) ? 0u : 1u;
          const bool near = box.near_face(xi, yi, zi, 0.5 * d[i]);
          touch[i] = near ? 1 : 0;
          near_walls += near ? 1u : 0u;
        }
      }
    }
    DriftSummary out;
    out.lowest[0] = lo_dx;
    out.lowest[1] = lo_dy;
    out.lowest[2] = lo_dz;
    out.highest[0] = hi_dx;
    out.highest[1] = hi_dy;
    out.highest[2] = hi_dz;
    out.max_disp2 = max_disp2;
    out.sum_disp2 = sum_disp2;
    out.spread[0] = hi_dx - lo_dx;
    out.spread[1] = hi_dy - lo_dy;
    out.spread[2] = hi_dz - lo_dz;
    if (VelocityExtremes && n > 0) {
      out.velocity_spread[0] = hi_vx - lo_vx;
      out.velocity_spread[1] = hi_vy - lo_vy;
      out.velocity_spread[2] = hi_vz - lo_vz;
    }
    out.outside = outside;
    out.near_walls = near_walls;
    return out;
  }

  // The lost-grain and wall tests of kick_drift<..., true>, on the grains
  // that can be near a face (near_wall_grains.hpp).
  void wall_scan(DriftSummary& drift) {
    // A non-finite grain (a blown-up run) escapes the extremes: test all,
    // so that it counts as outside and the rebuild stops the run.
    const NearWallGrains::Scan scan = near_walls_.scan(p_, list_, domain_, drift.lowest, drift.highest,
                                                       !std::isfinite(drift.sum_disp2), kParallelMinWallScan);
    drift.outside = scan.outside;
    drift.near_walls = scan.near;
  }

  // Applies a pending second kick (step_impl, 3.), so the particles hold v^{n+1}.
  void settle() override {
    if (!pending_kick_) return;
    pending_kick_ = false;
    const auto start = PhaseClock::now();
    const auto m = static_cast<std::ptrdiff_t>(p_.size());
    double* __restrict ux = p_.vx.data();
    double* __restrict uy = p_.vy.data();
    double* __restrict uz = p_.vz.data();
    const double* __restrict gx = p_.fx.data();
    const double* __restrict gy = p_.fy.data();
    const double* __restrict gz = p_.fz.data();
    const double* __restrict kick = kick_factor_.data();
#pragma omp parallel for simd schedule(static) if (m > kParallelMin)
    for (std::ptrdiff_t i = 0; i < m; ++i) {
      const double a = kick[i];
      ux[i] = ux[i] + a * gx[i];
      uy[i] = uy[i] + a * gy[i];
      uz[i] = uz[i] + a * gz[i];
    }
    phases_.integration += seconds_since(start);
  }

  // Per-particle factors of the fused pass: a = dt/2 / m (the kicks) and
  // m (1 - rho_f V / m) (the body force, Eq. 4-5); recomputed whenever the
  // particles may have changed (list builds, loads), as the old loops
  // computed them in every step, bit for bit.
  void refresh_factors() {
    const std::size_t n = p_.size();
    const double half_dt = 0.5 * dt_;
    kick_factor_.resize(n);
    body_mass_.resize(n);
    wall_touch_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      kick_factor_[i] = half_dt / p_.mass[i];
      body_mass_[i] = p_.mass[i] * body_factor_[i];
    }
  }

  // Half kick of the angular velocities with the torques T^n: w += dt/2 T / I.
  void kick_angular(double half_dt) {
    const auto n = static_cast<std::ptrdiff_t>(p_.size());
#pragma omp parallel for schedule(static) if (n > kParallelMin)
    for (std::ptrdiff_t si = 0; si < n; ++si) {
      const auto i = static_cast<std::size_t>(si);
      const double b = half_dt / p_.inertia[i];
      p_.wx[i] += b * p_.tx[i];
      p_.wy[i] += b * p_.ty[i];
      p_.wz[i] += b * p_.tz[i];
    }
  }

  // F^{n+1} in three passes, each adding to a particle's force in the order
  // of the original single loop (body force, then its contacts in ascending
  // j, then the walls), so the sums are bitwise those of that loop:
  //   1. body force of every particle (a streaming, vectorised pass);
  //   2. contacts, only for particles that have neighbour-list entries;
  //   3. walls: a vectorised test of every particle, the contact law only
  //      for those that touch one.
  // In a dilute cloud (the salt plume: 0.2 neighbours per grain) passes 2
  // and 3 visit few particles; in a dense bed pass 2 is the whole cost.
  void compute_forces() override {
    displacement_bound_ = std::numeric_limits<double>::infinity();  // unknown here
    compute_forces_after(false, 0, std::numeric_limits<double>::infinity());
  }

  // fused_pass: step_impl's kick_drift has already written the body force
  // and the wall mask at these positions, and counted near_walls particles
  // in the mask. approach: a bound on how much closer any two grains are
  // than in the last step (relative_drift_bound; infinity: unknown).
  void compute_forces_after(bool fused_pass, std::size_t near_walls, double approach) {
    auto start = PhaseClock::now();
    const auto n = static_cast<std::ptrdiff_t>(p_.size());
    const bool contacts = normal_contact_;
    ++phases_.force_evaluations;
    if (!fused_pass) {
      double* __restrict fx = p_.fx.data();
      double* __restrict fy = p_.fy.data();
      double* __restrict fz = p_.fz.data();
      const double* __restrict mass = p_.mass.data();
      const double* __restrict body = body_factor_.data();
      const double gx = gravity_.x(), gy = gravity_.y(), gz = gravity_.z();
#pragma omp parallel for simd schedule(static) if (n > kParallelMin)
      for (std::ptrdiff_t i = 0; i < n; ++i) {
        const double bm = mass[i] * body[i];  // Eq. 4-5
        fx[i] = bm * gx;
        fy[i] = bm * gy;
        fz[i] = bm * gz;
      }
    }
    if constexpr (Rotation) {
      std::fill(p_.tx.begin(), p_.tx.end(), 0.0);
      std::fill(p_.ty.begin(), p_.ty.end(), 0.0);
      std::fill(p_.tz.begin(), p_.tz.end(), 0.0);
    }
    phases_.body_force += seconds_since(start);
    if (contacts) {
      start = PhaseClock::now();
      // No grain near a wall (a cloud in mid-water, the falling block P):
      // the pass would only read the mask, unless slip histories are to be
      // forgotten (tangential contact).
      const bool walls_idle = fused_pass && near_walls == 0 && !Tangential;
      // wall_scan's near grains (the lean step): the threaded pair pass
      // applies their walls itself, each thread for its block of grains
      // right after their contacts (same order, so the same bits).
      walls_in_pair_pass_ = Walls && !walls_idle && fused_pass && near_wall_list_;
      pair_forces(approach);
      phases_.pair_entries_tested += list_.entries();
      phases_.pairs += seconds_since(start);
      if constexpr (Walls) {
        if (!walls_idle && !walls_applied_) {
          start = PhaseClock::now();
          all_wall_forces(fused_pass);
          phases_.walls += seconds_since(start);
        }
      }
    }
    if (external_ != nullptr) {
      start = PhaseClock::now();
      external_->add(p_, p_.fx, p_.fy, p_.fz);
      phases_.external += seconds_since(start);
    }
  }

 private:
  // Pass 2 with tangential contact (a slip history per list entry): each
  // thread owns particle i and writes only i's force and torque, from the
  // full neighbour list, in ascending j whatever the thread count, so
  // results are bit-identical for any count.
  void pair_forces(double approach) {
    if constexpr (!Tangential)
      half_pair_forces(approach);
    else
      full_pair_forces();
  }

  void full_pair_forces() {
    const std::vector<Index>& listed = list_.particles_with_neighbours();
    const auto count = static_cast<std::ptrdiff_t>(listed.size());
    // Blow-up detector: an overlap above half the smaller diameter never
    // happens in a stable run (a settled bed stays below 1 %); one compare
    // per contact, reported after the loop (no throw inside OpenMP).
    int overlap_blown = 0;
#pragma omp parallel for schedule(static) if (count > kParallelMin) reduction(max : overlap_blown)
    for (std::ptrdiff_t a = 0; a < count; ++a) {
      const auto i = static_cast<std::size_t>(listed[static_cast<std::size_t>(a)]);
      Vec3 f(p_.fx[i], p_.fy[i], p_.fz[i]);
      Vec3 torque = Vec3::Zero();
      const double ri = 0.5 * p_.diameter[i];
      const Vec3 xi(p_.x[i], p_.y[i], p_.z[i]);
      const Vec3 vi(p_.vx[i], p_.vy[i], p_.vz[i]);
      const Index begin = list_.offsets()[i], end = list_.offsets()[i + 1];
      const Index* const index = list_.indices().data();
      for (Index k = begin; k < end; ++k) {
        const auto j = static_cast<std::size_t>(index[k]);
        const Vec3 dx = Vec3(p_.x[j], p_.y[j], p_.z[j]) - xi;
        const double rj = 0.5 * p_.diameter[j];
        const double sum_r = ri + rj, dist2 = dx.squaredNorm();
        if (dist2 < sum_r * sum_r) {
          const PairForce cf =
              pair_contact(i, j, vi, ri, dx, dist2, rj, sum_r, &slip_[static_cast<std::size_t>(k)], overlap_blown);
          f += cf.normal;
          f += cf.tangential;
          if constexpr (Rotation) torque += (ri * cf.unit_normal).cross(cf.tangential);  // Eq. 10
        } else {
          slip_[static_cast<std::size_t>(k)].setZero();  // contact ended: forget the slip
        }
      }
      store_force(i, f, torque);
    }
    if (overlap_blown) [[unlikely]] report_overlap_blow_up();
  }

  // One touching pair (i, j) seen from i (Eq. 6-10): the force on i, and
  // the unit normal from i towards j for the torque. The one place the
  // pair's relative velocity and damping are formed, for both kernels.
  struct PairForce : ContactForce {
    Vec3 unit_normal;
  };
  PairForce pair_contact(std::size_t i, std::size_t j, const Vec3& vi, double ri, const Vec3& dx, double dist2,
                         double rj, double sum_r, Vec3* slip, int& overlap_blown) const {
    const double dist = std::sqrt(dist2);
    if (sum_r - dist > std::min(ri, rj)) [[unlikely]] overlap_blown = 1;
    const Vec3 nrm = dx * (1.0 / dist);  // from i towards j (one division, not three)
    Vec3 v_rel = vi - Vec3(p_.vx[j], p_.vy[j], p_.vz[j]);
    if constexpr (Rotation) {
      // contact-point velocities: v_i + w_i x (r_i n) - v_j - w_j x (-r_j n); written so that the
      // j->i evaluation is the exact negative (Newton's third law bit for bit).
      const Vec3 spin = ri * Vec3(p_.wx[i], p_.wy[i], p_.wz[i]) + rj * Vec3(p_.wx[j], p_.wy[j], p_.wz[j]);
      v_rel += spin.cross(nrm);
    }
    // Only a law that reads it (e.g. a damping set by restitution) needs the pair's effective mass.
    double m_eff = 0.0;
    if constexpr (NormalLaw::needs_effective_mass) m_eff = p_.mass[i] * p_.mass[j] / (p_.mass[i] + p_.mass[j]);
    PairForce out;
    static_cast<ContactForce&>(out) =
        contact_force<Tangential, NormalLaw>(law_, m_eff, sum_r - dist, nrm, v_rel, dt_, slip);
    out.unit_normal = nrm;
    return out;
  }

  // Pass 2 without tangential contact (no per-entry slip history), over the
  // half list (pairs i < j, ascending (i, j), built with the list): each
  // pair is tested and, touching, its force F on i formed once; f_i += F
  // and f_j -= F, pair after pair in pair order. So each particle p gets
  // first -F(i, p) for every touching i < p ascending (those pairs come in
  // earlier rows), then +F(p, k) for every touching k > p ascending: p's
  // contacts in ascending index order, the order of a full-list row.
  // With T threads the pairs are split at grain rows into T shares of
  // equal estimated work (pair_shares.hpp; thread order = pair order), and
  // thread t owns the grains of its share's rows: it alone writes their
  // forces, so no thread waits for another. It first forms again the
  // touching pairs of earlier rows whose j is one of its grains (the
  // crossing pairs, which the earlier thread forms too, for its i) and
  // adds their -F to those j, in pair order; then runs its own pairs,
  // adding F to i and -F to the j it owns. Each particle gets the same
  // additions in the same order as in one thread, each F formed by the
  // same code from the same positions and velocities, so the bits do not
  // depend on the thread count. (Until 2026-12-07 the threads kept their
  // touching pairs with F in lists, 32 bytes a contact, and summed them
  // in a second pass after a barrier.) The lean step's wall contacts
  // follow, each thread those of its own rows' grains right after their
  // contacts (after all of a grain's contacts, as in the serial wall
  // pass). One parallel region a step, no barrier in it.
  // Work is per pair and per contact, not per particle: a dilute cloud
  // (the plume: one pair per grain) pays no row loop. Only the pairs that
  // can touch are tested (near_pairs.hpp): leaving out pairs that cannot
  // leaves the touching pairs, their order and so every bit unchanged.
  void half_pair_forces(double approach) {
    const auto n = static_cast<std::ptrdiff_t>(p_.size());
    const std::size_t slots = static_cast<std::size_t>(std::max(1, omp_get_max_threads()));
    if (pair_scratch_.size() < slots) pair_scratch_.resize(slots);
    const NearPairs::Selection selection = near_.select(list_, p_, approach, displacement_bound_, kParallelMin);
    phases_.near_pair_filters += selection.filtered ? 1 : 0;
    phases_.threaded_near_filters += selection.threaded ? 1 : 0;
    const PairSet& pairs = selection.pairs;
    phases_.pairs_tested += pairs.size();
    int overlap_blown = 0;
    const bool parallel = static_cast<std::ptrdiff_t>(pairs.size()) > kParallelMin;
    if (!parallel || omp_get_max_threads() == 1) {  // one thread: every force to both ends
      phases_.pairs_touching += find_touching_pairs<true>(pairs.i, pairs.j, pairs.start[0], pairs.start[p_.size()],
                                                          static_cast<Index>(n), nullptr, overlap_blown);
      if (overlap_blown) [[unlikely]] report_overlap_blow_up();
      walls_applied_ = false;
      return;
    }
    const auto pair_count = static_cast<std::ptrdiff_t>(pairs.size());
    const auto planned = static_cast<std::ptrdiff_t>(omp_get_max_threads());
    // The split and the crossing pairs hold while the pair set does (a
    // list build or a near filtering makes a new one).
    const SplitKey key{pairs.i, near_.generation(), planned};
    const bool resplit = !(key == split_key_);
    if (resplit) {
      shares_.cut(pairs, p_.size(), static_cast<std::size_t>(planned), pair_scratch_);
      split_key_ = key;
    }
    std::size_t touching_count = 0;
    bool as_planned = true;
#pragma omp parallel if (parallel) reduction(max : overlap_blown) reduction(+ : touching_count)
    {
      const auto threads = static_cast<std::ptrdiff_t>(omp_get_num_threads());
      const auto t = static_cast<std::ptrdiff_t>(omp_get_thread_num());
      if (t == 0 && threads > 1) ++phases_.threaded_pair_passes;
      if (t == 0) as_planned = threads == planned;
      // The shares of estimated work (PairShares::cut; equal shares of the
      // pairs, cut at rows, if the runtime gave another thread count).
      // Any split gives the same bits.
      const auto row_begin = [&](std::ptrdiff_t s) -> Index {
        if (threads == planned) return shares_.first_rows()[static_cast<std::size_t>(s)];
        if (s == 0 || s == threads) return s == 0 ? 0 : static_cast<Index>(n);  // every grain owned, even past the last pair
        const Index target = static_cast<Index>(pair_count * s / threads);
        return static_cast<Index>(std::lower_bound(pairs.start, pairs.start + n, target) - pairs.start);
      };
      const Index own_begin = row_begin(t), own_end = row_begin(t + 1);
      PairShareScratch& mine = pair_scratch_[static_cast<std::size_t>(t)];
      // 1. The crossing pairs into this thread's grains (collected once a
      //    pair set and split, PairShares::crossing_pairs).
      if (resplit || threads != planned) shares_.crossing_pairs(pairs, own_begin, own_end, mine.cross_i, mine.cross_j);
      // Counted by the thread that owns their rows.
      find_touching_pairs<false>(mine.cross_i.data(), mine.cross_j.data(), 0, static_cast<Index>(mine.cross_i.size()),
                                 own_end, nullptr, overlap_blown);
      // 2. This thread's rows: F to i, -F to the j it owns.
      mine.touching_rows.clear();
      touching_count += find_touching_pairs<true>(pairs.i, pairs.j, pairs.start[own_begin], pairs.start[own_end],
                                                  own_end, &mine.touching_rows, overlap_blown);
      if (walls_in_pair_pass_) {
        const std::vector<Index>& near = near_walls_.grains();
        const auto first = std::lower_bound(near.begin(), near.end(), own_begin);
        const auto last = std::lower_bound(first, near.end(), own_end);
        for (auto it = first; it != last; ++it) wall_forces_of(static_cast<std::size_t>(*it));
      }
    }
    if (!as_planned) split_key_ = SplitKey{};  // the crossing pairs kept are another split's: collect anew next time
    phases_.pairs_touching += touching_count;
    if (overlap_blown) [[unlikely]] report_overlap_blow_up();
    walls_applied_ = walls_in_pair_pass_;
  }

  // Pass 2's pairs [begin, end) of the pair arrays pi, pj (i < j, in pair
  // order): most are not in contact (skin), and which are is random: a
  // branch per pair mispredicts. So a block of pairs is first tested
  // without branching, keeping the touching ones in order, then the law
  // runs on those, and each touching pair's F is added right after:
  // f_i += F when ToI, f_j -= F when j < j_end (half_pair_forces: the
  // grains a thread owns). F goes through an empty asm (opaque_copy)
  // first: else the compiler fuses F's last product into the sum, one
  // rounding fewer. (Applying the law masked to every pair was measured
  // 1.6-1.9x slower on scene B: sqrt and division for all.) rows: when
  // set, each touching pair's i appended (for the next PairShares::cut).
  // Returns how many pairs touch.
  template <bool ToI>
  std::size_t find_touching_pairs(const Index* pi, const Index* pj, Index begin, Index end, Index j_end,
                                  std::vector<Index>* rows, int& overlap_blown) {
#ifdef FDEM_DEM_PAIR_LANES
    if constexpr (!Rotation && NormalLaw::pair_independent_linear)
      return find_touching_pairs_by_lanes<ToI>(pi, pj, begin, end, j_end, rows, overlap_blown);
#endif
    return find_touching_pairs_scalar<ToI>(pi, pj, begin, end, j_end, rows, overlap_blown);
  }

  // The force of one touching pair to the ends find_touching_pairs names.
  template <bool ToI>
  void add_pair_force(std::size_t i, std::size_t j, Index j_end, double f_x, double f_y, double f_z) {
    if constexpr (ToI) {
      p_.fx[i] += f_x;
      p_.fy[i] += f_y;
      p_.fz[i] += f_z;
    }
    if (static_cast<Index>(j) < j_end) {
      p_.fx[j] -= f_x;
      p_.fy[j] -= f_y;
      p_.fz[j] -= f_z;
    }
  }

#ifdef FDEM_DEM_PAIR_LANES
  // find_touching_pairs eight (AVX-512) or four (AVX2) pairs a vector
  // (dem/touching_pairs_avx512.hpp, _avx2.hpp); the law's F leaves the
  // lanes through memory, rounded.
  template <bool ToI>
  std::size_t find_touching_pairs_by_lanes(const Index* pi, const Index* pj, Index begin, Index end, Index j_end,
                                           std::vector<Index>* rows, int& overlap_blown) {
    namespace lanes = pair_lanes;
    std::size_t touching = 0;
    const auto& coefficients = normal_coefficients<typename NormalLaw::Coefficients>(law_);
    const double stiffness = NormalLaw::linear_stiffness(coefficients), damping = NormalLaw::linear_damping(coefficients);
    constexpr int kBlock = 64;
    lanes::Lanes<kBlock> block{};  // one per thread; zeroed: a tail vector reads lanes past the pairs found
    for (Index k0 = begin; k0 < end; k0 += kBlock) {
      const Index k1 = std::min(end, k0 + kBlock);
      const int found = lanes::test(pi, pj, k0, k1, p_.x.data(), p_.y.data(), p_.z.data(), p_.diameter.data(), block);
      touching += static_cast<std::size_t>(found);
      if (lanes::law(block, found, p_.vx.data(), p_.vy.data(), p_.vz.data(), stiffness, damping)) [[unlikely]]
        overlap_blown = 1;
      for (int q = 0; q < found; ++q)
        add_pair_force<ToI>(static_cast<std::size_t>(block.i[q]), static_cast<std::size_t>(block.j[q]), j_end,
                            block.fx[q], block.fy[q], block.fz[q]);
      if (rows != nullptr) rows->insert(rows->end(), block.i, block.i + found);
    }
    return touching;
  }
#endif

  template <bool ToI>
  std::size_t find_touching_pairs_scalar(const Index* pi, const Index* pj, Index begin, Index end, Index j_end,
                                         std::vector<Index>* rows, int& overlap_blown) {
    std::size_t touching_pairs = 0;
    const double* const x = p_.x.data();
    const double* const y = p_.y.data();
    const double* const z = p_.z.data();
    const double* const d = p_.diameter.data();
    constexpr Index kBlock = 64;
    Index touching[kBlock];
    for (Index k0 = begin; k0 < end; k0 += kBlock) {
      const Index k1 = std::min(end, k0 + kBlock);
      int found = 0;
      for (Index k = k0; k < k1; ++k) {
        const auto i = static_cast<std::size_t>(pi[k]), j = static_cast<std::size_t>(pj[k]);
        // The expressions of the contact law below, so the test and the law agree to the bit.
        const Vec3 dx = Vec3(x[j], y[j], z[j]) - Vec3(x[i], y[i], z[i]);
        const double sum_r = 0.5 * d[i] + 0.5 * d[j];
        const bool hit = dx.squaredNorm() < sum_r * sum_r;
        touching[found] = k;
        found += hit ? 1 : 0;
      }
      touching_pairs += static_cast<std::size_t>(found);
      for (int q = 0; q < found; ++q) {
        const Index k = touching[q];
        const auto i = static_cast<std::size_t>(pi[k]), j = static_cast<std::size_t>(pj[k]);
        const Vec3 dx = Vec3(x[j], y[j], z[j]) - Vec3(x[i], y[i], z[i]);
        const double ri = 0.5 * d[i], rj = 0.5 * d[j];
        const Vec3 vi(p_.vx[i], p_.vy[i], p_.vz[i]);
        const Vec3 f = pair_contact(i, j, vi, ri, dx, dx.squaredNorm(), rj, ri + rj, nullptr, overlap_blown).normal;
        add_pair_force<ToI>(i, j, j_end, opaque_copy(f.x()), opaque_copy(f.y()), opaque_copy(f.z()));
        if (rows != nullptr) rows->push_back(pi[k]);
      }
    }
    return touching_pairs;
  }

  // v as a value the compiler cannot see into, so the product that made it
  // is rounded on its own and not fused into the sum it goes to (no code).
  static double opaque_copy(double v) {
#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
    asm("" : "+x"(v));
#elif defined(__GNUC__) && defined(__aarch64__)
    asm("" : "+w"(v));
#else
    volatile double copy = v;
    v = copy;
#endif
    return v;
  }


  // Pass 3. The wall test is a vectorised mask over all particles; the few
  // that touch get the contact law. With tangential contact every
  // non-touching wall forgets its slip, as in Eq. 8 for an ended contact.
  void all_wall_forces(bool mask_current) {
    if (mask_current && near_wall_list_) {  // wall_scan's grains (no slip history to forget)
      const std::vector<Index>& near = near_walls_.grains();
      const auto count = static_cast<std::ptrdiff_t>(near.size());
#pragma omp parallel for schedule(static) if (count > kParallelMin)
      for (std::ptrdiff_t a = 0; a < count; ++a) wall_forces_of(static_cast<std::size_t>(near[static_cast<std::size_t>(a)]));
      return;
    }
    const auto n = static_cast<std::ptrdiff_t>(p_.size());
    wall_touch_.resize(p_.size());
    if (!mask_current) {
      std::uint8_t* __restrict touch = wall_touch_.data();
      const double* __restrict x = p_.x.data();
      const double* __restrict y = p_.y.data();
      const double* __restrict z = p_.z.data();
      const double* __restrict d = p_.diameter.data();
      const BoxFaces box(domain_);
#pragma omp parallel for simd schedule(static) if (n > kParallelMin)
      for (std::ptrdiff_t i = 0; i < n; ++i) touch[i] = box.near_face(x[i], y[i], z[i], 0.5 * d[i]) ? 1 : 0;
    }
#pragma omp parallel for schedule(static) if (n > kParallelMin)
    for (std::ptrdiff_t si = 0; si < n; ++si) {
      const auto i = static_cast<std::size_t>(si);
      if (wall_touch_[i] == 0) {
        if constexpr (Tangential)
          for (std::size_t w = 0; w < kWalls; ++w) wall_slip_[kWalls * i + w].setZero();
        continue;
      }
      Vec3 f(p_.fx[i], p_.fy[i], p_.fz[i]);
      Vec3 torque = Vec3::Zero();
      if constexpr (Rotation) torque = Vec3(p_.tx[i], p_.ty[i], p_.tz[i]);
      wall_forces(i, f, torque);
      store_force(i, f, torque);
    }
  }

  // Grain i's wall contacts added to its force (and torque).
  void wall_forces_of(std::size_t i) {
    Vec3 f(p_.fx[i], p_.fy[i], p_.fz[i]);
    Vec3 torque = Vec3::Zero();
    if constexpr (Rotation) torque = Vec3(p_.tx[i], p_.ty[i], p_.tz[i]);
    wall_forces(i, f, torque);
    store_force(i, f, torque);
  }

  // Writes a particle's summed force (and torque, with rotation) back.
  void store_force(std::size_t i, const Vec3& f, const Vec3& torque) {
    p_.fx[i] = f.x();
    p_.fy[i] = f.y();
    p_.fz[i] = f.z();
    if constexpr (Rotation) {
      p_.tx[i] = torque.x();
      p_.ty[i] = torque.y();
      p_.tz[i] = torque.z();
    } else {
      (void)torque;
    }
  }

 // The run has blown up: name the step, the pair and the overlap, then stop.
  [[noreturn]] void report_overlap_blow_up() const {
    double worst = 0.0;
    std::size_t wi = 0, wj = 0;
    for (std::size_t i = 0; i < p_.size(); ++i)
      for (Index j : list_.neighbours(i)) {
        const auto uj = static_cast<std::size_t>(j);
        const double ratio = overlap_over_smaller_diameter(i, uj);
        if (ratio > worst) {
          worst = ratio;
          wi = i;
          wj = uj;
        }
      }
    throw SolverError(fmt::format(
        "DEM step {} (t = {:.6g} s): particle {} overlaps particle {} by {:.3g} of the smaller diameter (limit 0.5): "
        "the contacts blew up; the DEM step {:.3g} s is above the stable bound (fdem check prints it)",
        steps_ + 1, time_ + dt_, label(wi), label(wj), worst, dt_));
  }

  // Overlap of pair (i, j) over the smaller diameter; <= 0 when apart.
  double overlap_over_smaller_diameter(std::size_t i, std::size_t j) const {
    const double dx = p_.x[j] - p_.x[i], dy = p_.y[j] - p_.y[i], dz = p_.z[j] - p_.z[i];
    return (0.5 * (p_.diameter[i] + p_.diameter[j]) - std::sqrt(dx * dx + dy * dy + dz * dz)) /
           std::min(p_.diameter[i], p_.diameter[j]);
  }

  // The particle's original label (ids survive removals), for messages.
  Index label(std::size_t i) const { return p_.id.empty() ? static_cast<Index>(i) : p_.id[i]; }

  double wall_distance(std::size_t i, int w) const {
    const int axis = w / 2;
    const double xi = axis == 0 ? p_.x[i] : axis == 1 ? p_.y[i] : p_.z[i];
    return (w % 2 == 0) ? xi - domain_.lower[axis] : domain_.upper[axis] - xi;
  }

  // The six box planes, at rest; particle-wall m_eff = m. Per axis two
  // gaps; the contact branch is rarely taken, so it predicts well.
  void wall_forces(std::size_t i, Vec3& f, Vec3& torque) {
    const double ri = 0.5 * p_.diameter[i];
    const double pos[3] = {p_.x[i], p_.y[i], p_.z[i]};
    for (int axis = 0; axis < 3; ++axis) {
      const double gap_lower = pos[axis] - domain_.lower[axis];
      const double gap_upper = domain_.upper[axis] - pos[axis];
      if (gap_lower < ri) [[unlikely]] wall_contact(i, 2 * axis, ri, gap_lower, f, torque);
      else if constexpr (Tangential) wall_slip_[kWalls * i + static_cast<std::size_t>(2 * axis)].setZero();
      if (gap_upper < ri) [[unlikely]] wall_contact(i, 2 * axis + 1, ri, gap_upper, f, torque);
      else if constexpr (Tangential) wall_slip_[kWalls * i + static_cast<std::size_t>(2 * axis + 1)].setZero();
    }
  }

  void wall_contact(std::size_t i, int w, double ri, double gap, Vec3& f, Vec3& torque) {
    Vec3 nrm = Vec3::Zero();  // from the sphere towards the wall
    nrm[w / 2] = (w % 2 == 0) ? -1.0 : 1.0;
    Vec3 v_rel(p_.vx[i], p_.vy[i], p_.vz[i]);
    if constexpr (Rotation) v_rel += (ri * Vec3(p_.wx[i], p_.wy[i], p_.wz[i])).cross(nrm);
    Vec3* slip = nullptr;
    if constexpr (Tangential) slip = &wall_slip_[kWalls * i + static_cast<std::size_t>(w)];
    const ContactForce cf =
        contact_force<Tangential, NormalLaw>(law_, p_.mass[i], ri - gap, nrm, v_rel, dt_, slip);
    f += cf.normal;
    if constexpr (Tangential) {
      f += cf.tangential;
      if constexpr (Rotation) torque += (ri * nrm).cross(cf.tangential);  // Eq. 10
    }
  }

  Index old_index(std::size_t i) const {
    return old_to_new_base_.empty() ? static_cast<Index>(i) : old_to_new_base_[i];
  }

  // Removes particles whose centre left the domain box (lost: only an
  // exploding or escaping grain gets there). Keeps the order of the rest.
  bool remove_lost_particles() {
    const Vec3 lo = domain_.lower, hi = domain_.upper;
    if (!(hi.x() > lo.x() && hi.y() > lo.y() && hi.z() > lo.z())) return false;
    const std::size_t n = p_.size();
    auto outside = [&](std::size_t i) {
      return !(p_.x[i] >= lo.x() && p_.x[i] <= hi.x() && p_.y[i] >= lo.y() && p_.y[i] <= hi.y() &&
               p_.z[i] >= lo.z() && p_.z[i] <= hi.z());
    };
    std::size_t lost = 0;
    for (std::size_t i = 0; i < n; ++i) lost += outside(i) ? 1 : 0;
    if (lost == 0) return false;
    // A non-finite grain, or a grain through a wall, means the run blew up:
    // stop with the step and the particle instead of removing it silently.
    // Only grains that leave an open (wall-less) side are removed and counted.
    for (std::size_t i = 0; i < n; ++i) {
      if (!outside(i)) continue;
      const Index id = label(i);
      const bool finite = std::isfinite(p_.x[i]) && std::isfinite(p_.y[i]) && std::isfinite(p_.z[i]) &&
                          std::isfinite(p_.vx[i]) && std::isfinite(p_.vy[i]) && std::isfinite(p_.vz[i]);
      if (!finite)
        throw SolverError(fmt::format("DEM step {} (t = {:.6g} s): particle {} has a non-finite position or velocity",
                                      steps_ + 1, time_ + dt_, id));
      if (walls_ && normal_contact_)
        throw SolverError(fmt::format(
            "DEM step {} (t = {:.6g} s): particle {} crossed a wall at ({:.4g}, {:.4g}, {:.4g}) m with speed {:.3g} m/s: "
            "its wall overlap exceeded its radius; the DEM step {:.3g} s is above the stable bound",
            steps_ + 1, time_ + dt_, id, p_.x[i], p_.y[i], p_.z[i],
            std::sqrt(p_.vx[i] * p_.vx[i] + p_.vy[i] * p_.vy[i] + p_.vz[i] * p_.vz[i]), dt_));
    }
    std::vector<Index> kept;
    kept.reserve(n - lost);
    for (std::size_t i = 0; i < n; ++i)
      if (!outside(i)) kept.push_back(static_cast<Index>(i));
    auto compact = [&](auto& v) {
      if (v.size() != n) return;
      for (std::size_t k = 0; k < kept.size(); ++k) v[k] = v[static_cast<std::size_t>(kept[k])];
      v.resize(kept.size());
    };
    for (auto* v : {&p_.x, &p_.y, &p_.z, &p_.vx, &p_.vy, &p_.vz, &p_.fx, &p_.fy, &p_.fz, &p_.diameter, &p_.mass,
                    &p_.wx, &p_.wy, &p_.wz, &p_.tx, &p_.ty, &p_.tz, &p_.inertia, &body_factor_})
      compact(*v);
    compact(p_.id);
    for (std::vector<double>& v : carried_) compact(v);  // decomposed: the external force's state (rebuild_list)
    if constexpr (Tangential) {
      for (std::size_t k = 0; k < kept.size(); ++k)
        for (std::size_t w = 0; w < kWalls; ++w)
          wall_slip_[kWalls * k + w] = wall_slip_[kWalls * static_cast<std::size_t>(kept[k]) + w];
      wall_slip_.resize(kWalls * kept.size());
    }
    // new index -> old index (that of the last list), for the slip history transfer
    if (!old_to_new_base_.empty())
      for (Index& k : kept) k = old_to_new_base_[static_cast<std::size_t>(k)];
    old_to_new_base_ = std::move(kept);
    removed_ += lost;
    return true;
  }

 public:
  void init_storage() {
    if constexpr (Tangential) wall_slip_.assign(kWalls * p_.size(), Vec3::Zero());
    refresh_neighbours(true);  // F^0, so diagnostics and the first kick see the initial contacts
    compute_forces();
    forces_stale_ = false;
  }

  // Checkpoint, section "DEM " (layout: the order of the writes below).
  static constexpr std::uint32_t kStateVersion = 1;
  static constexpr std::uint32_t kEffectKey =
      (Tangential ? 8u : 0u) | (Rotation ? 4u : 0u) | (Walls ? 2u : 0u) | NormalLaw::checkpoint_key;

  void save_state(std::ostream& out) const override {
    checkpoint::Writer w(out);
    w.section("DEM ", kStateVersion);
    w.u32(kEffectKey);
    w.boolean(normal_contact_);
    // Decomposed: the whole set of the last collect(), as one process writes it.
    if (!whole_current_)
      throw std::logic_error("DemEngine::save_state on several ranks: collect() the grains of this step first");
    const Particles& p = exchange_ ? whole_ : p_;
    w.u64(p.size());
    w.f64(dt_);
    w.f64(time_);
    w.f64(skin_);
    w.u64(steps_);
    w.u64(exchange_ ? whole_diagnostics_.particles_removed : removed_);
    w.boolean(frozen_);
    w.boolean(forces_stale_);
    for (const auto* v : saved_arrays(p)) w.doubles(*v);
    w.indices(p.id);
    w.doubles(exchange_ ? body_factors(p, buoyancy_density_) : body_factor_);
    if constexpr (Tangential) {
      if (exchange_) {
        write_whole_slip_history(w);
        return;
      }
      w.u64(wall_slip_.size());
      for (const Vec3& s : wall_slip_) w.vec3(s);
      // Pair slips: only entries whose bits are not all +0 (a pair out of
      // contact holds +0; one in contact is in every valid list), in list
      // order, i.e. ascending (i, j): the same bytes whatever list the
      // writer had, so load-then-save reproduces the file.
      const std::size_t n = p_.size();
      const bool have_list = list_.offsets().size() == n + 1 && slip_.size() == list_.entries();
      std::vector<std::size_t> live;
      if (have_list)
        for (std::size_t k = 0; k < slip_.size(); ++k)
          if (!all_positive_zero(slip_[k])) live.push_back(k);
      w.u64(live.size());
      std::size_t i = 0;
      for (std::size_t k : live) {
        while (static_cast<std::size_t>(list_.offsets()[i + 1]) <= k) ++i;
        w.u64(i);
        w.u64(static_cast<std::uint64_t>(list_.indices()[k]));
        w.vec3(slip_[k]);
      }
    }
  }

  // save_state decomposed (a collective): the owned grains' wall slips and
  // live pair slips of every rank, as one process writes them for the whole
  // set of the last collect() (ascending id): walls per grain, pairs in
  // ascending (i, j) of whole-set indices.
  void write_whole_slip_history(checkpoint::Writer& w) const {
    const std::size_t n = p_.size();
    std::vector<std::vector<double>> walls;
    for (std::size_t k = 0; k < kWalls; ++k)
      for (int c = 0; c < 3; ++c) {
        std::vector<double> v(n);
        for (std::size_t i = 0; i < n; ++i) v[i] = wall_slip_[kWalls * i + k][c];
        walls.push_back(std::move(v));
      }
    const std::vector<std::vector<double>> whole_walls = exchange_->gather_owned_arrays(p_, walls);
    const std::size_t m = whole_.size();
    w.u64(kWalls * m);
    for (std::size_t i = 0; i < m; ++i)
      for (std::size_t k = 0; k < kWalls; ++k)
        w.vec3(Vec3(whole_walls[3 * k][i], whole_walls[3 * k + 1][i], whole_walls[3 * k + 2][i]));
    const std::span<const std::uint8_t> ghost = exchange_->ghost_mask();
    std::vector<double> mine;
    if (list_.offsets().size() == n + 1 && slip_.size() == list_.entries())
      for (std::size_t i = 0; i < n; ++i) {
        if (i < ghost.size() && ghost[i] != 0) continue;
        for (Index k = list_.offsets()[i]; k < list_.offsets()[i + 1]; ++k) {
          const Vec3& s = slip_[static_cast<std::size_t>(k)];
          if (all_positive_zero(s)) continue;
          const auto j = static_cast<std::size_t>(list_.indices()[static_cast<std::size_t>(k)]);
          mine.insert(mine.end(), {static_cast<double>(p_.id[i]), static_cast<double>(p_.id[j]), s.x(), s.y(), s.z()});
        }
      }
    const std::vector<double> all = exchange_->gather_records(mine);
    const auto whole_index = [&](double id) {
      const auto at = std::lower_bound(whole_.id.begin(), whole_.id.end(), static_cast<Index>(id));
      return static_cast<std::uint64_t>(at - whole_.id.begin());
    };
    std::vector<std::pair<std::array<std::uint64_t, 2>, Vec3>> pairs;
    for (std::size_t r = 0; r + kSlipRecord <= all.size(); r += kSlipRecord)
      pairs.push_back({{whole_index(all[r]), whole_index(all[r + 1])}, Vec3(all[r + 2], all[r + 3], all[r + 4])});
    std::sort(pairs.begin(), pairs.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    w.u64(pairs.size());
    for (const auto& [pair, slip] : pairs) {
      w.u64(pair[0]);
      w.u64(pair[1]);
      w.vec3(slip);
    }
  }

  void load_state(std::istream& in) override {
    checkpoint::Reader r(in);
    r.section("DEM ", kStateVersion);
    const std::uint32_t key = r.u32("the DEM effect set");
    const bool normal_contact = r.boolean("the DEM normal-contact flag");
    if (key != kEffectKey || normal_contact != normal_contact_)
      throw SolverError(fmt::format("checkpoint: DEM effects differ (tangential/rotation/walls/restitution key {} "
                                    "normal contact {} in the file, {} and {} in this run)",
                                    key, normal_contact, kEffectKey, normal_contact_));
    const std::uint64_t count = r.u64("the particle count");
    const std::size_t started_with = exchange_ ? decomposed_from_ : p_.size();
    if (count > started_with)
      throw SolverError(fmt::format("checkpoint: {} particles, this run started with {} (another scene?)", count,
                                    started_with));
    const auto n = static_cast<std::size_t>(count);
    const double dt = r.f64("the DEM step");
    if (dt != dt_)
      throw SolverError(fmt::format("checkpoint: DEM step {:.17g} s, this run {:.17g} s", dt, dt_));
    const double time = r.f64("the DEM time"), skin = r.f64("the Verlet skin");
    if (!(skin > 0.0)) throw SolverError(fmt::format("checkpoint: Verlet skin {} (corrupt)", skin));
    const std::uint64_t steps = r.u64("the DEM step count"), removed = r.u64("the removed-particle count");
    const bool frozen = r.boolean("the frozen flag"), forces_stale = r.boolean("the stale-force flag");
    Particles p;
    for (auto* v : saved_arrays(p)) {
      const std::vector<double> values = r.doubles("a particle array", n);
      v->assign(values.begin(), values.end());
    }
    p.id = r.indices("the particle ids", n);
    std::vector<double> body_factor = r.doubles_exactly("the body force factors", n);
    // Every array holds one value per particle, or none where the effect is
    // off (rotation arrays); the ones every step reads must be full.
    for (const auto* v : saved_arrays(p))
      if (!v->empty() && v->size() != n)
        throw SolverError(fmt::format("checkpoint: a particle array has {} values for {} particles", v->size(), n));
    for (const auto* v : {&p.x, &p.y, &p.z, &p.vx, &p.vy, &p.vz, &p.fx, &p.fy, &p.fz, &p.diameter, &p.mass})
      if (v->size() != n) throw SolverError("checkpoint: a particle array is missing (corrupt)");
    if (p.id.size() != n) throw SolverError("checkpoint: particle ids missing (corrupt)");
    if constexpr (Rotation)
      for (const auto* v : {&p.wx, &p.wy, &p.wz, &p.tx, &p.ty, &p.tz, &p.inertia})
        if (v->size() != n) throw SolverError("checkpoint: rotation arrays missing although rotation is on");
    std::vector<Vec3> wall_slip;
    std::vector<std::pair<std::array<std::size_t, 2>, Vec3>> pair_slip;
    if constexpr (Tangential) {
      const std::uint64_t walls = r.u64("the wall slip count");
      if (walls != static_cast<std::uint64_t>(kWalls) * count) throw SolverError("checkpoint: wall slip history does not match the particles");
      wall_slip.resize(static_cast<std::size_t>(kWalls) * n);
      for (Vec3& s : wall_slip) s = r.vec3("the wall slip history");
      const std::uint64_t pairs = r.u64("the pair slip count");
      if (n > 0 && pairs > count * (count - 1)) throw SolverError("checkpoint: pair slip count (corrupt)");
      for (std::uint64_t k = 0; k < pairs; ++k) {
        const std::uint64_t i = r.u64("a slip pair"), j = r.u64("a slip pair");
        if (i >= count || j >= count || i == j) throw SolverError("checkpoint: slip pair out of range (corrupt)");
        pair_slip.push_back({{static_cast<std::size_t>(i), static_cast<std::size_t>(j)}, r.vec3("a pair slip")});
      }
    }
    // All read and checked: commit, then rebuild the neighbour list at the
    // loaded positions and put each live slip on its pair's new entry.
    NeighbourList list;
    std::vector<Vec3> slip;
    if (normal_contact_) {
      list.build(p, skin);
      if constexpr (Tangential) {
        slip.assign(list.entries(), Vec3::Zero());
        for (const auto& [pair, value] : pair_slip) {
          const auto row = list.neighbours(pair[0]);
          const auto it = std::lower_bound(row.begin(), row.end(), static_cast<Index>(pair[1]));
          if (it == row.end() || *it != static_cast<Index>(pair[1]))
            throw SolverError(fmt::format("checkpoint: particles {} and {} carry a slip history but are not "
                                          "neighbours at the saved positions (corrupt)", pair[0], pair[1]));
          slip[static_cast<std::size_t>(list.offsets()[pair[0]] + (it - row.begin()))] = value;
        }
      }
    }
    p_ = std::move(p);
    body_factor_.assign(body_factor.begin(), body_factor.end());
    time_ = time;
    skin_ = skin;
    steps_ = static_cast<std::size_t>(steps);
    removed_ = static_cast<std::size_t>(removed);
    frozen_ = frozen;
    forces_stale_ = forces_stale;
    list_ = std::move(list);
    old_to_new_base_.clear();
    if constexpr (Tangential) {
      slip_ = std::move(slip);
      wall_slip_ = std::move(wall_slip);
    }
    pending_kick_ = false;  // the file holds v^{n+1} (save_state settles first)
    near_.invalidate();
    near_walls_.invalidate();
    refresh_factors();
    if (exchange_) {  // every rank loaded the whole set: its share, ghosts and list at the loaded positions
      exchange_->forget_distribution();
      rebuild_list(true);
      collect();
    }
  }

 private:
  // The particle arrays a checkpoint holds, in file order (id apart: Index).
  template <class P>
  static std::array<decltype(&std::declval<P&>().x), 18> saved_arrays(P& p) {
    return {&p.x, &p.y, &p.z, &p.vx, &p.vy, &p.vz, &p.fx, &p.fy, &p.fz, &p.diameter, &p.mass,
            &p.wx, &p.wy, &p.wz, &p.tx, &p.ty, &p.tz, &p.inertia};
  }
  static bool all_positive_zero(const Vec3& v) {
    return std::bit_cast<std::uint64_t>(v.x()) == 0 && std::bit_cast<std::uint64_t>(v.y()) == 0 &&
           std::bit_cast<std::uint64_t>(v.z()) == 0;
  }

  std::vector<Vec3> slip_;        // per neighbour-list entry (Tangential only)
  std::vector<double> routed_slips_;  // decomposed: the slip records this rank holds during a rebuild
  std::vector<Vec3> wall_slip_;   // per particle and wall (Tangential only)
  std::vector<Index> old_to_new_base_;  // after a removal: new index -> old index
  GrainArray no_reference_;             // zeros, when there is no neighbour list
  std::vector<std::uint8_t> wall_touch_;  // pass 3 of compute_forces: particle touches a wall
  GrainArray kick_factor_;                // dt/2 / m
  GrainArray body_mass_;                  // m (1 - rho_f V / m), Eq. 4-5
  // half_pair_forces (no tangential contact): the pairs that can touch
  // (near_pairs.hpp), and the displacement bound B since the list build
  // (infinite: unknown) that keeps their set.
  NearPairs near_;
  double displacement_bound_ = std::numeric_limits<double>::infinity();
  // What the pair pass's split and crossing pairs were made for: the pair
  // arrays (the half index's or the near set's) and their contents'
  // generation.
  struct SplitKey {
    const Index* pairs = nullptr;
    std::size_t generation = 0;
    std::ptrdiff_t threads = 0;
    bool operator==(const SplitKey&) const = default;
  };
  SplitKey split_key_;
  PairShares shares_;                           // the threaded pair pass's split (pair_shares.hpp)
  std::vector<PairShareScratch> pair_scratch_;  // one a thread
  NearWallGrains near_walls_;  // wall_scan: the grains near a face, from their candidates
  bool near_wall_list_ = false;  // this step's wall mask is near_walls_.grains() (not wall_touch_)
  bool walls_in_pair_pass_ = false;  // compute_forces_after: a threaded half_pair_forces applies the near grains' walls
  bool walls_applied_ = false;       // half_pair_forces did (it ran threaded)
};

template <bool T, bool R, bool W, class Law>
std::unique_ptr<DemEngine::Kernel> make(Particles&& p, const Scene& s) {
  auto k = std::make_unique<KernelFor<T, R, W, Law>>(std::move(p), s);
  k->init_storage();
  return k;
}

// The supported effect combinations for one normal law's kernel form.
template <class Law>
std::unique_ptr<DemEngine::Kernel> make_for_law(Particles&& p, const Scene& s) {
  const Effects& e = s.effects;
  const bool t = e.tangential_contact && e.normal_contact, r = e.rotation, w = e.walls;
  switch ((t ? 4 : 0) | (r ? 2 : 0) | (w ? 1 : 0)) {
    case 0: return make<false, false, false, Law>(std::move(p), s);
    case 1: return make<false, false, true, Law>(std::move(p), s);
    case 2: return make<false, true, false, Law>(std::move(p), s);
    case 3: return make<false, true, true, Law>(std::move(p), s);
    case 4: return make<true, false, false, Law>(std::move(p), s);
    case 5: return make<true, false, true, Law>(std::move(p), s);
    case 6: return make<true, true, false, Law>(std::move(p), s);
    default: return make<true, true, true, Law>(std::move(p), s);
  }
}

// The one table of kernels, dispatched once: the scene's contact law
// (contact_laws/contact_law_table.cpp) in its kernel form, then the effects.
std::unique_ptr<DemEngine::Kernel> make_kernel(Particles&& p, const Scene& s) {
  switch (s.contact.law) {
    case ContactLawKind::linear_spring_dashpot:
      if (s.contact.restitution) return make_for_law<LinearSpringDashpotForce<true>>(std::move(p), s);
      return make_for_law<LinearSpringDashpotForce<false>>(std::move(p), s);
  }
  throw std::logic_error("DemEngine: a contact law without a kernel");  // -Wswitch names a law without a case
}

}  // namespace

DemEngine::DemEngine(Particles particles, const Scene& scene) : kernel_(make_kernel(std::move(particles), scene)) {}
DemEngine::~DemEngine() = default;
DemEngine::DemEngine(DemEngine&&) noexcept = default;
DemEngine& DemEngine::operator=(DemEngine&&) noexcept = default;

void DemEngine::step() { kernel_->step(); }
void DemEngine::run(std::size_t steps) {
  for (std::size_t s = 0; s < steps; ++s) kernel_->step();
}
void DemEngine::run_sorting(std::size_t steps) {
  for (std::size_t s = 0; s < steps; ++s) {
    kernel_->step();
    if (sort_due(kernel_->steps_ - 1)) kernel_->sort_grains();
  }
}
double DemEngine::time() const { return kernel_->time_; }
double DemEngine::dem_step() const { return kernel_->dt_; }
Particles& DemEngine::particles() {
  kernel_->settle();
  return kernel_->p_;
}
const Particles& DemEngine::particles() const {
  kernel_->settle();
  return kernel_->p_;
}
void DemEngine::particles_moved() { kernel_->forces_stale_ = true; }
void DemEngine::set_external_force(ExternalForce* force) {
  kernel_->external_ = force;
  kernel_->forces_stale_ = true;
}
void DemEngine::set_frozen(bool frozen) {
  if (kernel_->frozen_ && !frozen) kernel_->forces_stale_ = true;
  kernel_->frozen_ = frozen;
}
bool DemEngine::frozen() const { return kernel_->frozen_; }
void DemEngine::save_state(std::ostream& out) const {
  kernel_->settle();
  kernel_->save_state(out);
}
void DemEngine::load_state(std::istream& in) { kernel_->load_state(in); }
DemDiagnostics DemEngine::diagnostics() const {
  kernel_->settle();
  return kernel_->diagnostics();
}
void DemEngine::decompose(std::unique_ptr<GrainExchange> exchange, bool owners_stay_in_slabs) {
  kernel_->decompose(std::move(exchange), owners_stay_in_slabs);
}
const GrainExchange* DemEngine::exchange() const { return kernel_->exchange_.get(); }
void DemEngine::collect() { kernel_->collect(); }
void DemEngine::collect_diagnostics() { kernel_->collect_diagnostics(); }
bool DemEngine::whole_particles_current() const { return kernel_->whole_current_; }
const Particles& DemEngine::whole_particles() const {
  kernel_->settle();
  return kernel_->exchange_ ? kernel_->whole_ : kernel_->p_;
}
std::size_t DemEngine::steps() const { return kernel_->steps_; }
void DemEngine::set_grain_sort_policy(GrainSortPolicy policy) { kernel_->sort_policy_ = policy; }
DemEngine::GrainSortPolicy DemEngine::grain_sort_policy() const { return kernel_->sort_policy_; }
bool DemEngine::sort_due(std::size_t steps_before) const {
  const GrainSortPolicy& policy = kernel_->sort_policy_;
  // Decomposed over MPI ranks the exchange keys its ghosts on the rank's
  // indices, and migration reorders the grains at every list build anyway.
  return policy.interval > 0 && !kernel_->exchange_ && kernel_->p_.size() >= policy.min_particles &&
         kernel_->steps_ / policy.interval != steps_before / policy.interval;
}
std::span<const Index> DemEngine::sort_in_cell_order() {
  kernel_->sort_grains();
  return kernel_->order_;
}
void DemEngine::set_skin(double skin_m) {
  if (!(skin_m > 0.0)) throw std::invalid_argument("DemEngine::set_skin: skin must be positive");
  kernel_->skin_ = skin_m;
  kernel_->forces_stale_ = true;
}

}  // namespace fdem
