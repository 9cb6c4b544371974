#include "study_io.hpp"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include <fmt/format.h>

#include "io/atomic_file.hpp"

namespace fdem::study {

namespace {

// Splits one CSV record; a field in double quotes may hold commas.
std::vector<std::string> split_record(const std::string& line) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (char c : line) {
    if (c == '"') {
      quoted = !quoted;
    } else if (c == ',' && !quoted) {
      fields.emplace_back();
    } else {
      fields.back() += c;
    }
  }
  return fields;
}

}  // namespace

std::map<std::string, ReferenceRow> read_reference(const std::string& study) {
  const std::string path = std::string(FDEM_SOURCE_DIR) + "/reference_data/" + study + ".csv";
  std::ifstream in(path);
  if (!in) throw std::runtime_error(fmt::format("{}: cannot open", path));
  std::map<std::string, ReferenceRow> rows;
  std::vector<std::string> header;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (line.empty() || line[0] == '#') continue;
    const std::vector<std::string> f = split_record(line);
    if (header.empty()) {
      header = f;
      continue;
    }
    if (f.size() != header.size())
      throw std::runtime_error(fmt::format("{}:{}: {} fields, header has {}", path, number, f.size(), header.size()));
    std::map<std::string, std::string> cell;
    for (std::size_t i = 0; i < f.size(); ++i) cell[header[i]] = f[i];
    ReferenceRow row;
    row.id = cell["id"];
    try {
      row.value = std::stod(cell["value"]);
      if (!cell["tolerance"].empty()) row.tolerance = std::stod(cell["tolerance"]);
    } catch (const std::exception&) {
      throw std::runtime_error(fmt::format("{}:{}: value or tolerance is not a number", path, number));
    }
    row.tolerance_kind = cell["tolerance_kind"];
    row.gate = cell["gate"] == "yes";
    rows[row.id] = row;
  }
  return rows;
}

const ReferenceRow& reference(const std::map<std::string, ReferenceRow>& rows, const std::string& id) {
  const auto it = rows.find(id);
  if (it == rows.end()) throw std::runtime_error("reference_data: no row " + id);
  return it->second;
}

bool within_tolerance(const ReferenceRow& row, double ours) {
  if (!row.tolerance) return true;
  const double allowed = row.tolerance_kind == "rel" ? *row.tolerance * std::abs(row.value) : *row.tolerance;
  return std::abs(ours - row.value) <= allowed;
}

std::string results_dir(const std::string& study) {
  const char* env = std::getenv("FDEM_RESULTS_DIR");
  const std::string root = (env != nullptr && *env != '\0') ? env : FDEM_RESULTS_DIR;
  return root + "/" + study;
}

void write_numeric_csv(const std::string& path, const std::vector<std::string>& columns,
                       const std::vector<std::vector<double>>& rows, const std::vector<std::string>& comment) {
  std::string out;
  for (const std::string& c : comment) out += "# " + c + "\n";
  out += fmt::format("{}\n", fmt::join(columns, ","));
  for (const auto& r : rows) out += fmt::format("{}\n", fmt::join(r, ","));  // shortest round-trip
  write_file_atomically(path, out);
}

void write_values(const std::string& dir, const std::vector<std::pair<std::string, double>>& values) {
  std::string out = "id,value\n";
  for (const auto& [id, v] : values) out += fmt::format("{},{}\n", id, v);
  write_file_atomically(dir + "/values.csv", out);
}

void write_meta(const std::string& dir, const std::string& study, const std::string& tier, double wall_time_s,
                bool passed) {
  write_file_atomically(dir + "/meta.json",
                        fmt::format("{{\"study\": \"{}\", \"tier\": \"{}\", \"wall_time_s\": {:.3f}, \"passed\": {}}}\n",
                                    study, tier, wall_time_s, passed ? "true" : "false"));
}

void clear_dir(const std::string& dir) {
  namespace fs = std::filesystem;
  if (!fs::is_directory(dir)) return;
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.is_regular_file()) fs::remove(entry.path());
}

}  // namespace fdem::study
