// A scene whose memory estimate exceeds the available memory is refused (exit
// 2) by `fdem check` and `fdem run` before anything is allocated, and `check`
// stays cheap on it: it counts 1e8 grains instead of drawing them.
#include <gtest/gtest.h>

#include <sys/resource.h>

#include "memory_scenes.hpp"
#include "test_support.hpp"

namespace fdem {
namespace {

namespace fs = std::filesystem;

TEST(MemoryRefusal, HundredMillionGrainsAboveTheCapAreRefusedBeforeAllocatingAndCheckCountsThemCheaply) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer reserves terabytes of address space for its shadow memory, so an address-space cap "
                  "(RLIMIT_AS) cannot be applied; the Release build runs this case";
#endif
  // 1e8 grains (the loader's most), about 17 GiB estimated, against a cap of
  // 4 GiB (FDEM_MEMORY_LIMIT_MIB), so the refusal does not depend on the test
  // machine's memory. Before: `check` drew all 1e8 grains (8.4 GiB, 50 s) and
  // called the scene valid; the 1 GiB address-space cap makes that fail fast here.
  const fs::path dir = hard::scratch_dir("memory_refusal");
  hard::write_text(dir / "scene.yaml", hard::random_grains_yaml(100000000, 1.0));
  const std::vector<std::string> cap{"FDEM_MEMORY_LIMIT_MIB=4096"};
  constexpr rlim_t address_cap = rlim_t{1} << 30;  // 1 GiB: drawing the grains fails fast instead of filling the machine
  for (const std::string command : {"check", "run"}) {
    std::vector<std::string> args{command, (dir / "scene.yaml").string()};
    if (command == "run") args.insert(args.end(), {"-o", (dir / "out").string(), "-q"});
    rusage usage{};
    const int code = hard::run_fdem_limited(args, dir, RLIMIT_AS, address_cap, &usage, cap);
    const std::string err = hard::read_text(dir / "stderr.txt");
    EXPECT_EQ(code, 2) << command << ": " << err;
    EXPECT_NE(err.find("4.00 GiB is available"), std::string::npos) << err;
    EXPECT_NE(err.find("--ignore-memory-limit"), std::string::npos) << err;
    EXPECT_LT(usage.ru_maxrss, 200 * 1024) << command << ": peak RSS [KiB]";
  }
  // With the override `check` prints its numbers, still without drawing a grain.
  rusage usage{};
  const int code = hard::run_fdem_limited({"check", (dir / "scene.yaml").string(), "--ignore-memory-limit"}, dir,
                                          RLIMIT_AS, address_cap, &usage, cap);
  const std::string out = hard::read_text(dir / "stdout.txt");
  EXPECT_EQ(code, 0) << hard::read_text(dir / "stderr.txt");
  EXPECT_NE(out.find("100000000 in 1 set(s), not drawn"), std::string::npos) << out;
  EXPECT_NE(out.find("GiB peak"), std::string::npos) << out;
  EXPECT_LT(usage.ru_maxrss, 200 * 1024) << "peak RSS [KiB]";
}

}  // namespace
}  // namespace fdem
