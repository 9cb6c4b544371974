// Crash safety: output files are written atomically (io/atomic_file.hpp). A
// reader running beside the writer, and a writer killed at any moment, only
// ever see a complete previous or complete new file, never a torn one.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <string>
#include <thread>

#include "core/error.hpp"
#include "io/atomic_file.hpp"
#include "test_support.hpp"

namespace fdem {
namespace {

// Two contents of equal size (so a torn file could not be told apart by its size alone),
// each ending with its own marker.
std::string content(char fill) {
  std::string s(256 * 1024, fill);
  s += std::string("\nEND-") + fill + "\n";
  return s;
}

// A child process that rewrites `path` with A, B, A, ... until killed.
pid_t start_writer(const std::string& path) {
  const std::string a = content('a'), b = content('b');
  const pid_t pid = ::fork();
  if (pid == 0) {
    for (long k = 0;; ++k) {
      try {
        write_file_atomically(path, (k % 2 == 0) ? a : b);
      } catch (...) {
        ::_exit(1);
      }
    }
  }
  return pid;
}

TEST(AtomicOutput, ReaderBesideAWriterSeesOnlyWholeFiles) {
  // Shows: 300 reads while another process rewrites a 256 KiB file each see exactly content A or B.
  const auto dir = hard::scratch_dir("atomic_reader");
  const std::string path = (dir / "series.csv").string();
  write_file_atomically(path, content('a'));
  const pid_t writer = start_writer(path);
  ASSERT_GT(writer, 0);
  const std::string a = content('a'), b = content('b');
  int reads = 0, torn = 0, saw_b = 0;
  // Read until 300 reads AND one replacement seen: on a loaded machine the forked
  // writer may not be scheduled for a while; the deadline only bounds a hung writer.
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while ((reads < 300 || saw_b == 0) && std::chrono::steady_clock::now() < end) {
    const std::string text = hard::read_text(path);
    ++reads;
    if (text == b) ++saw_b;
    else if (text != a) ++torn;
  }
  ::kill(writer, SIGKILL);
  int status = 0;
  ::waitpid(writer, &status, 0);
  EXPECT_EQ(torn, 0) << "of " << reads << " reads";
  EXPECT_GE(reads, 50);
  EXPECT_GT(saw_b, 0) << "the writer must actually have replaced the file while we read";
}

TEST(AtomicOutput, WriterKilledAtAnyMomentLeavesAWholeFile) {
  // Shows: 20 writers SIGKILLed at staggered moments each leave the target equal to A or B; temporaries stay hidden.
  const auto dir = hard::scratch_dir("atomic_killed");
  const std::string path = (dir / "particles_000000.vtu").string();
  const std::string a = content('a'), b = content('b');
  for (int trial = 0; trial < 20; ++trial) {
    const pid_t writer = start_writer(path);
    ASSERT_GT(writer, 0);
    std::this_thread::sleep_for(std::chrono::microseconds(3000 + 1700 * trial));
    ::kill(writer, SIGKILL);
    int status = 0;
    ::waitpid(writer, &status, 0);
    if (!hard::fs::exists(path)) continue;  // killed before its first rename: no file, which is not a torn one
    const std::string text = hard::read_text(path);
    EXPECT_TRUE(text == a || text == b) << "trial " << trial << ": " << text.size() << " bytes";
  }
  // A killed writer may leave its temporary behind, but under a hidden name that no
  // series (.pvd, .csv) refers to.
  for (const auto& entry : hard::fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (name != "particles_000000.vtu") {
      EXPECT_EQ(name.front(), '.') << name;
    }
  }
}

TEST(AtomicOutput, CompletedWriteLeavesNoTemporaryAndUnwritablePathIsNamed) {
  // Shows: a finished write leaves only the target; a folder that is a file gives SolverError naming the path.
  const auto dir = hard::scratch_dir("atomic_clean");
  write_file_atomically((dir / "a.txt").string(), "1\n");
  write_file_atomically((dir / "a.txt").string(), "2\n");
  int files = 0;
  for (const auto& entry : hard::fs::directory_iterator(dir)) {
    ++files;
    EXPECT_EQ(entry.path().filename(), "a.txt");
  }
  EXPECT_EQ(files, 1);
  EXPECT_EQ(hard::read_text(dir / "a.txt"), "2\n");
  const std::string bad = (dir / "a.txt" / "inside.vtu").string();
  try {
    write_file_atomically(bad, "x");
    FAIL() << "writing under a regular file must fail";
  } catch (const SolverError& e) {
    EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace fdem
