#include "parallel/grain_exchange.hpp"

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <numeric>
#include <stdexcept>

#include "core/error.hpp"

namespace fdem {

namespace {

// The per-grain double arrays of Particles, in record order; rotation's after the base ones.
constexpr std::size_t kBaseFields = 11, kRotationFields = 7;
template <class P>
std::array<decltype(&std::declval<P&>().x), kBaseFields + kRotationFields> fields(P& p) {
  return {&p.x, &p.y, &p.z, &p.vx, &p.vy, &p.vz, &p.fx, &p.fy, &p.fz, &p.diameter, &p.mass,
          &p.wx, &p.wy, &p.wz, &p.tx, &p.ty, &p.tz, &p.inertia};
}

// What a ghost update carries: position and velocity, then angular velocity.
constexpr std::size_t kMotionFields = 6, kSpinFields = 3;
template <class P>
std::array<decltype(&std::declval<P&>().x), kMotionFields + kSpinFields> motion_fields(P& p) {
  return {&p.x, &p.y, &p.z, &p.vx, &p.vy, &p.vz, &p.wx, &p.wy, &p.wz};
}

// Keeps grains `keep` (indices into the old arrays, in the new order) of every array in use and the carried ones.
void select(Particles& p, const std::vector<std::size_t>& keep, std::span<std::vector<double>> carried = {}) {
  const std::size_t n = p.size();
  std::vector<double> scratch(keep.size());
  auto keep_of = [&](auto& v) {
    for (std::size_t k = 0; k < keep.size(); ++k) scratch[k] = v[keep[k]];
    v.assign(scratch.begin(), scratch.end());
  };
  for (auto* v : fields(p))
    if (v->size() == n) keep_of(*v);
  for (std::vector<double>& v : carried) keep_of(v);
  std::vector<Index> ids(keep.size());
  for (std::size_t k = 0; k < keep.size(); ++k) ids[k] = p.id[keep[k]];
  p.id = std::move(ids);
}

MPI_Comm communicator(int handle) { return MPI_Comm_f2c(handle); }
int mpi_neighbour(int rank) { return rank == SlabPartition::kNoRank ? MPI_PROC_NULL : rank; }

}  // namespace

GrainExchange::GrainExchange(const SlabPartition& slabs, bool rotation)
    : slabs_(slabs), rotation_(rotation), comm_("GrainExchange") {
  MPI_Comm comm = communicator(comm_.handle());
  int size = 1;
  MPI_Comm_size(comm, &size);
  MPI_Comm_rank(comm, &rank_);
  if (size != slabs.ranks())
    throw std::invalid_argument(fmt::format("GrainExchange: {} slabs for {} MPI ranks", slabs.ranks(), size));
}

GrainExchange::~GrainExchange() = default;

void GrainExchange::set_cutoff(double cutoff_m) {
  if (!(cutoff_m >= 0.0)) throw std::invalid_argument(fmt::format("GrainExchange: cutoff {} m", cutoff_m));
  for (int r = 0; r < ranks(); ++r)
    if (ranks() > 1 && slabs_.slab_upper(r) - slabs_.slab_lower(r) < cutoff_m)
      throw std::invalid_argument(fmt::format(
          "GrainExchange: slab {} is {:.4g} m thin, less than the ghost cutoff {:.4g} m (largest diameter + "
          "Verlet skin): run on fewer MPI ranks",
          r, slabs_.slab_upper(r) - slabs_.slab_lower(r), cutoff_m));
  cutoff_ = cutoff_m;
}

bool GrainExchange::rebalance(const Particles& p) {
  if (ranks() == 1 || !balancing_) return false;
  const int axis = slabs_.axis();
  const std::span<const double> along = axis == 0 ? std::span<const double>(p.x)
                                        : axis == 1 ? std::span<const double>(p.y)
                                                    : std::span<const double>(p.z);
  // The grains this rank counts: its owned ones, or (before the first
  // redistribute) the whole set, the same on every rank.
  std::vector<double> counted;
  counted.reserve(distributed_ ? owned_count_ : along.size());
  for (std::size_t i = 0; i < along.size(); ++i)
    if (!distributed_ || (i < ghost_.size() && ghost_[i] == 0)) counted.push_back(along[i]);
  const auto over_ranks = [&](std::vector<double>& values) {
    if (distributed_) sum_over_ranks(values);  // counts: integers, exact in any order
  };
  // One message: the histogram, then the load of the present boundaries.
  const std::size_t bins = kBalanceBins, slabs = static_cast<std::size_t>(ranks());
  std::vector<double> sums(bins + slabs, 0.0);
  for (double c : counted) sums[static_cast<std::size_t>(slabs_.bin_of_coordinate(c, kBalanceBins))] += 1.0;
  const std::vector<double> load = slabs_.counts_of(counted);
  std::copy(load.begin(), load.end(), sums.begin() + static_cast<std::ptrdiff_t>(bins));
  over_ranks(sums);
  double total = 0.0, most = 0.0;
  for (std::size_t r = 0; r < slabs; ++r) {
    total += sums[bins + r];
    most = std::max(most, sums[bins + r]);
  }
  const double mean = total / static_cast<double>(slabs), slack = kBalanceTolerance * mean;
  if (!(most > mean + slack)) return false;
  const SlabPartition candidate =
      slabs_.rebalanced(std::span<const double>(sums.data(), bins), cutoff_, distributed_);
  std::vector<double> predicted = candidate.counts_of(counted);
  over_ranks(predicted);
  // Worth the migration only when it takes the tolerance off the largest
  // load (a lone grain, or grains stacked in one bin, cannot be split: stay).
  if (!(*std::max_element(predicted.begin(), predicted.end()) <= most - slack)) return false;
  slabs_ = candidate;
  ++counters_.rebalances;
  return true;
}

std::size_t GrainExchange::record_size(std::size_t carried) const {
  return kBaseFields + (rotation_ ? kRotationFields : 0) + carried + 1;
}

void GrainExchange::pack(const Particles& p, std::span<const std::vector<double>> carried, std::size_t i,
                         std::vector<double>& out) const {
  const auto all = fields(p);
  const std::size_t used = kBaseFields + (rotation_ ? kRotationFields : 0);
  for (std::size_t f = 0; f < used; ++f) out.push_back((*all[f])[i]);
  for (const std::vector<double>& v : carried) out.push_back(v[i]);
  out.push_back(static_cast<double>(p.id[i]));  // exact: ids are 32-bit
}

void GrainExchange::unpack(std::span<const double> in, Particles& p, std::span<std::vector<double>> carried) const {
  const std::size_t size = record_size(carried.size()), used = kBaseFields + (rotation_ ? kRotationFields : 0);
  const auto all = fields(p);
  for (std::size_t r = 0; r + size <= in.size(); r += size) {
    for (std::size_t f = 0; f < used; ++f) all[f]->push_back(in[r + f]);
    for (std::size_t c = 0; c < carried.size(); ++c) carried[c].push_back(in[r + used + c]);
    p.id.push_back(static_cast<Index>(in[r + size - 1]));
  }
}

namespace {
void require_carried_lengths(std::span<const std::vector<double>> carried, std::size_t n) {
  for (const std::vector<double>& v : carried)
    if (v.size() != n)
      throw std::invalid_argument(fmt::format("GrainExchange: a carried array of {} values for {} grains", v.size(), n));
}
}  // namespace

std::array<std::vector<double>, 2> GrainExchange::swap_with_neighbours(const std::array<std::vector<double>, 2>& send,
                                                                      int tag) const {
  MPI_Comm comm = communicator(comm_.handle());
  const int peer[2] = {mpi_neighbour(slabs_.lower_neighbour(rank_)), mpi_neighbour(slabs_.upper_neighbour(rank_))};
  long long send_count[2] = {static_cast<long long>(send[0].size()), static_cast<long long>(send[1].size())};
  long long recv_count[2] = {0, 0};
  MPI_Request requests[4];
  for (int s = 0; s < 2; ++s) {
    MPI_Irecv(&recv_count[s], 1, MPI_LONG_LONG, peer[s], tag, comm, &requests[s]);
    MPI_Isend(&send_count[s], 1, MPI_LONG_LONG, peer[s], tag, comm, &requests[2 + s]);
  }
  MPI_Waitall(4, requests, MPI_STATUSES_IGNORE);
  std::array<std::vector<double>, 2> received;
  for (int s = 0; s < 2; ++s) {
    received[static_cast<std::size_t>(s)].resize(static_cast<std::size_t>(recv_count[s]));
    MPI_Irecv(received[static_cast<std::size_t>(s)].data(), static_cast<int>(recv_count[s]), MPI_DOUBLE, peer[s],
              tag + 1, comm, &requests[s]);
    MPI_Isend(send[static_cast<std::size_t>(s)].data(), static_cast<int>(send_count[s]), MPI_DOUBLE, peer[s],
              tag + 1, comm, &requests[2 + s]);
    if (peer[s] != MPI_PROC_NULL) counters_.bytes_sent += sizeof(double) * send[static_cast<std::size_t>(s)].size();
  }
  MPI_Waitall(4, requests, MPI_STATUSES_IGNORE);
  return received;
}

void GrainExchange::drop_ghosts(Particles& p, std::span<std::vector<double>> carried) {
  const std::size_t n = p.size();
  if (p.id.size() != n) throw std::invalid_argument("GrainExchange: particles without ids");
  require_carried_lengths(carried, n);
  std::vector<std::size_t> keep;
  keep.reserve(n);
  if (!distributed_) {
    // Every rank holds the whole set: keep this slab's share.
    for (std::size_t i = 0; i < n; ++i)
      if (slabs_.owner(p.x[i], p.y[i], p.z[i]) == rank_) keep.push_back(i);
  } else {
    if (ghost_.size() != n)
      throw std::logic_error("GrainExchange::drop_ghosts: the particles changed since the last redistribute");
    for (std::size_t i = 0; i < n; ++i)
      if (ghost_[i] == 0) keep.push_back(i);
  }
  if (keep.size() != n) select(p, keep, carried);
  ghost_.assign(p.size(), 0);
  owned_count_ = p.size();
}

void GrainExchange::migrate_and_gather_ghosts(Particles& p, std::span<std::vector<double>> carried) {
  require_carried_lengths(carried, p.size());
  ++counters_.redistributions;
  // 1. Migration: grains whose centre is now in a neighbour's slab go there.
  std::array<std::vector<double>, 2> leaving;
  std::vector<std::size_t> staying;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const int owner = slabs_.owner(p.x[i], p.y[i], p.z[i]);
    if (owner == rank_) {
      staying.push_back(i);
    } else if (distributed_ && (owner == rank_ - 1 || owner == rank_ + 1)) {
      pack(p, carried, i, leaving[owner < rank_ ? 0 : 1]);
      ++counters_.migrated;
    } else {
      throw SolverError(fmt::format("DEM on {} MPI ranks: particle {} at ({:.4g}, {:.4g}, {:.4g}) m moved from slab {} "
                                    "to slab {} between two neighbour-list rebuilds",
                                    ranks(), p.id[i], p.x[i], p.y[i], p.z[i], rank_, owner));
    }
  }
  distributed_ = true;
  const auto arrived = swap_with_neighbours(leaving, 10);
  if (staying.size() != p.size()) select(p, staying, carried);
  for (const auto& records : arrived) unpack(records, p, carried);
  const std::size_t owned = p.size();

  // 2. Ghosts: owned grains within the cutoff of a face, to the slab across it.
  std::array<std::vector<double>, 2> ghosts_out;
  std::array<std::vector<std::size_t>, 2> sent;
  const int axis = slabs_.axis();
  const double lower_face = slabs_.slab_lower(rank_), upper_face = slabs_.slab_upper(rank_);
  const bool has_lower = slabs_.lower_neighbour(rank_) != SlabPartition::kNoRank;
  const bool has_upper = slabs_.upper_neighbour(rank_) != SlabPartition::kNoRank;
  for (std::size_t i = 0; i < owned; ++i) {
    const double c = axis == 0 ? p.x[i] : axis == 1 ? p.y[i] : p.z[i];
    if (has_lower && c - lower_face < cutoff_) {
      pack(p, carried, i, ghosts_out[0]);
      sent[0].push_back(i);
    }
    if (has_upper && upper_face - c < cutoff_) {
      pack(p, carried, i, ghosts_out[1]);
      sent[1].push_back(i);
    }
  }
  const auto ghosts_in = swap_with_neighbours(ghosts_out, 20);
  std::array<std::vector<std::size_t>, 2> placed;
  for (std::size_t s = 0; s < 2; ++s) {
    const std::size_t first = p.size();
    unpack(ghosts_in[s], p, carried);
    for (std::size_t i = first; i < p.size(); ++i) placed[s].push_back(i);
  }

  // 3. Owned and ghosts together in ascending id.
  const std::size_t n = p.size();
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return p.id[a] < p.id[b]; });
  std::vector<std::size_t> new_index(n);
  for (std::size_t k = 0; k < n; ++k) new_index[order[k]] = k;
  select(p, order, carried);
  ghost_.assign(n, 0);
  for (std::size_t s = 0; s < 2; ++s) {
    sent_index_[s].clear();
    ghost_index_[s].clear();
    for (std::size_t i : sent[s]) sent_index_[s].push_back(new_index[i]);
    for (std::size_t i : placed[s]) {
      ghost_index_[s].push_back(new_index[i]);
      ghost_[new_index[i]] = 1;
    }
  }
  owned_count_ = owned;
}

void GrainExchange::update_ghosts(Particles& p) {
  ++counters_.ghost_updates;
  const std::size_t used = kMotionFields + (rotation_ ? kSpinFields : 0);
  const auto motion = motion_fields(p);
  std::array<std::vector<double>, 2> out;
  for (std::size_t s = 0; s < 2; ++s) {
    out[s].reserve(used * sent_index_[s].size());
    for (std::size_t i : sent_index_[s])
      for (std::size_t f = 0; f < used; ++f) out[s].push_back((*motion[f])[i]);
  }
  const auto in = swap_with_neighbours(out, 30);
  for (std::size_t s = 0; s < 2; ++s) {
    if (in[s].size() != used * ghost_index_[s].size())
      throw std::logic_error("GrainExchange::update_ghosts: a neighbour sent another ghost count");
    for (std::size_t k = 0; k < ghost_index_[s].size(); ++k)
      for (std::size_t f = 0; f < used; ++f) (*motion[f])[ghost_index_[s][k]] = in[s][used * k + f];
  }
}

void GrainExchange::max_over_ranks(std::span<double> values) const {
  if (values.empty()) return;
  MPI_Allreduce(MPI_IN_PLACE, values.data(), static_cast<int>(values.size()), MPI_DOUBLE, MPI_MAX,
                communicator(comm_.handle()));
}

void GrainExchange::sum_over_ranks(std::span<double> values) const {
  if (values.empty()) return;
  MPI_Allreduce(MPI_IN_PLACE, values.data(), static_cast<int>(values.size()), MPI_DOUBLE, MPI_SUM,
                communicator(comm_.handle()));
}

bool GrainExchange::any_rank(bool flag) const {
  int mine = flag ? 1 : 0, any = 0;
  MPI_Allreduce(&mine, &any, 1, MPI_INT, MPI_LOR, communicator(comm_.handle()));
  return any != 0;
}

Particles GrainExchange::gather_owned(const Particles& p) const {
  std::vector<double> mine;
  mine.reserve(record_size(0) * owned_count_);
  for (std::size_t i = 0; i < p.size(); ++i)
    if (i >= ghost_.size() || ghost_[i] == 0) pack(p, {}, i, mine);
  const std::vector<double> all = gather_records(mine);
  Particles out;
  unpack(all, out, {});
  std::vector<std::size_t> order(out.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return out.id[a] < out.id[b]; });
  select(out, order);
  return out;
}

std::vector<std::vector<double>> GrainExchange::gather_owned_arrays(
    const Particles& p, std::span<const std::vector<double>> arrays) const {
  require_carried_lengths(arrays, p.size());
  // Records: the id, then one value per array.
  const std::size_t size = arrays.size() + 1;
  std::vector<double> mine;
  mine.reserve(size * owned_count_);
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (i < ghost_.size() && ghost_[i] != 0) continue;
    mine.push_back(static_cast<double>(p.id[i]));  // exact: ids are 32-bit
    for (const std::vector<double>& v : arrays) mine.push_back(v[i]);
  }
  const std::vector<double> all = gather_records(mine);
  const std::size_t n = all.size() / size;
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return all[size * a] < all[size * b]; });
  std::vector<std::vector<double>> out(arrays.size(), std::vector<double>(n));
  for (std::size_t k = 0; k < n; ++k)
    for (std::size_t c = 0; c < arrays.size(); ++c) out[c][k] = all[size * order[k] + 1 + c];
  return out;
}

std::vector<double> GrainExchange::route_with_grains(const Particles& p, std::span<const std::size_t> grain,
                                                     std::span<const double> records, std::size_t record_size) const {
  if (record_size == 0 || grain.size() * record_size != records.size())
    throw std::invalid_argument("GrainExchange::route_with_grains: one grain per record");
  std::vector<double> kept;
  std::array<std::vector<double>, 2> leaving;
  for (std::size_t r = 0; r < grain.size(); ++r) {
    const std::size_t i = grain[r];
    const int owner = slabs_.owner(p.x[i], p.y[i], p.z[i]);
    const auto record = records.subspan(r * record_size, record_size);
    if (owner == rank_) {
      kept.insert(kept.end(), record.begin(), record.end());
    } else if (distributed_ && (owner == rank_ - 1 || owner == rank_ + 1)) {
      auto& out = leaving[owner < rank_ ? 0 : 1];
      out.insert(out.end(), record.begin(), record.end());
    }  // else: the whole set on every rank (the owner keeps its own), or a grain redistribute refuses
  }
  const auto arrived = swap_with_neighbours(leaving, 40);
  for (const auto& in : arrived) kept.insert(kept.end(), in.begin(), in.end());
  return kept;
}

std::vector<double> GrainExchange::gather_records(std::span<const double> mine) const {
  MPI_Comm comm = communicator(comm_.handle());
  const int count = static_cast<int>(mine.size());
  std::vector<int> counts(static_cast<std::size_t>(ranks())), offsets(static_cast<std::size_t>(ranks()), 0);
  MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, comm);
  for (std::size_t r = 1; r < counts.size(); ++r) offsets[r] = offsets[r - 1] + counts[r - 1];
  std::vector<double> all(static_cast<std::size_t>(offsets.back() + counts.back()));
  MPI_Allgatherv(mine.data(), count, MPI_DOUBLE, all.data(), counts.data(), offsets.data(), MPI_DOUBLE, comm);
  return all;
}

}  // namespace fdem
