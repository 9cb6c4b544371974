#include "scene/particle_csv.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <optional>
#include <string_view>

#include <fmt/format.h>

#include "core/error.hpp"

namespace fdem {

namespace {

std::vector<std::string_view> split_commas(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    std::string_view field = line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start);
    while (!field.empty() && (field.front() == ' ' || field.front() == '\t')) field.remove_prefix(1);
    while (!field.empty() && (field.back() == ' ' || field.back() == '\t' || field.back() == '\r')) field.remove_suffix(1);
    out.push_back(field);
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return out;
}

std::optional<double> parse_double(std::string_view text) {
  double value = 0.0;
  const auto* end = text.data() + text.size();
  const auto result = std::from_chars(text.data(), end, value);
  if (result.ec != std::errc() || result.ptr != end || !std::isfinite(value)) return std::nullopt;
  return value;
}

// Column slots, in the order ParticleRecord is filled.
enum Column { c_id, c_d, c_rho, c_x, c_y, c_z, c_vx, c_vy, c_vz, column_count };
constexpr std::array<std::string_view, column_count> column_names{"id", "d", "rho", "x", "y", "z", "vx", "vy", "vz"};

}  // namespace

std::vector<ParticleRecord> read_particle_csv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "file", path, "cannot open the particle CSV file");
  std::string line;
  int line_number = 0;
  // Header: find where each column sits.
  std::array<int, column_count> where{};
  where.fill(-1);
  while (std::getline(in, line)) {
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (!line.empty()) break;
  }
  if (line.empty()) throw InputError(path, "header", "", "the particle CSV file is empty", line_number);
  const auto header = split_commas(line);
  for (std::size_t i = 0; i < header.size(); ++i) {
    bool known = false;
    for (std::size_t c = 0; c < column_count; ++c) {
      if (header[i] == column_names[c]) {
        if (where[c] >= 0) throw InputError(path, std::string(header[i]), "", "column appears twice", line_number);
        where[c] = static_cast<int>(i);
        known = true;
      }
    }
    if (!known) {
      throw InputError(path, std::string(header[i]), "", "unknown column (expected id,d,rho,x,y,z[,vx,vy,vz])",
                       line_number);
    }
  }
  for (int c = c_id; c <= c_z; ++c) {
    if (where[static_cast<std::size_t>(c)] < 0) {
      throw InputError(path, std::string(column_names[static_cast<std::size_t>(c)]), "", "required column missing",
                       line_number);
    }
  }

  const int velocity_columns = (where[c_vx] >= 0) + (where[c_vy] >= 0) + (where[c_vz] >= 0);
  if (velocity_columns != 0 && velocity_columns != 3) {
    throw InputError(path, "vx,vy,vz", "", "give all three velocity columns or none", line_number);
  }
  std::vector<ParticleRecord> records;
  while (std::getline(in, line)) {
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    const auto fields = split_commas(line);
    if (fields.size() != header.size()) {
      throw InputError(path, "row", line, fmt::format("row has {} fields, the header {}", fields.size(), header.size()), line_number);
    }
    std::array<double, column_count> value{};
    for (std::size_t c = 0; c < column_count; ++c) {
      if (where[c] < 0) continue;
      const std::string_view field = fields[static_cast<std::size_t>(where[c])];
      const auto parsed = parse_double(field);
      if (!parsed)
        throw InputError(path, std::string(column_names[c]), std::string(field),
                         fmt::format("column {}: not a finite number", where[c] + 1), line_number);
      value[c] = *parsed;
    }
    ParticleRecord r;
    r.diameter = value[c_d];
    r.density = value[c_rho];
    r.position = Vec3(value[c_x], value[c_y], value[c_z]);
    r.velocity = Vec3(value[c_vx], value[c_vy], value[c_vz]);
    r.line = line_number;
    r.has_velocity = velocity_columns == 3;
    if (!(r.diameter > 0.0)) {
      throw InputError(path, "d", std::string(fields[static_cast<std::size_t>(where[c_d])]), "diameter must be > 0", line_number);
    }
    if (!(r.density > 0.0)) {
      throw InputError(path, "rho", std::string(fields[static_cast<std::size_t>(where[c_rho])]), "density must be > 0",
                       line_number);
    }
    records.push_back(r);
  }
  return records;
}

}  // namespace fdem
