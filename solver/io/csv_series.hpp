#pragma once
// A CSV time series (probes): a header of column names, one row per sample,
// shortest round-trip decimals. Each row is appended to the file with one
// write(2) as it is sampled, so a run killed at any moment (kill -9 included)
// leaves every row sampled before it; a row the disk refuses (full disk) is
// cut back off, so the file always ends with a complete row.
#include <span>
#include <string>
#include <vector>

namespace fdem {

class CsvSeries {
 public:
  /// Creates (truncates) the file and writes the header; SolverError when it cannot.
  CsvSeries(std::string path, std::vector<std::string> columns);
  ~CsvSeries();
  CsvSeries(const CsvSeries&) = delete;
  CsvSeries& operator=(const CsvSeries&) = delete;

  /// Appends one row to the file; its size must equal the number of columns.
  /// SolverError (naming the file and the system's reason) when the row
  /// cannot be written; the file then still ends with the previous row.
  void append(std::span<const double> values);

  /// Restart: copies the rows of an earlier run's series at `old_path` whose
  /// column `key_column` is below `below` (e.g. the steps before the
  /// checkpoint), byte for byte. Returns the rows carried; -1 when the file
  /// is missing or its header differs (nothing carried).
  long carry_rows(const std::string& old_path, const std::string& key_column, double below);

  /// Forces the rows written so far to the disk (fsync).
  void sync() const;

  std::size_t rows() const { return rows_; }
  const std::vector<std::string>& columns() const { return columns_; }
  const std::string& path() const { return path_; }

 private:
  void write_text(const std::string& text);
  std::string path_;
  std::vector<std::string> columns_;
  std::size_t rows_ = 0;
  long long length_ = 0;  // bytes of complete rows in the file
  int fd_ = -1;
};

}  // namespace fdem
