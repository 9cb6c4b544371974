#pragma once
// Whole-file writes that are atomic: the content goes to a temporary name in
// the same folder, is flushed to disk, and is renamed over the target. A run
// killed mid-write leaves either the previous complete file or none, never a
// truncated file posing as complete (rename within one file system is atomic
// in POSIX).
#include <string>
#include <string_view>

namespace fdem {

/// Writes `content` to `path` atomically; creates missing parent folders.
/// Throws SolverError naming the path when the disk refuses.
void write_file_atomically(const std::string& path, std::string_view content);

}  // namespace fdem
