#include "io/csv_series.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>

#include <fmt/format.h>

#include "core/error.hpp"

namespace fdem {

CsvSeries::CsvSeries(std::string path, std::vector<std::string> columns)
    : path_(std::move(path)), columns_(std::move(columns)) {
  if (columns_.empty()) throw SolverError(fmt::format("CSV series {} has no columns", path_));
  fd_ = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) throw SolverError(fmt::format("cannot write output file {}: {}", path_, std::strerror(errno)));
  write_text(fmt::format("{}\n", fmt::join(columns_, ",")));
}

CsvSeries::~CsvSeries() {
  if (fd_ >= 0) ::close(fd_);
}

void CsvSeries::write_text(const std::string& text) {
  std::size_t written = 0;
  while (written < text.size()) {
    const ssize_t n = ::pwrite(fd_, text.data() + written, text.size() - written,
                               static_cast<off_t>(length_ + static_cast<long long>(written)));
    if (n < 0 && errno == EINTR) continue;  // a signal (SIGINT for a clean stop) must not lose a row
    if (n <= 0) {
      const int error = n < 0 ? errno : ENOSPC;
      // Cut a partly written row back off: the file ends with a complete row.
      if (::ftruncate(fd_, static_cast<off_t>(length_)) != 0) {
        // The disk refuses even that; the reader's row check flags the partial line.
      }
      throw SolverError(fmt::format("cannot append to output file {}: {} (the rows before are kept)", path_,
                                    std::strerror(error)));
    }
    written += static_cast<std::size_t>(n);
  }
  length_ += static_cast<long long>(text.size());
}

void CsvSeries::append(std::span<const double> values) {
  if (values.size() != columns_.size()) {
    throw SolverError(fmt::format("CSV series {}: row of {} values for {} columns", path_, values.size(), columns_.size()));
  }
  fmt::memory_buffer out;
  for (std::size_t c = 0; c < values.size(); ++c) {
    if (c > 0) out.push_back(',');
    fmt::format_to(std::back_inserter(out), "{}", values[c]);
  }
  out.push_back('\n');
  write_text(fmt::to_string(out));
  ++rows_;
}

long CsvSeries::carry_rows(const std::string& old_path, const std::string& key_column, double below) {
  std::ifstream in(old_path, std::ios::binary);
  std::string line;
  if (!in || !std::getline(in, line) || line != fmt::format("{}", fmt::join(columns_, ","))) return -1;
  std::size_t key = 0;
  while (key < columns_.size() && columns_[key] != key_column) ++key;
  if (key == columns_.size()) return -1;
  std::string carried;
  long count = 0;
  while (std::getline(in, line) && !in.eof()) {  // a last line without its newline was cut short: dropped
    std::size_t begin = 0;
    for (std::size_t c = 0; c < key && begin != std::string::npos; ++c) {
      begin = line.find(',', begin);
      if (begin != std::string::npos) ++begin;
    }
    if (begin == std::string::npos) break;
    char* end = nullptr;
    const double value = std::strtod(line.c_str() + begin, &end);
    if (end == line.c_str() + begin || !(value < below)) break;
    carried += line;
    carried += '\n';
    ++count;
  }
  write_text(carried);
  rows_ += static_cast<std::size_t>(count);
  return count;
}

void CsvSeries::sync() const {
  if (fd_ >= 0) ::fsync(fd_);
}

}  // namespace fdem
