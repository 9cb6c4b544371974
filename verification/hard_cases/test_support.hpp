#pragma once
// Small helpers shared by the hard-case and restart suites: spawning the
// `fdem` command, reading files back, parsing the probes CSV, and scenes
// built in code. Header-only; test code only.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "scene/scene.hpp"

extern char** environ;

namespace fdem::hard {

namespace fs = std::filesystem;

/// Whether `text` holds `part` (messages the tests read).
inline bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

/// A fresh, empty folder under the build tree for one test.
inline fs::path scratch_dir(const std::string& name) {
  const fs::path dir = fs::path(FDEM_BINARY_DIR) / "hard_cases_scratch" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

inline std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path.string());
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline void write_text(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

/// A child process running `fdem` with arguments; stdout and stderr go to files.
class FdemProcess {
 public:
  FdemProcess(const std::vector<std::string>& args, const fs::path& log_dir) {
    stderr_path_ = log_dir / "stderr.txt";
    stdout_path_ = log_dir / "stdout.txt";
    std::vector<std::string> argv_s{FDEM_EXE};
    argv_s.insert(argv_s.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (auto& a : argv_s) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, stdout_path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&actions, 2, stderr_path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int rc = posix_spawn(&pid_, FDEM_EXE, &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (rc != 0) throw std::runtime_error("cannot spawn " + std::string(FDEM_EXE));
  }
  ~FdemProcess() {
    if (pid_ > 0 && !reaped_) {
      ::kill(pid_, SIGKILL);
      int status = 0;
      ::waitpid(pid_, &status, 0);
    }
  }
  FdemProcess(const FdemProcess&) = delete;
  FdemProcess& operator=(const FdemProcess&) = delete;

  void signal(int sig) const { ::kill(pid_, sig); }
  /// True while the child has not exited (does not reap).
  bool running() {
    if (reaped_) return false;
    int status = 0;
    const pid_t r = ::waitpid(pid_, &status, WNOHANG);
    if (r == pid_) {
      reaped_ = true;
      status_ = status;
      return false;
    }
    return true;
  }
  /// Exit code (128 + signal when killed by a signal).
  int wait() {
    if (!reaped_) {
      ::waitpid(pid_, &status_, 0);
      reaped_ = true;
    }
    if (WIFEXITED(status_)) return WEXITSTATUS(status_);
    if (WIFSIGNALED(status_)) return 128 + WTERMSIG(status_);
    return -1;
  }
  std::string stderr_text() const { return read_text(stderr_path_); }
  std::string stdout_text() const { return read_text(stdout_path_); }

 private:
  pid_t pid_ = -1;
  bool reaped_ = false;
  int status_ = 0;
  fs::path stderr_path_, stdout_path_;
};

/// Runs `fdem` with arguments to its end (stdout, stderr in log_dir); returns
/// the exit code (128 + signal) and, when `err` is given, what it printed to stderr.
inline int run_fdem(const std::vector<std::string>& args, const fs::path& log_dir, std::string* err = nullptr) {
  FdemProcess p(args, log_dir);
  const int code = p.wait();
  if (err != nullptr) *err = p.stderr_text();
  return code;
}

/// Runs `fdem` with arguments to its end under one resource limit (setrlimit
/// in the child: RLIMIT_FSIZE with SIGXFSZ ignored makes a write past it fail
/// as on a full disk; RLIMIT_AS caps memory). stdout and stderr go to
/// log_dir/stdout.txt and stderr.txt; `usage` (when given) gets the child's
/// rusage (ru_maxrss: peak RSS in KiB); `extra_env` ("NAME=value") comes before
/// the inherited environment. Returns the exit code (128 + signal).
inline int run_fdem_limited(const std::vector<std::string>& args, const fs::path& log_dir, int resource,
                            rlim_t limit, rusage* usage = nullptr, const std::vector<std::string>& extra_env = {}) {
  std::vector<std::string> env_s(extra_env);  // built before fork: the child only execs
  for (char** e = environ; *e != nullptr; ++e) env_s.emplace_back(*e);
  std::vector<char*> envp;
  for (auto& e : env_s) envp.push_back(e.data());
  envp.push_back(nullptr);
  std::vector<std::string> argv_s{FDEM_EXE};
  argv_s.insert(argv_s.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : argv_s) argv.push_back(a.data());
  argv.push_back(nullptr);
  const std::string out_path = (log_dir / "stdout.txt").string(), err_path = (log_dir / "stderr.txt").string();
  const pid_t pid = ::fork();
  if (pid == 0) {  // only async-signal-safe calls until exec
    const int out = ::open(out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int err = ::open(err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (out >= 0) ::dup2(out, 1);
    if (err >= 0) ::dup2(err, 2);
    const rlimit value{limit, limit};
    ::setrlimit(resource, &value);
    ::signal(SIGXFSZ, SIG_IGN);
    ::execve(FDEM_EXE, argv.data(), envp.data());
    ::_exit(127);
  }
  int status = 0;
  rusage ignored{};
  ::wait4(pid, &status, 0, usage != nullptr ? usage : &ignored);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

/// Waits until pred() holds or the timeout passes; returns pred().
template <class Pred>
bool wait_for(Pred pred, double timeout_s) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (std::chrono::steady_clock::now() < end) {
    if (pred()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return pred();
}

/// The probes CSV written by `fdem run`: header and numeric rows.
struct Csv {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  bool well_formed = true;  // every row has the header's column count, every value parses
  int column(const std::string& name) const {
    for (std::size_t i = 0; i < columns.size(); ++i)
      if (columns[i] == name) return static_cast<int>(i);
    return -1;
  }
};

inline std::vector<std::string> split(const std::string& line, char sep) {
  std::vector<std::string> out;
  std::string cell;
  std::istringstream s(line);
  while (std::getline(s, cell, sep)) out.push_back(cell);
  if (!line.empty() && line.back() == sep) out.emplace_back();
  return out;
}

inline Csv read_csv(const fs::path& path) {
  Csv csv;
  std::istringstream in(read_text(path));
  std::string line;
  if (!std::getline(in, line)) {
    csv.well_formed = false;
    return csv;
  }
  csv.columns = split(line, ',');
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    const auto cells = split(line, ',');
    if (cells.size() != csv.columns.size()) csv.well_formed = false;
    std::vector<double> row;
    for (const auto& c : cells) {
      try {
        std::size_t used = 0;
        row.push_back(std::stod(c, &used));
        if (used != c.size()) csv.well_formed = false;
      } catch (const std::exception&) {
        csv.well_formed = false;
        row.push_back(std::nan(""));
      }
    }
    csv.rows.push_back(std::move(row));
  }
  return csv;
}

/// A VTK XML file is complete when it ends with its closing tag.
inline bool vtk_file_complete(const fs::path& path) {
  if (!fs::exists(path)) return false;
  std::string text = read_text(path);
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  return text.size() >= 10 && text.compare(text.size() - 10, 10, "</VTKFile>") == 0;
}

/// The files a .pvd names (DataSet file="...").
inline std::vector<std::string> pvd_datasets(const fs::path& pvd) {
  std::vector<std::string> files;
  const std::string text = read_text(pvd);
  const std::string key = "file=\"";
  for (std::size_t at = text.find(key); at != std::string::npos; at = text.find(key, at + 1)) {
    const std::size_t begin = at + key.size();
    files.push_back(text.substr(begin, text.find('"', begin) - begin));
  }
  return files;
}

}  // namespace fdem::hard
