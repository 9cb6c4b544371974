// Property test of the scene parser (robustness): valid scenes
// mutated at random (lines deleted, duplicated, swapped, re-indented; values
// retyped; bytes flipped or inserted; the file truncated) must each give a
// Scene or a clean InputError, never a crash, a hang or another exception.
// Run under ASan/UBSan too (scripts/test.sh --sanitize). Bounded: a fixed
// number of mutants per sample, and a wall-clock cap so a slow sanitizer
// build stays within the tier's budget.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "app/check_command.hpp"
#include "core/error.hpp"
#include "io/tests/scratch_files.hpp"
#include "scene/particle_generator.hpp"
#include "scene/scene_loader.hpp"

// A namespace of its own: the executable compiles its files as one unit.
namespace fdem::scene_fuzz_test {
namespace {

const std::string kExamples = std::string(FDEM_SOURCE_DIR) + "/examples/";

std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::string join_lines(const std::vector<std::string>& lines) {
  std::string out;
  for (const auto& l : lines) out += l + "\n";
  return out;
}

// Values that probe conversions and ranges: wrong types, extremes, YAML specials.
const char* const kNastyValues[] = {
    "-1", "0", "1e400", "-1e-400", ".nan", ".inf", "-.inf", "nan", "abc", "''", "\"\"", "[]", "{}", "[1, 2]",
    "[1, 2, 3, 4]", "[a, b, c]", "{x: 1}", "~", "null", "true", "off", "2147483648", "-2147483649",
    "99999999999999999999", "0x10", "1_000", "&a 1", "*a", "!!binary aGVsbG8=", "|\n  block", "? x", "- 1",
    "1e-320", "100000", "1e8", "0.5", "[0, 0, 0]", "[1e9, 1e9, 1e9]", "csv", "normal", "lattice", "random"};

std::string mutate(const std::string& text, std::mt19937_64& rng) {
  auto pick = [&](std::size_t n) { return static_cast<std::size_t>(rng() % std::max<std::size_t>(n, 1)); };
  std::vector<std::string> lines = split_lines(text);
  switch (rng() % 9) {
    case 0:  // delete a line
      if (!lines.empty()) lines.erase(lines.begin() + static_cast<std::ptrdiff_t>(pick(lines.size())));
      return join_lines(lines);
    case 1: {  // duplicate a line (duplicate keys)
      if (lines.empty()) return text;
      const std::size_t i = pick(lines.size());
      lines.insert(lines.begin() + static_cast<std::ptrdiff_t>(i), lines[i]);
      return join_lines(lines);
    }
    case 2: {  // swap two lines
      if (lines.size() < 2) return text;
      std::swap(lines[pick(lines.size())], lines[pick(lines.size())]);
      return join_lines(lines);
    }
    case 3: {  // re-indent a line
      if (lines.empty()) return text;
      std::string& l = lines[pick(lines.size())];
      if (rng() % 2 == 0 && !l.empty() && l[0] == ' ') l.erase(0, 1 + pick(2));
      else l.insert(0, std::string(1 + pick(4), ' '));
      return join_lines(lines);
    }
    case 4:
    case 5: {  // retype the value after a ':' (or inside a flow list)
      if (lines.empty()) return text;
      std::string& l = lines[pick(lines.size())];
      const std::size_t colon = l.find(':');
      if (colon == std::string::npos) return text;
      std::size_t end = l.find_first_of(",}]", colon + 1);
      if (end == std::string::npos) end = l.size();
      l = l.substr(0, colon + 1) + " " + kNastyValues[pick(std::size(kNastyValues))] + l.substr(end);
      return join_lines(lines);
    }
    case 6: {  // flip random bytes
      std::string out = text;
      for (std::size_t n = 1 + pick(4); n > 0 && !out.empty(); --n) out[pick(out.size())] = static_cast<char>(rng());
      return out;
    }
    case 7: {  // insert random bytes, YAML punctuation more often
      static const char punctuation[] = "{}[]:,-#&*!|>'\"%@`\t\n ";
      std::string out = text;
      for (std::size_t n = 1 + pick(6); n > 0; --n) {
        const char c = rng() % 2 ? punctuation[pick(sizeof punctuation - 1)] : static_cast<char>(rng());
        out.insert(out.begin() + static_cast<std::ptrdiff_t>(pick(out.size() + 1)), c);
      }
      return out;
    }
    default:  // truncate
      return text.substr(0, pick(text.size() + 1));
  }
}

// Everything `fdem check` does with a loaded scene, bounded in size.
void exercise(const Scene& scene, std::FILE* sink) {
  double count = 0.0;
  for (const ParticleSet& set : scene.particles) {
    count += set.placement == PlacementKind::lattice ? static_cast<double>(set.lattice[0]) * set.lattice[1] * set.lattice[2]
             : set.placement == PlacementKind::random ? set.count
                                                      : 1.0;
  }
  if (count > 50000.0) return;  // a mutant that asks for millions of particles is valid, just slow
  const Particles particles = generate_particles(scene);
  print_scene_check(scene, particles, sink);
}

// Returns the number of mutants that loaded.
int fuzz(const std::string& sample, int mutants, std::uint64_t seed, std::chrono::seconds budget) {
  const std::string text = file_contents(std::string(FDEM_SOURCE_DIR) + "/" + sample);
  std::mt19937_64 rng(seed);
  std::FILE* sink = std::fopen("/dev/null", "w");
  const auto start = std::chrono::steady_clock::now();
  int loaded = 0;
  for (int i = 0; i < mutants && std::chrono::steady_clock::now() - start < budget; ++i) {
    std::string mutant = text;
    for (int k = static_cast<int>(1 + rng() % 3); k > 0; --k) mutant = mutate(mutant, rng);
    try {
      const Scene scene = load_scene_from_string(mutant, "fuzz.yaml", kExamples);
      ++loaded;
      exercise(scene, sink);
    } catch (const InputError&) {
      // a clean refusal
    } catch (const std::exception& e) {
      std::fclose(sink);
      ADD_FAILURE() << sample << " mutant " << i << " threw " << e.what() << " instead of InputError:\n" << mutant;
      return loaded;
    }
  }
  std::fclose(sink);
  return loaded;
}

class SceneFuzz : public ::testing::TestWithParam<const char*> {};

TEST_P(SceneFuzz, EveryMutantLoadsOrIsACleanInputError) {
  // 1500 mutants per sample take 1-5 s in a release build; the 10 s cap bounds a sanitizer build.
  const int loaded = fuzz(GetParam(), 1500, 0x5eed0000u + std::filesystem::path(GetParam()).filename().string().size(), std::chrono::seconds(10));
  // Some mutants (comment edits, equivalent re-indents) stay valid: the fuzzer
  // reaches past the parser into validation and generation.
  EXPECT_GT(loaded, 0);
  std::printf("%s: %d mutants loaded as valid scenes, the rest refused cleanly\n", GetParam(), loaded);
}

INSTANTIATE_TEST_SUITE_P(Samples, SceneFuzz,
                         ::testing::Values("examples/dry_drop.yaml", "verification/settling/settling.yaml",
                                           "verification/channel/channel.yaml", "verification/plume/plume.yaml"),
                         [](const auto& param_info) { return std::filesystem::path(param_info.param).stem().string(); });

TEST(SceneFuzz, PathologicalInputsAreCleanErrors) {
  const std::string deep_list = std::string(100000, '[') + std::string(100000, ']');
  const std::string deep_map = [] {
    std::string s;
    for (int i = 0; i < 5000; ++i) s += "{a: ";
    return s + "1" + std::string(5000, '}');
  }();
  const std::string nul_bytes("title: a\0b\ndomain: 1\n", 21);
  const std::string inputs[] = {
      "",                                   // empty
      "# only a comment\n",                 //
      "\xEF\xBB\xBF" "title: bom\n",        // byte-order mark
      "just a scalar",                      //
      "- a\n- list\n",                      //
      deep_list,                            // recursion depth
      deep_map,                             //
      nul_bytes,                            //
      "a: &x [*x]\n",                       // self-referencing alias
      "domain: &d {lower: [0,0,0], upper: [1,1,1]}\nmesh: *d\n",
      "\t\ttitle: tabs\n",                  //
      "title: " + std::string(1 << 20, 'x') + "\n",  // a 1 MiB line
      "? [complex, key]\n: 1\n",           // non-scalar key
      "!!map {title: x}\n",                 //
      "%YAML 1.2\n---\ntitle: a\n---\ntitle: b\n",   // two documents
  };
  for (const std::string& input : inputs) {
    try {
      (void)load_scene_from_string(input, "pathological.yaml", kExamples);
      ADD_FAILURE() << "accepted: " << input.substr(0, 80);
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), "pathological.yaml");
    } catch (const std::exception& e) {
      ADD_FAILURE() << "threw " << e.what() << " for: " << input.substr(0, 80);
    }
  }
}

}  // namespace
}  // namespace fdem::scene_fuzz_test
