#include "io/atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include <fmt/format.h>

#include "core/error.hpp"

namespace fdem {

void write_file_atomically(const std::string& path, std::string_view content) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  std::error_code ec;
  if (target.has_parent_path()) fs::create_directories(target.parent_path(), ec);
  // Same folder, so the rename never crosses a file system; the pid keeps two
  // writers of one name (two runs into one folder) from sharing a temporary.
  const fs::path temporary =
      target.parent_path() / fmt::format(".{}.tmp{}", target.filename().string(), static_cast<long>(::getpid()));
  const auto fail = [&](const char* what) {
    const int error = errno;
    ::unlink(temporary.c_str());
    throw SolverError(fmt::format("cannot write output file {}: {} failed: {}", path, what, std::strerror(error)));
  };
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) fail("open");
  std::size_t written = 0;
  while (written < content.size()) {
    const ssize_t n = ::write(fd, content.data() + written, content.size() - written);
    if (n < 0) {
      if (errno == EINTR) continue;  // a signal (SIGINT for a clean stop) must not lose output
      ::close(fd);
      fail("write");
    }
    written += static_cast<std::size_t>(n);
  }
  // Data on disk before the name points at it, or a power cut could expose an empty file.
  if (::fsync(fd) != 0) {
    ::close(fd);
    fail("fsync");
  }
  if (::close(fd) != 0) fail("close");
  if (::rename(temporary.c_str(), target.c_str()) != 0) fail("rename");
}

}  // namespace fdem
