// A fluid mesh whose linear system a 32-bit sparse index cannot address is
// refused before anything is allocated, naming mesh.cells; the counts behind
// the refusal are computed in 64 bits from the cell counts alone, and agree
// with the meshes actually built.
#include <gtest/gtest.h>

#include <sys/resource.h>

#include <algorithm>
#include <set>
#include <utility>

#include "core/error.hpp"
#include "fluid/fluid_solver.hpp"
#include "fluid/fluid_system_size.hpp"
#include "hard_scenes.hpp"
#include "mesh/box_mesh.hpp"
#include "mesh/box_mesh_size.hpp"
#include "run_scenes.hpp"
#include "test_support.hpp"

namespace fdem {
namespace {

namespace fs = std::filesystem;

TEST(IndexLimits, ClosedFormCountsEqualTheBuiltMeshesEdgesAndNodes) {
  for (const std::array<int, 3> cells : {std::array<int, 3>{1, 1, 1}, {2, 3, 4}, {5, 1, 2}, {4, 4, 4}}) {
    const BoxMesh mesh(Vec3::Zero(), Vec3(1.0, 1.0, 1.0), cells);
    std::set<std::pair<Index, Index>> edges;
    for (Index e = 0; e < mesh.num_elements(); ++e) {
      const auto& nodes = mesh.element_nodes(e);
      for (std::size_t a = 0; a < 4; ++a)
        for (std::size_t b = a + 1; b < 4; ++b) edges.emplace(std::minmax(nodes[a], nodes[b]));
    }
    const BoxMeshSize size = box_mesh_size(cells);
    EXPECT_EQ(size.nodes, mesh.num_nodes());
    EXPECT_EQ(size.elements, mesh.num_elements());
    EXPECT_EQ(size.edges, static_cast<std::int64_t>(edges.size())) << cells[0] << "x" << cells[1] << "x" << cells[2];
  }
}

TEST(IndexLimits, RefusalSitsExactlyAtTheLastIndexableMesh) {
  // A 200 x 200 x nz column: find the nz where the ILUT factors (fill factor 4)
  // pass 2^31 - 1 entries; nz is accepted, nz + 1 refused, both without a mesh.
  constexpr int fill = FluidSolverOptions{}.ilut_fill_factor;
  int nz = 1;
  while (fluid_system_size({200, 200, nz + 1}, fill).factor_nonzeros <= kMaxSparseEntries) ++nz;
  ASSERT_GT(nz, 10);
  EXPECT_LE(fluid_system_size({200, 200, nz}, fill).factor_nonzeros, kMaxSparseEntries);
  EXPECT_NO_THROW(require_indexable_fluid_system({200, 200, nz}, fill, "scene.yaml"));
  try {
    require_indexable_fluid_system({200, 200, nz + 1}, fill, "scene.yaml");
    ADD_FAILURE() << "200 x 200 x " << nz + 1 << " must be refused";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "mesh.cells");
    EXPECT_NE(std::string(e.what()).find("32-bit"), std::string::npos) << e.what();
  }
  // A 220 x 220 x 400 box (1e8 tetrahedra): 4.0e9 non-zeros, over 2^31 even without fill.
  EXPECT_GT(fluid_system_size({220, 220, 400}, 1).nonzeros, kMaxSparseEntries);
}

TEST(IndexLimits, FluidSolverRefusesAnUnindexableMeshBeforeBuildingItsSystem) {
  // The guard in FluidSolver itself, for scenes built in code: a fill factor
  // that puts a small mesh over the limit is refused at construction.
  Scene scene = hard::water_box(8, 8, 8, 1e-3);
  const BoxMesh mesh(scene.domain.lower, scene.domain.upper, scene.cells);
  FluidSolverOptions options;
  options.ilut_fill_factor = 1 << 20;  // 1e6 x 75k non-zeros > 2^31
  EXPECT_THROW(FluidSolver(mesh, scene, options), InputError);
}

TEST(IndexLimits, FdemCheckAndRunRefuseTheLargeMeshWithExitCode2AndAlmostNoMemory) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer reserves terabytes of address space for its shadow memory, so an address-space cap "
                  "(RLIMIT_AS) cannot be applied; the Release build runs this case";
#endif
  // Before: `check` called it valid and `run` faulted (SIGSEGV) after 69 s at 10 GiB.
  const fs::path dir = hard::scratch_dir("index_limit_cli");
  hard::write_text(dir / "scene.yaml", hard::still_water_yaml("[0.22, 0.22, 0.4]", "[220, 220, 400]", 0.01));
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"check", (dir / "scene.yaml").string()},
        std::vector<std::string>{"run", (dir / "scene.yaml").string(), "-o", (dir / "out").string(), "-q"}}) {
    // A 1 GiB address-space cap: a build that allocates the mesh fails fast instead of filling the machine.
    rusage usage{};
    const int code = hard::run_fdem_limited(args, dir, RLIMIT_AS, rlim_t{1} << 30, &usage);
    const std::string err = hard::read_text(dir / "stderr.txt");
    EXPECT_EQ(code, 2) << args[0] << ": " << err;
    EXPECT_NE(err.find("mesh.cells"), std::string::npos) << err;
    EXPECT_NE(err.find("32-bit"), std::string::npos) << err;
    EXPECT_LT(usage.ru_maxrss, 200 * 1024) << args[0] << ": peak RSS [KiB] of a refusal before allocating";
  }
}

}  // namespace
}  // namespace fdem
