#pragma once
// Particle lists from CSV, in the format of the LIGGGHTS anchors
// (/work/shared/anchors/liggghts/gen/*.csv): a header line naming the columns
// id,d,rho,x,y,z and optionally vx,vy,vz (any order), then one particle per
// line, SI units (d [m], rho [kg/m^3], x,y,z [m], vx,vy,vz [m/s]).
#include <string>
#include <vector>

#include "core/types.hpp"

namespace fdem {

struct ParticleRecord {
  double diameter = 0.0;   // [m]
  double density = 0.0;    // [kg/m^3]
  Vec3 position = Vec3::Zero();
  Vec3 velocity = Vec3::Zero();
  bool has_velocity = false;  // the file has vx,vy,vz columns
  int line = 0;            // line in the file, for messages
};

/// Reads every row; a malformed row, a missing column or a non-positive
/// diameter or density throws InputError naming the file, column and line.
std::vector<ParticleRecord> read_particle_csv(const std::string& path);

}  // namespace fdem
