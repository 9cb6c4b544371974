// fdem command line: `fdem run SCENE`, `fdem check SCENE`.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <cstdio>

int main(int argc, char** argv) {
  CLI::App app{"fdem: hybrid FEM-DEM solver for fluid flow laden with many particles"};
  app.set_version_flag("--version", std::string("fdem ") + FDEM_VERSION);
  app.require_subcommand(1);
  CLI11_PARSE(app, argc, argv);
  return 0;
}
