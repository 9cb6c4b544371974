// The LIGGGHTS anchors' particle CSV (../shared/anchors/liggghts): one header
// line, then id,d,rho,x,y,z[,vx,vy,vz]; a block without velocity columns
// starts at rest. Shared by bench_dem and dem_steps, which open the file and
// report a missing one in their own way.
#pragma once

#include <istream>
#include <sstream>
#include <string>

#include "core/particles.hpp"

namespace fdem {

inline Particles read_anchor_particles(std::istream& in) {
  Particles p;
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::istringstream row(line);
    double v[9] = {};
    std::string cell;
    for (int c = 0; c < 9 && std::getline(row, cell, ','); ++c) v[c] = std::stod(cell);
    p.add(v[3], v[4], v[5], v[1], v[2], v[6], v[7], v[8]);
  }
  return p;
}

}  // namespace fdem
