#pragma once
// Writes a gtest-based verification study's results for the report
// (reference_data/README.md): $FDEM_RESULTS_DIR/<study>/values.csv (id,value)
// and meta.json (study, tier, wall_time_s, passed).
//
// Tests report a value with RecordProperty("<study>.<quantity>...", value)
// (shortest round-trip text, see study_value()); a gtest Environment reads
// those properties back from every test that ran when the program ends, so no
// test keeps global state. ctest runs each TEST in its own process, possibly
// in parallel, so each process writes only its own part,
// <study>/.parts/<Suite.Test>.csv (passed, wall time, its values), and then,
// under an exclusive lock, merges all parts into values.csv and meta.json:
// passed = every part passed, wall_time_s = the sum. All writes are atomic
// (temporary file, then rename), so the report never reads a half file.
// Series files (restitution.csv, convergence.csv, ...) are collected the same
// way, one row per record_series_row() call.
// Header-only, on top of fdem_study_io (study_io.hpp): used by verification/dem
// and verification/fluid, whose scenes are built in code (no scene file).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "io/atomic_file.hpp"
#include "study_io.hpp"
#include "study_tier.hpp"

namespace fdem::verification {

/// The text RecordProperty stores for a value: shortest round-trip decimals.
inline std::string study_value(double v) { return fmt::format("{}", v); }

/// Records `value` under reference id `id` (which starts with the study name
/// and a dot) for the running test.
inline void record_value(const std::string& id, double value) {
  ::testing::Test::RecordProperty(id, study_value(value));
}

/// Records one row of the series file `file` (a name the report knows, e.g.
/// "restitution.csv") for the running test: `row_key` orders the rows and must
/// be unique within the file, `columns` is the header, `cells` the row's text.
inline void record_series_row(const std::string& study, const std::string& file, const std::string& row_key,
                              const std::vector<std::string>& columns, const std::vector<std::string>& cells) {
  ::testing::Test::RecordProperty(fmt::format("{}|{}|{}|{}", study, file, row_key, fmt::join(columns, ";")),
                                  fmt::format("{}", fmt::join(cells, ",")));
}

/// A study's values of its tier, as its gates read them: each one recorded
/// for the running test under "<study>.<tier>.<quantity>" and kept, in
/// order, for study::gate_failures.
class TierValues {
 public:
  explicit TierValues(std::string study) : study_(std::move(study)) {}
  void add(const std::string& quantity, double value) {
    const std::string id = fmt::format("{}.{}.{}", study_, tier_name, quantity);
    list.emplace_back(id, value);
    record_value(id, value);
  }
  std::vector<std::pair<std::string, double>> list;

 private:
  std::string study_;
};

class StudyResultsWriter : public ::testing::Environment {
 public:
  explicit StudyResultsWriter(std::string study) : study_(std::move(study)) {}

  void TearDown() override {
    namespace fs = std::filesystem;
    const char* env = std::getenv("FDEM_RESULTS_DIR");
    const fs::path dir = fs::path((env != nullptr && *env != '\0') ? env : FDEM_RESULTS_DIR) / study_;
    const fs::path parts = dir / ".parts";
    fs::create_directories(parts);
    const std::string prefix = study_ + ".";
    const ::testing::UnitTest& unit = *::testing::UnitTest::GetInstance();
    for (int s = 0; s < unit.total_test_suite_count(); ++s) {
      const ::testing::TestSuite& suite = *unit.GetTestSuite(s);
      for (int t = 0; t < suite.total_test_count(); ++t) {
        const ::testing::TestInfo& info = *suite.GetTestInfo(t);
        if (!info.should_run()) continue;
        const ::testing::TestResult& r = *info.result();
        std::string part = fmt::format("passed,{}\nwall_time_s,{}\n", r.Failed() ? 0 : 1,
                                       static_cast<double>(r.elapsed_time()) / 1000.0);
        for (int p = 0; p < r.test_property_count(); ++p) {
          const ::testing::TestProperty& prop = r.GetTestProperty(p);
          const std::string key = prop.key();
          if (key.rfind(prefix, 0) == 0 || key.rfind(study_ + "|", 0) == 0)
            part += fmt::format("{},{}\n", key, prop.value());
        }
        std::string name = fmt::format("{}.{}", suite.name(), info.name());
        for (char& c : name)
          if (c == '/') c = '_';  // parameterized names: Suite/Test/0
        write_file_atomically((parts / (name + ".csv")).string(), part);
      }
    }
    merge(dir, parts);
  }

 private:
  // Merges every part into values.csv and meta.json under an exclusive lock
  // (two tests ending at once must not drop each other's rows).
  void merge(const std::filesystem::path& dir, const std::filesystem::path& parts) const {
    namespace fs = std::filesystem;
    const int lock = ::open((parts / "lock").c_str(), O_CREAT | O_RDWR, 0644);
    if (lock >= 0) ::flock(lock, LOCK_EX);
    std::map<std::string, std::string> values;  // sorted ids: a stable file
    struct Series {
      std::string header;
      std::map<std::string, std::string> rows;  // row key -> cells
    };
    std::map<std::string, Series> series;  // file name -> rows
    bool passed = true;
    double wall = 0.0;
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(parts))
      if (e.is_regular_file() && e.path().extension() == ".csv") files.push_back(e.path());
    for (const fs::path& f : files) {
      std::ifstream in(f);
      std::string line;
      while (std::getline(in, line)) {
        const auto comma = line.find(',');
        if (comma == std::string::npos) continue;
        const std::string key = line.substr(0, comma), value = line.substr(comma + 1);
        if (key == "passed")
          passed = passed && value == "1";
        else if (key == "wall_time_s")
          wall += std::stod(value);
        else if (key.find('|') != std::string::npos) {
          // study|file|row_key|col;col;...
          const auto a = key.find('|'), b = key.find('|', a + 1), c = key.find('|', b + 1);
          if (b == std::string::npos || c == std::string::npos) continue;
          Series& file = series[key.substr(a + 1, b - a - 1)];
          file.header = key.substr(c + 1);
          std::replace(file.header.begin(), file.header.end(), ';', ',');
          file.rows[key.substr(b + 1, c - b - 1)] = value;
        } else
          values[key] = value;
      }
    }
    std::string csv = "id,value\n";
    for (const auto& [id, v] : values) csv += fmt::format("{},{}\n", id, v);
    write_file_atomically((dir / "values.csv").string(), csv);
    for (const auto& [name, file] : series) {
      std::string text = file.header + "\n";
      for (const auto& [row_key, cells] : file.rows) text += cells + "\n";
      write_file_atomically((dir / name).string(), text);
    }
    study::RunRecord run;
    run.tier = "fast";
    run.wall_time_s = wall;
    run.passed = passed;
    study::write_meta(dir.string(), study_, run);  // the shared writer: commit, threads, date
    if (lock >= 0) {
      ::flock(lock, LOCK_UN);
      ::close(lock);
    }
  }

  std::string study_;
};

/// Registers the writer for `study`; call once per test executable, at
/// namespace scope: `const auto* const kResults = register_study_results("dem");`.
inline ::testing::Environment* register_study_results(const std::string& study) {
  return ::testing::AddGlobalTestEnvironment(new StudyResultsWriter(study));
}

}  // namespace fdem::verification
