#pragma once
// A CSV time series (probes): a header of column names, one row per sample,
// shortest round-trip decimals. Rows are kept in memory and the whole file is
// rewritten atomically on write(), so the file on disk is always complete up
// to its last row.
#include <span>
#include <string>
#include <vector>

namespace fdem {

class CsvSeries {
 public:
  CsvSeries(std::string path, std::vector<std::string> columns);

  /// One row; its size must equal the number of columns (SolverError otherwise).
  void append(std::span<const double> values);
  /// Drops rows whose first column (time) exceeds `time_s` (restart).
  void truncate_after(double time_s);
  void write() const;
  std::string content() const;

  std::size_t rows() const { return rows_.size() / columns_.size(); }
  const std::vector<std::string>& columns() const { return columns_; }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::vector<std::string> columns_;
  std::vector<double> rows_;  // row-major
};

}  // namespace fdem
