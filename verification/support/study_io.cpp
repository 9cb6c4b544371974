#include "study_io.hpp"

#include <unistd.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>
#include <omp.h>

#include "coupling/checkpoint_format.hpp"
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

// Standard output of a shell command (empty if it failed).
std::string command_output(const std::string& command) {
  std::string out;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr) return out;
  std::array<char, 256> buf{};
  while (std::fgets(buf.data(), static_cast<int>(buf.size()), pipe) != nullptr) out += buf.data();
  if (::pclose(pipe) != 0) return {};
  return out;
}

// A JSON string literal (quotes, backslashes and control characters escaped).
std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      out += fmt::format("\\u{:04x}", static_cast<int>(c));
    } else {
      out += c;
    }
  }
  return out + "\"";
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
    row.row_class = cell["class"];
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
  if (row.tolerance_kind == "at_least") return ours >= row.value - *row.tolerance;
  if (row.tolerance_kind == "at_most") return ours <= row.value + *row.tolerance;
  const double allowed = row.tolerance_kind == "rel" ? *row.tolerance * std::abs(row.value) : *row.tolerance;
  return std::abs(ours - row.value) <= allowed;
}

std::vector<std::string> gate_failures(const std::map<std::string, ReferenceRow>& rows,
                                       const std::vector<std::pair<std::string, double>>& values, int* measured) {
  std::vector<std::string> failures;
  int found = 0;
  for (const auto& [id, value] : values) {
    const auto it = rows.find(id);
    if (it == rows.end() || !it->second.gate || !it->second.tolerance) continue;
    ++found;
    if (!std::isfinite(value) || !within_tolerance(it->second, value))
      failures.push_back(fmt::format("{}: ours {}, reference {} (tolerance {} {})", id, value, it->second.value,
                                     *it->second.tolerance, it->second.tolerance_kind));
  }
  if (measured != nullptr) *measured = found;
  return failures;
}

std::vector<std::pair<std::string, double>> read_values(const std::string& dir) {
  const std::string path = dir + "/values.csv";
  std::ifstream in(path);
  if (!in) throw std::runtime_error(fmt::format("{}: cannot open", path));
  std::vector<std::pair<std::string, double>> values;
  std::string line;
  std::getline(in, line);  // header id,value
  for (int number = 2; std::getline(in, line); ++number) {
    const auto comma = line.find(',');
    if (comma == std::string::npos) throw std::runtime_error(fmt::format("{}:{}: no comma", path, number));
    values.emplace_back(line.substr(0, comma), std::strtod(line.c_str() + comma + 1, nullptr));
  }
  return values;
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

SourceState source_state() {
  SourceState s;
  // A driver that built the binaries itself (scripts/nightly.sh) pins the
  // commit it built, so a commit made while the studies run does not relabel them.
  const char* pinned = std::getenv("FDEM_SOURCE_COMMIT");
  if (pinned != nullptr && std::string(pinned).size() == 40) {
    const char* dirty = std::getenv("FDEM_SOURCE_DIRTY");
    s.commit = pinned;
    s.dirty = dirty != nullptr && std::string(dirty) == "1";
    s.known = true;
    return s;
  }
  const std::string git = fmt::format("git -C '{}' ", FDEM_SOURCE_DIR);
  std::string head = command_output(git + "rev-parse HEAD 2>/dev/null");
  while (!head.empty() && (head.back() == '\n' || head.back() == ' ')) head.pop_back();
  if (head.size() != 40) return s;
  s.commit = head;
  s.known = true;
  // Tracked files only: build output and results are untracked or ignored.
  s.dirty = !command_output(git + "status --porcelain --untracked-files=no 2>/dev/null").empty();
  return s;
}

std::string file_hash(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return {};
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  checkpoint::Hasher h;
  h.bytes(bytes.data(), bytes.size());
  return fmt::format("{:016x}", h.value());
}

void write_meta(const std::string& dir, const std::string& study, const RunRecord& run) {
  const SourceState src = source_state();
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm utc{};
  ::gmtime_r(&now, &utc);
  std::array<char, 32> when{};
  std::strftime(when.data(), when.size(), "%Y-%m-%dT%H:%M:%SZ", &utc);
  std::array<char, 256> host{};
  if (::gethostname(host.data(), host.size() - 1) != 0) host[0] = '\0';
  std::string scene = "null";
  if (!run.scene_file.empty()) {
    const std::string full = run.scene_file.front() == '/' ? run.scene_file
                                                            : std::string(FDEM_SOURCE_DIR) + "/" + run.scene_file;
    scene = fmt::format("{{\"file\": {}, \"fnv1a64\": {}}}", json_string(run.scene_file), json_string(file_hash(full)));
  }
  std::string params = "{";
  for (std::size_t i = 0; i < run.parameters.size(); ++i)
    params += fmt::format("{}{}: {}", i ? ", " : "", json_string(run.parameters[i].first),
                          json_string(run.parameters[i].second));
  params += "}";
  std::string out = fmt::format(
      "{{\"study\": {}, \"tier\": {}, \"wall_time_s\": {:.3f}, \"passed\": {}, \"status\": {},\n"
      " \"finished_utc\": {}, \"commit\": {}, \"dirty\": {}, \"threads\": {}, \"host\": {},\n"
      " \"scene\": {},\n \"parameters\": {}",
      json_string(study), json_string(run.tier), run.wall_time_s, run.passed ? "true" : "false",
      json_string(run.status), json_string(when.data()), json_string(src.commit),
      src.known ? (src.dirty ? "true" : "false") : "null", omp_get_max_threads(), json_string(host.data()), scene,
      params);
  if (!run.extra_json.empty()) out += ",\n " + run.extra_json;
  write_file_atomically(dir + "/meta.json", out + "}\n");
}

void clear_dir(const std::string& dir) {
  namespace fs = std::filesystem;
  if (!fs::is_directory(dir)) return;
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.is_regular_file()) fs::remove(entry.path());
}

}  // namespace fdem::study
