#pragma once
// What a verification study reads and writes (reference_data/README.md,
// reports/FORMATS.md): the reference rows of reference_data/<study>.csv, and
// the files under $FDEM_RESULTS_DIR/<study>/ (values.csv, meta.json, series
// CSVs), each written atomically (ctest runs tests in parallel and the report
// may read a folder while a study writes it). Used by the mesh_sensitivity
// and channel studies.
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
  std::string tolerance_kind;       // rel | abs | pct_points
  bool gate = false;
};

/// Reads reference_data/<study>.csv under the source tree (FDEM_SOURCE_DIR);
/// throws std::runtime_error naming the file and line on a malformed row.
std::map<std::string, ReferenceRow> read_reference(const std::string& study);

/// The row with this id, or std::runtime_error naming the id.
const ReferenceRow& reference(const std::map<std::string, ReferenceRow>& rows, const std::string& id);

/// |ours - ref| within the row's tolerance (rel: fraction of |ref|; abs and
/// pct_points: same unit). Rows without tolerance always pass.
bool within_tolerance(const ReferenceRow& row, double ours);

/// $FDEM_RESULTS_DIR (environment) or the FDEM_RESULTS_DIR of the build, plus /<study>.
std::string results_dir(const std::string& study);

/// A CSV with a header row and numeric rows; `comment` lines go first as `# ...`.
void write_numeric_csv(const std::string& path, const std::vector<std::string>& columns,
                       const std::vector<std::vector<double>>& rows, const std::vector<std::string>& comment = {});

/// values.csv: header `id,value`, one row per id (shortest round-trip decimals).
void write_values(const std::string& dir, const std::vector<std::pair<std::string, double>>& values);

/// meta.json: {"study", "tier", "wall_time_s", "passed"}.
void write_meta(const std::string& dir, const std::string& study, const std::string& tier, double wall_time_s,
                bool passed);

/// Removes every regular file in `dir` (a study starts from an empty folder,
/// so no stale file of an earlier run is reported as this run's).
void clear_dir(const std::string& dir);

}  // namespace fdem::study
