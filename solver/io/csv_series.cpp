#include "io/csv_series.hpp"

#include <iterator>

#include <fmt/format.h>

#include "core/error.hpp"
#include "io/atomic_file.hpp"

namespace fdem {

CsvSeries::CsvSeries(std::string path, std::vector<std::string> columns)
    : path_(std::move(path)), columns_(std::move(columns)) {
  if (columns_.empty()) throw SolverError(fmt::format("CSV series {} has no columns", path_));
}

void CsvSeries::append(std::span<const double> values) {
  if (values.size() != columns_.size()) {
    throw SolverError(fmt::format("CSV series {}: row of {} values for {} columns", path_, values.size(), columns_.size()));
  }
  rows_.insert(rows_.end(), values.begin(), values.end());
}

void CsvSeries::truncate_after(double time_s) {
  const std::size_t width = columns_.size();
  std::size_t keep = 0;
  while (keep < rows() && rows_[keep * width] <= time_s) ++keep;
  rows_.resize(keep * width);
}

std::string CsvSeries::content() const {
  fmt::memory_buffer out;
  fmt::format_to(std::back_inserter(out), "{}\n", fmt::join(columns_, ","));
  const std::size_t width = columns_.size();
  for (std::size_t r = 0; r < rows(); ++r) {
    for (std::size_t c = 0; c < width; ++c) {
      if (c > 0) out.push_back(',');
      fmt::format_to(std::back_inserter(out), "{}", rows_[r * width + c]);
    }
    out.push_back('\n');
  }
  return fmt::to_string(out);
}

void CsvSeries::write() const { write_file_atomically(path_, content()); }

}  // namespace fdem
