#pragma once
// An output folder owned by one run. Claiming it, before any set-up:
//   1. refuses a path that is not a folder, and a folder that holds one of the
//      scene's inputs (the scene file, its particle CSV files): a probes.csv or
//      an --overwrite could destroy them;
//   2. takes an exclusive lock, `.fdem.lock` (flock(2), so the kernel releases
//      it when the process dies, kill -9 included): a second live run into the
//      folder is refused naming the holder's process; a lock file left by a
//      dead run is reported as stale and taken over;
//   3. keeps a new run from mixing with old files: a folder whose manifest
//      names the same scene (same scene hash) is cleared; a non-empty folder
//      of another scene, or of files fdem did not write, is refused unless
//      `overwrite`, which clears it first;
//   4. writes `run_manifest.json` (scene, scene hash, start time, commit).
// Every refusal is an InputError naming the folder and the key it came from.
#include <cstdio>
#include <string>
#include <vector>

namespace fdem {

struct OutputFolderRequest {
  std::string directory;                 // the folder to own
  std::string key;                       // where it was given: "--output" or "output.directory"
  std::string scene_file;                // for messages and the manifest
  std::vector<std::string> input_files;  // the scene file and every file it reads
  std::string scene_hash;                // hex digest of the scene's inputs
  std::string restart_from;              // checkpoint resumed from (manifest only; empty: none)
  bool overwrite = false;                // clear a folder of another scene instead of refusing
};

class OutputFolder {
 public:
  /// Claims the folder (steps 1-4 above); notes (stale lock, folder created
  /// or cleared) go to `log` when not null.
  OutputFolder(const OutputFolderRequest& request, std::FILE* log);
  /// Releases the lock (the lock file stays, empty).
  ~OutputFolder();
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;

  const std::string& directory() const { return directory_; }

  static constexpr const char* lock_name = ".fdem.lock";
  static constexpr const char* manifest_name = "run_manifest.json";

 private:
  void release();
  std::string directory_;
  std::string lock_path_;
  int lock_fd_ = -1;
};

/// The scene hash a manifest records (empty when the file holds none).
std::string manifest_scene_hash(const std::string& manifest_path);

}  // namespace fdem
