#include "parallel/element_sums.hpp"

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <stdexcept>

#include "core/error.hpp"

namespace fdem {

namespace {
MPI_Comm communicator(int handle) { return MPI_Comm_f2c(handle); }
}  // namespace

ElementSums::ElementSums(const MeshCells& mesh, std::vector<std::pair<Index, Index>> fluid_nodes,
                         const GrainExchange& grains)
    : mesh_(mesh), grains_(&grains), comm_("ElementSums") {
  const int n = grains.ranks();
  if (static_cast<int>(fluid_nodes.size()) != n)
    throw std::invalid_argument(fmt::format("ElementSums: {} fluid node ranges for {} ranks", fluid_nodes.size(), n));
  const Index per_level = mesh.nodes_per_level();
  const Index nodes = mesh.nodes();
  const Index per_layer = mesh.elements_per_layer();
  Index expected = 0;
  for (const auto& [first, end] : fluid_nodes) {
    if (first != expected || end < first)
      throw std::invalid_argument("ElementSums: the fluid node ranges do not cover the nodes once, in order");
    expected = end;
  }
  if (expected != nodes) throw std::invalid_argument("ElementSums: the fluid node ranges do not cover the mesh");
  const auto ceil_div = [](Index a, Index b) { return (a + b - 1) / b; };
  for (int r = 0; r < n; ++r) {
    const auto [first, end] = fluid_nodes[static_cast<std::size_t>(r)];
    Interval f;
    if (end > first) {
      // Rows at node levels l0..l1 assemble layers l0-1..l1; their nodal
      // averages take in one layer more on each side.
      const auto l0 = static_cast<int>(first / per_level), l1 = static_cast<int>((end - 1) / per_level);
      f.first = std::max(0, l0 - 2);
      f.last = std::min(mesh.cells[2] - 1, l1 + 1);
    }
    fluid_layers_.push_back(f);
    if (r == grains.rank()) {
      // Layer k is owned by the rank holding its first node k * per_level.
      const Index k0 = std::min<Index>(ceil_div(first, per_level), mesh.cells[2]);
      const Index k1 = std::min<Index>(ceil_div(end, per_level), mesh.cells[2]);
      owned_elements_ = {k0 * per_layer, std::max(k0, k1) * per_layer};
      owned_nodes_ = {first, end};
    }
  }
  marked_.assign(static_cast<std::size_t>(std::max(mesh.elements(), mesh.nodes())), 0);
}

ElementSums::~ElementSums() = default;

int ElementSums::along_axis(Index cell) const {
  const Index nx = mesh_.cells[0], ny = mesh_.cells[1];
  switch (grains_->slabs().axis()) {
    case 0: return static_cast<int>(cell % nx);
    case 1: return static_cast<int>((cell / nx) % ny);
    default: return static_cast<int>(cell / (nx * ny));
  }
}

ElementSums::Interval ElementSums::band(int first_rank, int last_rank, double pad_m, int pad_cells) const {
  const SlabPartition& slabs = grains_->slabs();
  const int axis = slabs.axis();
  const int cells = mesh_.cells[static_cast<std::size_t>(axis)];
  const double lower = mesh_.lower[axis], h = mesh_.cell_size[axis];
  const auto cell_of = [&](double c) {
    const double at = std::floor((c - lower) / h);
    return static_cast<int>(std::clamp(at, -1.0e9, 1.0e9));
  };
  Interval out;
  // The end slabs hold every point beyond the box too.
  out.first = first_rank == 0 ? 0 : std::max(0, cell_of(slabs.slab_lower(first_rank) - pad_m) - pad_cells);
  out.last = last_rank + 1 == slabs.ranks()
                 ? cells - 1
                 : std::min(cells - 1, cell_of(slabs.slab_upper(last_rank) + pad_m) + pad_cells);
  return out;
}

ElementSums::Interval ElementSums::contribution(int rank) const { return band(rank, rank, grains_->cutoff(), 1); }
ElementSums::Interval ElementSums::reading(int rank) const {
  // The neighbours' slabs too: a rebalance in the middle of a fluid step
  // may move this rank's faces up to a cutoff short of its neighbours' far
  // faces, and a grain that then arrives reads the porosity of the step's
  // start if the drag maps the grains again (grains lost mid-step).
  return band(std::max(0, rank - 1), std::min(ranks() - 1, rank + 1), 2.0 * grains_->cutoff(), 2);
}

ElementSums::Interval ElementSums::cells_along(Index item, Items kind) const {
  if (kind == Items::elements) {
    const int c = along_axis(item / 5);
    return {c, c};
  }
  // A node at index a along the axis is a corner of the cells a - 1 and a.
  const Index nx = mesh_.cells[0] + 1, ny = mesh_.cells[1] + 1;
  int a = 0;
  switch (grains_->slabs().axis()) {
    case 0: a = static_cast<int>(item % nx); break;
    case 1: a = static_cast<int>((item / nx) % ny); break;
    default: a = static_cast<int>(item / (nx * ny)); break;
  }
  return {a - 1, a};
}

ElementSums::Interval ElementSums::layers_of(Index item, Items kind) const {
  if (kind == Items::elements) {
    const int k = layer(item / 5);
    return {k, k};
  }
  const auto k = static_cast<int>(item / mesh_.nodes_per_level());  // the layers below and above its level
  return {k - 1, k};
}

bool ElementSums::needs(const Interval& reading_band, const Interval& fluid, Index item, Items kind) const {
  if (kind == Items::nodes_everywhere) return true;
  return reading_band.meets(cells_along(item, kind)) || fluid.meets(layers_of(item, kind));
}

bool ElementSums::needs_element(Index e) const {
  return needs(reading(rank()), fluid_layers_[static_cast<std::size_t>(rank())], e, Items::elements);
}

bool ElementSums::needs_node(Index n) const {
  return needs(reading(rank()), fluid_layers_[static_cast<std::size_t>(rank())], n, Items::nodes);
}

bool ElementSums::linked(int from, int to, Items kind) const {
  if (kind == Items::nodes_everywhere) return true;
  Interval c = contribution(from);
  if (kind == Items::nodes && c.first <= c.last) {  // the corners of the band's cells: a cell more each side
    --c.first;
    ++c.last;
  }
  if (c.meets(reading(to))) return true;
  const Interval& f = fluid_layers_[static_cast<std::size_t>(to)];
  if (f.last < f.first || c.last < c.first) return false;
  // Cut along z both are layer intervals; along x or y the band crosses every layer.
  return grains_->slabs().axis() == 2 ? c.meets(f) : true;
}

void ElementSums::sum_over_ranks(std::span<const Field> fields, std::span<const Index> touched) const {
  complete(fields, touched, Items::elements);
}

void ElementSums::sum_nodes_over_ranks(std::span<const Field> fields, std::span<const Index> touched,
                                       bool everywhere) const {
  complete(fields, touched, everywhere ? Items::nodes_everywhere : Items::nodes);
}

void ElementSums::complete(std::span<const Field> fields, std::span<const Index> touched, Items kind) const {
  const Index elements = kind == Items::elements ? mesh_.elements() : mesh_.nodes();  // the items
  std::size_t record = 1;  // the item, then every field's components
  for (const Field& f : fields) {
    if (f.components < 1 || f.values.size() != static_cast<std::size_t>(elements) * static_cast<std::size_t>(f.components))
      throw std::invalid_argument(fmt::format("ElementSums: a field of {} values for {} items x {}",
                                              f.values.size(), elements, f.components));
    record += static_cast<std::size_t>(f.components);
  }
  ++exchanges_;
  // 0. The touched elements, each once, ascending (the records' order).
  touched_.clear();
  for (const Index e : touched) {
    if (e < 0) continue;  // a grain outside the mesh
    if (e >= elements) throw std::invalid_argument(fmt::format("ElementSums: touched item {} of {}", e, elements));
    std::uint8_t& mark = marked_[static_cast<std::size_t>(e)];
    if (mark != 0) continue;
    mark = 1;
    touched_.push_back(e);
  }
  for (const Index e : touched_) marked_[static_cast<std::size_t>(e)] = 0;
  std::sort(touched_.begin(), touched_.end());
  const auto at = [](const Field& f, Index e, int c) -> double& {
    return f.values[static_cast<std::size_t>(e) * static_cast<std::size_t>(f.components) + static_cast<std::size_t>(c)];
  };

  const int me = rank(), n = ranks();
  std::vector<int> send_to, receive_from;
  for (int s = 0; s < n; ++s) {
    if (s == me) continue;
    if (linked(me, s, kind)) send_to.push_back(s);
    if (linked(s, me, kind)) receive_from.push_back(s);
  }
  // 1. This rank's non-zero partial sums, to every linked rank that needs
  // them; set aside (`own`, a record per touched element) and cleared.
  const Interval mine = contribution(me);
  std::vector<Interval> their_reading;
  for (int s : send_to) their_reading.push_back(reading(s));
  std::vector<std::vector<double>> out(send_to.size());
  std::vector<double> own;
  own.reserve(touched_.size() * (record - 1));
  for (const Index e : touched_) {
    bool any = false;
    const std::size_t first = own.size();
    for (const Field& f : fields)
      for (int c = 0; c < f.components; ++c) {
        double& x = at(f, e, c);
        own.push_back(x);
        any = any || x != 0.0;
        x = 0.0;
      }
    if (!any) continue;
    if (!mine.meets(cells_along(e, kind)))
      throw SolverError(fmt::format("coupling on {} MPI ranks: rank {} summed grains into {} {}, outside its "
                                    "band of cells {}..{} along the cut (a grain far outside its slab)",
                                    n, me, kind == Items::elements ? "element" : "node", e, mine.first, mine.last));
    for (std::size_t k = 0; k < send_to.size(); ++k) {
      if (!needs(their_reading[k], fluid_layers_[static_cast<std::size_t>(send_to[k])], e, kind)) continue;
      out[k].push_back(static_cast<double>(e));  // exact: element indices are below 2^53
      out[k].insert(out[k].end(), own.begin() + static_cast<std::ptrdiff_t>(first), own.end());
    }
  }
  MPI_Comm comm = communicator(comm_.handle());
  std::vector<long long> send_count(send_to.size()), receive_count(receive_from.size(), 0);
  std::vector<MPI_Request> requests(2 * (send_to.size() + receive_from.size()));
  std::size_t q = 0;
  for (std::size_t k = 0; k < receive_from.size(); ++k)
    MPI_Irecv(&receive_count[k], 1, MPI_LONG_LONG, receive_from[k], 50, comm, &requests[q++]);
  for (std::size_t k = 0; k < send_to.size(); ++k) {
    send_count[k] = static_cast<long long>(out[k].size());
    MPI_Isend(&send_count[k], 1, MPI_LONG_LONG, send_to[k], 50, comm, &requests[q++]);
  }
  MPI_Waitall(static_cast<int>(q), requests.data(), MPI_STATUSES_IGNORE);
  std::vector<std::vector<double>> in(receive_from.size());
  q = 0;
  for (std::size_t k = 0; k < receive_from.size(); ++k) {
    in[k].resize(static_cast<std::size_t>(receive_count[k]));
    MPI_Irecv(in[k].data(), static_cast<int>(receive_count[k]), MPI_DOUBLE, receive_from[k], 51, comm, &requests[q++]);
  }
  for (std::size_t k = 0; k < send_to.size(); ++k) {
    MPI_Isend(out[k].data(), static_cast<int>(out[k].size()), MPI_DOUBLE, send_to[k], 51, comm, &requests[q++]);
    bytes_sent_ += sizeof(double) * out[k].size();
  }
  MPI_Waitall(static_cast<int>(q), requests.data(), MPI_STATUSES_IGNORE);

  // 2. The complete sums, ranks in ascending order from +0 (the fields are
  // 0 now wherever a rank's record or this rank's own sums land): this
  // rank's own where it needs them, the others' records as they come.
  const auto add_record = [&](Index e, const double* values) {
    for (const Field& f : fields)
      for (int c = 0; c < f.components; ++c) at(f, e, c) += *values++;
  };
  const Interval my_reading = reading(me), my_fluid = fluid_layers_[static_cast<std::size_t>(me)];
  const auto add_own = [&] {
    for (std::size_t k = 0; k < touched_.size(); ++k)
      if (needs(my_reading, my_fluid, touched_[k], kind)) add_record(touched_[k], own.data() + k * (record - 1));
  };
  std::size_t next = 0;  // receive_from is ascending
  for (int r = 0; r < n; ++r) {
    if (r == me) {
      add_own();
      continue;
    }
    if (next < receive_from.size() && receive_from[next] == r) {
      const std::vector<double>& records = in[next++];
      if (records.size() % record != 0)
        throw std::logic_error("ElementSums: a neighbour sent a partial record");
      for (std::size_t a = 0; a < records.size(); a += record) {
        const double e = records[a];
        if (!(e >= 0.0 && e < static_cast<double>(elements)))
          throw std::logic_error("ElementSums: a neighbour sent an item outside the mesh");
        add_record(static_cast<Index>(e), records.data() + a + 1);
      }
    }
  }
}

std::vector<double> ElementSums::gather_block(std::span<const double> per_item, int components,
                                              std::pair<Index, Index> mine, Index items) const {
  const auto width = static_cast<std::size_t>(components);
  if (components < 1 || per_item.size() != static_cast<std::size_t>(items) * width)
    throw std::invalid_argument("ElementSums: a gathered field of the wrong size");
  MPI_Comm comm = communicator(comm_.handle());
  const int count = static_cast<int>(static_cast<std::size_t>(mine.second - mine.first) * width);
  std::vector<int> counts(static_cast<std::size_t>(ranks())), offsets(static_cast<std::size_t>(ranks()), 0);
  MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm);
  std::vector<double> whole;
  if (rank() == 0) {
    for (std::size_t r = 1; r < counts.size(); ++r) offsets[r] = offsets[r - 1] + counts[r - 1];
    whole.resize(static_cast<std::size_t>(offsets.back() + counts.back()));
    if (whole.size() != per_item.size()) throw std::logic_error("ElementSums: the owned blocks do not tile the mesh");
  }
  MPI_Gatherv(per_item.data() + static_cast<std::size_t>(mine.first) * width, count, MPI_DOUBLE, whole.data(),
              counts.data(), offsets.data(), MPI_DOUBLE, 0, comm);
  return whole;
}

std::vector<double> ElementSums::gather_elements(std::span<const double> per_item, int components) const {
  return gather_block(per_item, components, owned_elements_, mesh_.elements());
}

std::vector<double> ElementSums::gather_nodes(std::span<const double> per_item, int components) const {
  return gather_block(per_item, components, owned_nodes_, mesh_.nodes());
}

}  // namespace fdem
