#pragma once
// What a verification study reads and writes (reference_data/README.md,
// reports/FORMATS.md): the reference rows of reference_data/<study>.csv, and
// the files under $FDEM_RESULTS_DIR/<study>/ (values.csv, meta.json, series
// CSVs), each written atomically (ctest runs tests in parallel and the report
// may read a folder while a study writes it). The one writer every study
// uses: a new study calls read_reference, write_values, write_numeric_csv and
// write_meta, adds reference_data/<study>.csv, and appears in the report.
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace fdem::study {

/// One row of reference_data/<study>.csv.
struct ReferenceRow {
  std::string id;
  double value = 0.0;
  std::optional<double> tolerance;  // empty: tabulated, not gated
  std::string tolerance_kind;       // rel | abs | pct_points | at_least | at_most
  bool gate = false;
  std::string row_class;            // verification | validation | reproduction | consistency
};

/// Reads reference_data/<study>.csv under the source tree (FDEM_SOURCE_DIR);
/// throws std::runtime_error naming the file and line on a malformed row.
std::map<std::string, ReferenceRow> read_reference(const std::string& study);

/// The row with this id, or std::runtime_error naming the id.
const ReferenceRow& reference(const std::map<std::string, ReferenceRow>& rows, const std::string& id);

/// |ours - ref| within the row's tolerance (rel: fraction of |ref|; abs and
/// pct_points: same unit); one-sided: at_least ours >= ref - tol, at_most
/// ours <= ref + tol. Rows without tolerance always pass.
bool within_tolerance(const ReferenceRow& row, double ours);

/// Every gated row of reference_data/<study>.csv (gate = yes, with a
/// tolerance) that `values` holds and that misses its tolerance, as one
/// message each (id, ours, reference, tolerance); `measured` counts the gated
/// rows found. The study's gates read from reference_data, not from code.
std::vector<std::string> gate_failures(const std::map<std::string, ReferenceRow>& rows,
                                       const std::vector<std::pair<std::string, double>>& values, int* measured = nullptr);

/// values.csv of a results folder read back (id -> value).
std::vector<std::pair<std::string, double>> read_values(const std::string& dir);

/// $FDEM_RESULTS_DIR (environment) or the FDEM_RESULTS_DIR of the build, plus /<study>.
std::string results_dir(const std::string& study);

/// A CSV with a header row and numeric rows; `comment` lines go first as `# ...`.
void write_numeric_csv(const std::string& path, const std::vector<std::string>& columns,
                       const std::vector<std::vector<double>>& rows, const std::vector<std::string>& comment = {});

/// values.csv: header `id,value`, one row per id (shortest round-trip decimals).
void write_values(const std::string& dir, const std::vector<std::pair<std::string, double>>& values);

/// What defines one run of a study, for meta.json (reports/FORMATS.md).
struct RunRecord {
  std::string tier;        // fast | full (or a study's own name for a size)
  std::string scene_file;  // the scene it loaded, relative to the source tree ("" if built in code)
  std::vector<std::pair<std::string, std::string>> parameters;  // what the tier changes: mesh, steps, end time, ...
  double wall_time_s = 0.0;
  bool passed = false;
  std::string status = "done";  // done | running | error
  std::string extra_json;       // further members, already JSON: `"key": value, ...` (may be empty)
};

/// The source tree's state when the study ran: `git rev-parse HEAD` and
/// whether tracked files differ from it, or FDEM_SOURCE_COMMIT and
/// FDEM_SOURCE_DIRTY (1/0) when a driver pins the commit it built.
/// "unknown" outside a git checkout.
struct SourceState {
  std::string commit = "unknown";
  bool dirty = false;
  bool known = false;
};
SourceState source_state();

/// 64-bit FNV-1a of a file's bytes as 16 hex digits (the report recomputes
/// it to tell whether the scene changed since the run); "" if unreadable.
std::string file_hash(const std::string& path);

/// meta.json: study, tier, wall_time_s, passed, status, finished_utc, commit,
/// dirty, scene {file, fnv1a64}, parameters {..}, threads (OpenMP), host, and
/// `run.extra_json`.
void write_meta(const std::string& dir, const std::string& study, const RunRecord& run);

/// Removes every regular file in `dir` (a study starts from an empty folder,
/// so no stale file of an earlier run is reported as this run's).
void clear_dir(const std::string& dir);

}  // namespace fdem::study
