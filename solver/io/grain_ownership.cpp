#include "io/grain_ownership.hpp"

namespace fdem {

std::vector<std::size_t> owned_indices(const Particles& particles, const SlabPartition& slabs, int rank) {
  std::vector<std::size_t> owned;
  for (std::size_t i = 0; i < particles.size(); ++i)
    if (slabs.owner(particles.x[i], particles.y[i], particles.z[i]) == rank) owned.push_back(i);
  return owned;
}

namespace {
template <class Array>
void copy_selected(const Array& from, Array& to, std::size_t n, std::span<const std::size_t> indices) {
  if (from.size() != n) return;  // an array this set does not fill (rotation off, no forces yet)
  to.reserve(indices.size());
  for (std::size_t i : indices) to.push_back(from[i]);
}
}  // namespace

Particles particle_subset(const Particles& p, std::span<const std::size_t> indices) {
  const std::size_t n = p.size();
  Particles s;
  for (auto [from, to] : {std::pair{&p.x, &s.x}, {&p.y, &s.y}, {&p.z, &s.z}, {&p.vx, &s.vx}, {&p.vy, &s.vy},
                          {&p.vz, &s.vz}, {&p.fx, &s.fx}, {&p.fy, &s.fy}, {&p.fz, &s.fz}, {&p.diameter, &s.diameter},
                          {&p.mass, &s.mass}, {&p.wx, &s.wx}, {&p.wy, &s.wy}, {&p.wz, &s.wz}, {&p.tx, &s.tx},
                          {&p.ty, &s.ty}, {&p.tz, &s.tz}, {&p.inertia, &s.inertia}})
    copy_selected(*from, *to, n, indices);
  copy_selected(p.id, s.id, n, indices);
  return s;
}

}  // namespace fdem
