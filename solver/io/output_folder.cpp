#include "io/output_folder.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "core/error.hpp"
#include "io/atomic_file.hpp"

#ifndef FDEM_GIT_COMMIT
#define FDEM_GIT_COMMIT "unknown"
#endif

namespace fdem {

namespace fs = std::filesystem;

namespace {

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    if (static_cast<unsigned char>(c) < 0x20) {
      out += fmt::format("\\u{:04x}", static_cast<int>(c));
      continue;
    }
    out += c;
  }
  return out + "\"";
}

std::string utc_now() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&now, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return text;
}

// The value of "key": "..." in a small JSON object written by this file.
std::string json_field(const std::string& text, const std::string& key) {
  const std::string tag = "\"" + key + "\": \"";
  const std::size_t at = text.find(tag);
  if (at == std::string::npos) return {};
  const std::size_t begin = at + tag.size();
  const std::size_t end = text.find('"', begin);
  return end == std::string::npos ? std::string() : text.substr(begin, end - begin);
}

std::string read_small_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// True when `inner` is `outer` or lies below it (both canonical).
bool is_within(const fs::path& inner, const fs::path& outer) {
  auto i = inner.begin();
  for (auto o = outer.begin(); o != outer.end(); ++o, ++i)
    if (i == inner.end() || *i != *o) return false;
  return true;
}

}  // namespace

std::string manifest_scene_hash(const std::string& manifest_path) {
  return json_field(read_small_file(manifest_path), "scene_hash");
}

OutputFolder::OutputFolder(const OutputFolderRequest& request, std::FILE* log) : directory_(request.directory) {
  const fs::path dir(request.directory);
  auto refuse = [&](const std::string& reason) {
    release();
    throw InputError(request.scene_file, request.key, request.directory, reason);
  };
  auto note = [&](const std::string& text) {
    if (log != nullptr) std::fprintf(log, "fdem: %s\n", text.c_str());
  };
  std::error_code ec;

  // 1. A folder, and none of the scene's inputs in it.
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    refuse("is a file, not a folder; give a folder for the output (--output DIR)");
  const fs::path dir_canonical = fs::weakly_canonical(fs::absolute(dir), ec);
  for (const std::string& input : request.input_files) {
    const fs::path input_canonical = fs::weakly_canonical(fs::absolute(input), ec);
    if (is_within(input_canonical, dir_canonical))
      refuse(fmt::format("holds the scene's input {}: its outputs (probes.csv, snapshots) or --overwrite could "
                         "destroy it; write the output to another folder",
                         input));
  }
  if (!fs::exists(dir, ec)) {
    fs::create_directories(dir, ec);
    if (ec) refuse(fmt::format("cannot create the folder: {}", ec.message()));
    note(fmt::format("created the output folder {}", request.directory));
  }

  // 2. The lock: held for the object's lifetime, released by the kernel if the process dies.
  lock_path_ = (dir / lock_name).string();
  lock_fd_ = ::open(lock_path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (lock_fd_ < 0) refuse(fmt::format("cannot create the lock file {}: {}", lock_name, std::strerror(errno)));
  const std::string holder = read_small_file(lock_path_);
  if (::flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
    const int error = errno;
    ::close(lock_fd_);  // not ours: leave its content
    lock_fd_ = -1;
    if (error == EWOULDBLOCK)
      refuse(fmt::format("is in use by another fdem run ({}); wait for it to end or choose another folder",
                         holder.empty() ? "process unknown" : holder));
    refuse(fmt::format("cannot lock the folder: {}", std::strerror(error)));
  }
  if (!holder.empty())
    note(fmt::format("{}: a stale lock of a run that is no longer running ({}) was taken over", request.directory,
                     holder));
  const std::string started = utc_now();
  const std::string me = fmt::format("process {}, started {}", static_cast<long>(::getpid()), started);
  if (::ftruncate(lock_fd_, 0) != 0 || ::pwrite(lock_fd_, me.data(), me.size(), 0) != static_cast<ssize_t>(me.size()))
    refuse(fmt::format("cannot write the lock file {}: {}", lock_name, std::strerror(errno)));

  // 3. No mixing with an earlier run's files.
  std::vector<fs::path> old_entries;
  for (const auto& entry : fs::directory_iterator(dir, ec))
    if (entry.path().filename() != lock_name) old_entries.push_back(entry.path());
  if (!old_entries.empty()) {
    const fs::path manifest = dir / manifest_name;
    const std::string old_hash = fs::exists(manifest, ec) ? manifest_scene_hash(manifest.string()) : std::string();
    const bool same_scene = !old_hash.empty() && old_hash == request.scene_hash;
    if (!same_scene && !request.overwrite) {
      const std::string owner =
          old_hash.empty()
              ? fmt::format("{} entries fdem did not write (e.g. {})", old_entries.size(),
                            old_entries.front().filename().string())
              : fmt::format("the output of another scene ({})",
                            json_field(read_small_file(manifest), "scene"));
      refuse(fmt::format("is not empty: it holds {}; pass --overwrite to clear it first, or choose another folder",
                         owner));
    }
    for (const fs::path& entry : old_entries) {
      fs::remove_all(entry, ec);
      if (ec) refuse(fmt::format("cannot clear {}: {}", entry.string(), ec.message()));
    }
    note(fmt::format("cleared {} entries of the earlier run in {}", old_entries.size(), request.directory));
  }

  // 4. The manifest.
  const std::string manifest = fmt::format(
      "{{\n  \"scene\": {},\n  \"scene_hash\": {},\n  \"started_utc\": {},\n  \"commit\": {},\n  \"version\": {},\n"
      "  \"process\": {},\n  \"restart_from\": {}\n}}\n",
      json_string(fs::weakly_canonical(fs::absolute(request.scene_file), ec).string()), json_string(request.scene_hash),
      json_string(started), json_string(FDEM_GIT_COMMIT), json_string(FDEM_VERSION), static_cast<long>(::getpid()),
      json_string(request.restart_from));
  write_file_atomically((dir / manifest_name).string(), manifest);
}

OutputFolder::~OutputFolder() { release(); }

void OutputFolder::release() {
  if (lock_fd_ < 0) return;
  // Emptied, not removed: a process that opened the name just now must lock
  // the same file as the next one. An empty lock file is not stale.
  if (::ftruncate(lock_fd_, 0) != 0) {
    // Nothing to do: the next run reports it as stale and takes it over.
  }
  ::close(lock_fd_);
  lock_fd_ = -1;
}

}  // namespace fdem
