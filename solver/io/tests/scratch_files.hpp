#pragma once
// Scratch folders and file reads for the tests that write output (io, app,
// verification/scene_input): one definition instead of a copy in each.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>

namespace fdem {

/// <temp>/fdem_<suite>_<name>_<pid>, emptied (a run of the same test in
/// another process has its own), and created unless `create` is false (a
/// test of a command that must create its output folder itself).
inline std::filesystem::path fresh_test_directory(std::string_view suite, std::string_view name, bool create = true) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                    ("fdem_" + std::string(suite) + "_" + std::string(name) + "_" +
                                     std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  if (create) std::filesystem::create_directories(dir);
  return dir;
}

/// A file's bytes ("" when it cannot be opened).
inline std::string file_contents(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

}  // namespace fdem
