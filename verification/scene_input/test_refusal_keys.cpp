// Every refusal names a key that exists. Three walks, each against the schema
// (scene/scene_schema.hpp): (1) the loader accepts exactly the schema's keys
// in every map (probed with an unknown key, whose refusal lists the valid
// ones); (2) every key a message in the loader's and the stability check's
// sources names, dotted (`contact.kn`) or relative to its map (`m.fail("kn",
// ...)`); (3) every refusal of the scenes in bad/, as `fdem check` produces
// it (load, generate, stability), names in its key and its text only keys of
// the schema.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "app/check_command.hpp"
#include "core/error.hpp"
#include "drag_laws/drag_law.hpp"
#include "io/tests/scratch_files.hpp"
#include "scene/scene_loader.hpp"
#include "scene/scene_schema.hpp"
#include "scene/tests/every_key_scene.hpp"

namespace fdem {
namespace {

namespace fs = std::filesystem;

const fs::path kSource = FDEM_SOURCE_DIR;

using scene_test::kEveryKeyScene;

// The YAML node of the map at a schema path in kEveryKeyScene (list items: the first;
// `<face>`: x_min).
YAML::Node map_at(YAML::Node root, const std::string& path) {
  YAML::Node node = root;
  std::stringstream parts(path);
  for (std::string part; std::getline(parts, part, '.');) {
    if (part == "<face>") part = "x_min";
    const bool item = part.size() > 2 && part.ends_with("[]");
    if (item) part.resize(part.size() - 2);
    node.reset(node[part]);
    if (item) node.reset(node[0]);
  }
  return node;
}

std::set<std::string> valid_list_of(const std::string& message) {
  const std::size_t at = message.find("(valid: ");
  if (at == std::string::npos) return {};
  const std::string list = message.substr(at + 8, message.rfind(')') - at - 8);
  std::set<std::string> out;
  std::stringstream s(list);
  for (std::string k; std::getline(s, k, ',');) out.insert(k.substr(k.find_first_not_of(' ')));
  return out;
}

TEST(SceneSchema, LoaderAcceptsExactlyTheSchemaKeysInEveryMap) {
  ASSERT_NO_THROW((void)load_scene_from_string(kEveryKeyScene, "every_map.yaml"));
  std::vector<std::string> maps{""};
  for (const SceneKey& k : scene_schema()) {
    if (k.is_map) maps.emplace_back(k.path);
  }
  for (const std::string& path : maps) {
    YAML::Node root = YAML::Load(kEveryKeyScene);
    YAML::Node map = map_at(root, path);
    ASSERT_TRUE(map.IsMap()) << path << " is not a map in the probe scene";
    map["zz_not_a_key"] = 1;
    YAML::Emitter text;
    text << root;
    try {
      (void)load_scene_from_string(text.c_str(), "probe.yaml");
      ADD_FAILURE() << "an unknown key in '" << path << "' was accepted";
    } catch (const InputError& e) {
      const std::vector<std::string> below = scene_keys_below(path);
      EXPECT_EQ(valid_list_of(e.what()), std::set<std::string>(below.begin(), below.end()))
          << "map '" << path << "': the loader's keys (left) differ from solver/scene/scene_schema.cpp (right): "
          << e.what();
    }
  }
}

TEST(SceneSchema, FdemHelpScenePrintsEveryKeyWithTypeAndDefault) {
  std::FILE* pipe = ::popen((std::string(FDEM_EXE) + " help scene").c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string text;
  char buffer[4096];
  for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;) text.append(buffer, n);
  EXPECT_EQ(::pclose(pipe), 0);
  for (const SceneKey& k : scene_schema()) {
    const std::string line = fmt::format("\n{}  ({}; default: {})\n", k.path, k.type, k.default_value);
    EXPECT_NE(text.find(line), std::string::npos) << "missing: " << line;
    if (!k.doc.empty()) {
      EXPECT_NE(text.find(line + "    " + std::string(k.doc) + "\n"), std::string::npos) << k.path;
    }
  }
  EXPECT_NE(text.find("\ncontact.kn  (number > 0; default: required with particles and normal contact)\n"
                      "    normal stiffness Kn [N/m]\n"),
            std::string::npos);
}

TEST(SceneSchema, PathsAsMessagesWriteThem) {
  EXPECT_EQ(schema_path_of("particles[2].size.min"), "particles[].size.min");
  EXPECT_EQ(schema_path_of("fluid.boundaries.x_min.velocity"), "fluid.boundaries.<face>.velocity");
  EXPECT_EQ(schema_path_of("fluid.boundaries.z_max"), "fluid.boundaries.z_max");
  EXPECT_TRUE(is_scene_key("contact.kn"));
  EXPECT_TRUE(is_scene_key("particles[0].lattice"));
  EXPECT_FALSE(is_scene_key("contact.normal_stiffness"));  // the field's name in ContactSpec, not a key
  EXPECT_FALSE(is_scene_key("particles[0].sizes"));
}

// Dotted keys inside the string literals of a source file: a top-level
// section, then one or more `.name` (file names such as particles.pvd are not keys).
std::vector<std::string> dotted_keys_in(const std::string& source) {
  std::string sections;
  for (const std::string& top : scene_keys_below("")) sections += (sections.empty() ? "" : "|") + top;
  const std::regex literal(R"lit("((?:[^"\\\n]|\\.)*)")lit");
  const std::regex key("\\b(?:" + sections + ")(?:\\[\\d*\\])?(?:\\.[a-z_]+(?:\\[\\d*\\])?)+");
  const std::regex file_name(R"(\.(hpp|cpp|md|csv|pvd|vtu|yaml|bin|json)$)");
  std::vector<std::string> out;
  std::stringstream lines(source);
  for (std::string line; std::getline(lines, line);) {
    if (line.starts_with("#include")) continue;
    for (std::sregex_iterator l(line.begin(), line.end(), literal), end; l != end; ++l) {
      const std::string text = (*l)[1];
      for (std::sregex_iterator k(text.begin(), text.end(), key); k != end; ++k) {
        if (!std::regex_search(k->str(), file_name)) out.push_back(k->str());
      }
    }
  }
  return out;
}

// The sources whose messages a scene's refusal can print.
const char* const kMessageSources[] = {"solver/scene/scene_loader.cpp", "solver/scene/particle_generator.cpp",
                                       "solver/scene/particle_csv.cpp", "solver/scene/stability.cpp",
                                       "solver/app/check_command.cpp"};

TEST(RefusalKeys, EveryDottedKeyInTheLoaderAndStabilityMessagesExists) {
  std::size_t checked = 0;
  for (const char* file : kMessageSources) {
    for (const std::string& k : dotted_keys_in(file_contents(kSource / file))) {
      EXPECT_TRUE(is_scene_key(k)) << file << " names '" << k << "', which is not a scene key";
      ++checked;
    }
  }
  // The walk must see the messages it checks (mesh.cells, time.dem_step, contact.kn, ...).
  EXPECT_GE(checked, 20u);
}

TEST(RefusalKeys, EveryKeyTheLoaderNamesRelativeToItsMapExists) {
  // m.fail("kn", ...), m.require(ok, "kn", ...), m.number("kn") ...: the key is
  // relative to the map being read, so it must be the last part of some key.
  std::set<std::string> leaves;
  for (const SceneKey& k : scene_schema()) {
    const std::string path(k.path);
    leaves.insert(path.substr(path.find_last_of(".]") == std::string::npos ? 0 : path.find_last_of(".]") + 1));
  }
  const std::string source = file_contents(kSource / "solver/scene/scene_loader.cpp");
  const std::regex call(
      R"(\b(?:fail|missing|number|integer|boolean|text|vec3|has|node|choice<\w+>)\(\s*"([a-z_]+)\")");
  const std::regex require(R"(\brequire\([^;]*?,\s*"([a-z_]+)\",)");
  std::size_t checked = 0;
  for (const std::regex* r : {&call, &require}) {
    for (std::sregex_iterator m(source.begin(), source.end(), *r), end; m != end; ++m) {
      EXPECT_TRUE(leaves.count((*m)[1])) << "scene_loader.cpp reads or refuses '" << (*m)[1]
                                         << "', which is no key of any map";
      ++checked;
    }
  }
  EXPECT_GE(checked, 100u);
}

TEST(RefusalKeys, EveryBadSceneIsRefusedNamingOnlyKeysThatExist) {
  const std::set<std::string> pseudo_keys{"(syntax)", "(file)", "(document)"};
  std::size_t refused = 0;
  std::FILE* sink = std::tmpfile();  // fdem check's table
  for (const auto& entry : fs::directory_iterator(kSource / "verification/scene_input/bad")) {
    if (entry.path().extension() != ".yaml") continue;
    try {
      (void)run_check_command(entry.path().string(), sink);
      ADD_FAILURE() << entry.path() << " passed fdem check";
    } catch (const InputError& e) {
      ++refused;
      const std::string message = e.what();
      if (message.find("unknown key") != std::string::npos) {
        // The key is the user's mistake; what the message offers instead must exist.
        const std::size_t dot = e.key().rfind('.');
        const std::string map = dot == std::string::npos ? "" : e.key().substr(0, dot + 1);
        const std::set<std::string> offered = valid_list_of(message);
        EXPECT_FALSE(offered.empty()) << message;
        for (const std::string& k : offered) EXPECT_TRUE(is_scene_key(map + k)) << map + k << ": " << message;
        continue;
      }
      const bool csv_column = e.file().ends_with(".csv");  // a particle file's column, e.g. x,y,z
      EXPECT_TRUE(is_scene_key(e.key()) || pseudo_keys.count(e.key()) || csv_column)
          << entry.path().filename() << ": key '" << e.key() << "' is not a scene key";
      for (const std::string& k : dotted_keys_in('"' + message + '"')) {
        EXPECT_TRUE(is_scene_key(k)) << entry.path().filename() << ": message names '" << k << "': " << message;
      }
    }
  }
  std::fclose(sink);
  EXPECT_GE(refused, 29u);  // every file in bad/ (29 when written)
}

TEST(RefusalKeys, UnstableStepAdviceNamesContactKn) {
  std::FILE* sink = std::tmpfile();
  try {
    (void)run_check_command((kSource / "verification/scene_input/bad/paper_channel_unstable_step.yaml").string(), sink);
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("soften contact.kn"), std::string::npos) << message;
    EXPECT_EQ(message.find("normal_stiffness"), std::string::npos) << message;
  }
  std::fclose(sink);
}

TEST(SceneSchema, ExamplesReadmeDocumentsEveryKey) {
  // Each key's last part appears as a word in the README's section of its
  // top-level key (`### \`contact\``), or in "top level" for the keys whose
  // row there describes them (domain, mesh).
  const std::string readme = file_contents(kSource / "examples/README.md");
  auto section = [&](const std::string& top) {
    const std::string heading = top.empty() ? "### top level" : "### `" + top + "`";
    const std::size_t at = readme.find(heading);
    if (at == std::string::npos) return std::string();
    const std::size_t next = readme.find("\n### ", at + heading.size());
    return readme.substr(at, next == std::string::npos ? std::string::npos : next - at);
  };
  for (const SceneKey& k : scene_schema()) {
    const std::string path(k.path);
    const std::size_t dot = path.find_first_of(".[");
    const std::string top = dot == std::string::npos ? "" : path.substr(0, dot);
    const std::size_t last = path.find_last_of(".]");
    const std::string leaf = last == std::string::npos ? path : path.substr(last + 1);
    if (leaf.empty() || leaf == "<face>") continue;  // the list item and the face map themselves
    std::string text = section(top);
    if (text.empty()) text = section("");
    EXPECT_TRUE(std::regex_search(text, std::regex("\\b" + leaf + "\\b")))
        << "examples/README.md does not document '" << path << "'";
  }
}

TEST(SceneSchema, ExamplesReadmeTablesNameOnlySchemaKeysWithTheSchemasDefaults) {
  // The other direction: every row of the tables under "## Schema" names a key
  // of the schema (`kt`, `ct` rows name two), its default column holds
  // the first word of the schema's default (`bdf2`, **required**, none, ...),
  // and its values column every word the key accepts.
  const std::string readme = file_contents(kSource / "examples/README.md");
  const std::size_t begin = readme.find("\n## Schema");
  ASSERT_NE(begin, std::string::npos);
  const std::string schema_part = readme.substr(begin, readme.find("\n## ", begin + 1) - begin);
  std::stringstream lines(schema_part);
  std::string top = "", line;
  int rows = 0;
  std::size_t words_checked = 0;
  for (std::string l; std::getline(lines, l);) {
    if (l.starts_with("### ")) {
      const std::size_t open = l.find('`');
      top = open == std::string::npos ? "" : l.substr(open + 1, l.find('`', open + 1) - open - 1);
      if (top == "particles") top = "particles[]";
      continue;
    }
    if (!l.starts_with("| `")) continue;
    std::vector<std::string> cells;
    std::stringstream row(l.substr(1));
    for (std::string cell; std::getline(row, cell, '|');) cells.push_back(cell);
    ASSERT_GE(cells.size(), 3u) << l;
    std::stringstream names(cells[0]);
    for (std::string name; std::getline(names, name, ',');) {
      const std::size_t a = name.find('`'), b = name.rfind('`');
      name = name.substr(a + 1, b - a - 1);
      const std::string path = top.empty() ? name : top + "." + name;
      ++rows;
      if (!is_scene_key(path)) {
        ADD_FAILURE() << "examples/README.md documents '" << path << "', which the schema lacks";
        continue;
      }
      for (const SceneKey& k : scene_schema()) {
        if (k.path != path) continue;
        const std::string first(k.default_value.substr(0, k.default_value.find_first_of(" ;(")));
        EXPECT_NE(cells[2].find(first), std::string::npos)
            << "examples/README.md gives '" << path << "' the default '" << cells[2] << "', the schema '"
            << k.default_value << "'";
      }
      // Every word the key accepts (a registered term's: its table's rows) is in the row's values column.
      std::vector<std::string> words;
      for (const std::string_view w : choice_words(path)) words.emplace_back(w);
      if (path == "effects.drag")
        for (const DragLawEntry& law : drag_laws()) words.emplace_back(law.name);
      for (const std::string& w : words)
        EXPECT_NE(cells[1].find("`" + w + "`"), std::string::npos)
            << "examples/README.md's row of '" << path << "' does not list '" << w << "'";
      words_checked += words.size();
    }
  }
  EXPECT_GE(rows, 60) << "rows read from examples/README.md's schema tables";
  EXPECT_GE(words_checked, 28u) << "accepted words checked against examples/README.md (28 when written)";
}

}  // namespace
}  // namespace fdem
