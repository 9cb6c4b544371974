// Output writers: atomic files survive a kill mid-write; VTU/PVD read back by
// two readers written apart from fdem (vtk_check.py: xml.etree + zlib from
// VTK's format description; meshio_dump.py: Debian's meshio) with the counts
// and the exact values written, binary and ASCII; CSV series; progress lines.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <span>
#include <sstream>
#include <thread>

#include "core/error.hpp"
#include "io/atomic_file.hpp"
#include "io/csv_series.hpp"
#include "io/progress.hpp"
#include "io/pvd_writer.hpp"
#include "io/tests/scratch_files.hpp"
#include "io/vtu_writer.hpp"

namespace fdem {
namespace {

namespace fs = std::filesystem;

// Runs a reader script (vtk_check.py or meshio_dump.py) on a file; returns
// its stdout lines keyed by "section name" for arrays.
struct VtkDump {
  int status = -1;
  std::vector<std::string> datasets;
  std::map<std::string, std::vector<double>> arrays;  // "<section> <name>" of the last file read
  std::vector<std::string> cell_types;                // meshio's cell blocks
  long points = -1, cells = -1;
};

VtkDump read_back(const char* script, const fs::path& file) {
  VtkDump dump;
  const fs::path out = file.parent_path() / "read_back.out";
  const std::string command = std::string(FDEM_PYTHON) + " " + FDEM_SOURCE_DIR + "/solver/io/tests/" + script + " " +
                              file.string() + " > " + out.string();
  dump.status = std::system(command.c_str());
  std::ifstream in(out);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string kind;
    s >> kind;
    if (kind == "dataset") {
      std::string time, name;
      s >> time >> name;
      dump.datasets.push_back(time + " " + name);
    } else if (kind == "piece") {
      std::string path, word;
      s >> path >> word >> dump.points >> word >> dump.cells;
    } else if (kind == "array") {
      std::string path, section, name;
      int components = 0;
      s >> path >> section >> name >> components;
      std::vector<double> v;
      for (double x; s >> x;) v.push_back(x);
      dump.arrays[section + " " + name] = v;
    } else if (kind == "celltype") {
      std::string path, type;
      s >> path >> type;
      dump.cell_types.push_back(type);
    }
  }
  return dump;
}

VtkDump vtk_check(const fs::path& file) { return read_back("vtk_check.py", file); }
VtkDump meshio_read(const fs::path& file) { return read_back("meshio_dump.py", file); }

TEST(AtomicFile, WritesExactContentAndLeavesNoTemporary) {
  const fs::path dir = fresh_test_directory("test_io", "atomic");
  write_file_atomically((dir / "sub" / "a.txt").string(), "first");
  write_file_atomically((dir / "sub" / "a.txt").string(), "second, longer");
  EXPECT_EQ(file_contents(dir / "sub" / "a.txt"), "second, longer");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir / "sub"), fs::directory_iterator()), 1);
  fs::remove_all(dir);
}

TEST(AtomicFile, UnwritablePathIsASolverErrorNamingIt) {
  const fs::path dir = fresh_test_directory("test_io", "atomic_fail");
  write_file_atomically((dir / "file").string(), "x");
  // A path below a regular file cannot be created.
  try {
    write_file_atomically((dir / "file" / "below.vtu").string(), "y");
    FAIL() << "no error";
  } catch (const SolverError& e) {
    EXPECT_NE(std::string(e.what()).find("below.vtu"), std::string::npos);
  }
  fs::remove_all(dir);
}

TEST(AtomicFile, KilledWriterNeverLeavesATruncatedFile) {
  // A child rewrites a 16 MiB file in a loop; SIGKILL at varying moments. The
  // target must always be absent or complete (full size, end marker).
  const fs::path dir = fresh_test_directory("test_io", "atomic_kill");
  const fs::path target = dir / "big.dat";
  std::string content(16u << 20, 'x');
  content.replace(content.size() - 4, 4, "END\n");
  for (int trial = 0; trial < 6; ++trial) {
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      for (;;) write_file_atomically(target.string(), content);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5 + 17 * trial));
    ::kill(child, SIGKILL);
    int status = 0;
    ::waitpid(child, &status, 0);
    if (fs::exists(target)) {
      ASSERT_EQ(fs::file_size(target), content.size()) << "trial " << trial;
      std::ifstream in(target, std::ios::binary);
      in.seekg(-4, std::ios::end);
      std::string tail(4, '\0');
      in.read(tail.data(), 4);
      EXPECT_EQ(tail, "END\n");
    }
  }
  fs::remove_all(dir);
}

Particles three_particles() {
  Particles p;
  p.x = {0.1, 0.2, 1.0 / 3.0};
  p.y = {0.0, -0.5, 2.0e-7};
  p.z = {1.0, 1.5, 0.123456789012345};
  p.vx = {0.01, 0.02, 0.03};
  p.vy = {0.0, 0.0, -1e-300};
  p.vz = {-0.1, -0.2, -0.3};
  p.fx = {1.0, 2.0, 3.0};
  p.fy = {4.0, 5.0, 6.0};
  p.fz = {7.0, 8.0, 9.0};
  p.diameter = {2.08e-4, 7.6e-4, 3.09e-4};
  p.mass = {1e-8, 2e-7, 3e-8};
  return p;
}

TEST(VtuWriter, ParticlesReadBackWithExactValues) {
  const fs::path dir = fresh_test_directory("test_io", "vtu_particles");
  const Particles p = three_particles();
  write_particles_vtu((dir / "p.vtu").string(), p, 0.25);
  const VtkDump d = vtk_check(dir / "p.vtu");
  ASSERT_EQ(d.status, 0);
  EXPECT_EQ(d.points, 3);
  EXPECT_EQ(d.cells, 3);
  // Shortest round-trip decimals: the values come back bit for bit.
  EXPECT_EQ(d.arrays.at("PointData diameter"), std::vector<double>(p.diameter.begin(), p.diameter.end()));
  EXPECT_EQ(d.arrays.at("PointData velocity"),
            (std::vector<double>{0.01, 0.0, -0.1, 0.02, 0.0, -0.2, 0.03, -1e-300, -0.3}));
  EXPECT_EQ(d.arrays.at("PointData force"), (std::vector<double>{1, 4, 7, 2, 5, 8, 3, 6, 9}));
  EXPECT_EQ(d.arrays.at("Points Points"),
            (std::vector<double>{0.1, 0.0, 1.0, 0.2, -0.5, 1.5, 1.0 / 3.0, 2.0e-7, 0.123456789012345}));
  EXPECT_EQ(d.arrays.at("FieldData TimeValue"), std::vector<double>{0.25});
  fs::remove_all(dir);
}

// n grains with values of every magnitude a run holds (positions in a 0.1 m
// box, velocities of mm/s, forces of uN), drawn from a fixed seed.
Particles random_particles(std::size_t n) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Particles p;
  for (std::size_t i = 0; i < n; ++i) {
    p.x.push_back(0.1 * unit(rng));
    p.y.push_back(0.1 * unit(rng));
    p.z.push_back(0.2 * unit(rng));
    p.vx.push_back(1e-3 * (unit(rng) - 0.5));
    p.vy.push_back(1e-3 * (unit(rng) - 0.5));
    p.vz.push_back(-0.05 * unit(rng));
    p.fx.push_back(1e-6 * (unit(rng) - 0.5));
    p.fy.push_back(1e-6 * (unit(rng) - 0.5));
    p.fz.push_back(-1e-5 * unit(rng));
    p.diameter.push_back(2e-4 + 4e-4 * unit(rng));
    p.mass.push_back(2650.0 * sphere_volume(p.diameter.back()));
  }
  return p;
}

std::vector<double> interleave(std::span<const double> x, std::span<const double> y, std::span<const double> z) {
  std::vector<double> out;
  for (std::size_t i = 0; i < x.size(); ++i) out.insert(out.end(), {x[i], y[i], z[i]});
  return out;
}

}  // namespace

// Found by argument-dependent lookup, so it lives in VtuEncoding's namespace.
void PrintTo(VtuEncoding encoding, std::ostream* os) { *os << (encoding == VtuEncoding::binary ? "binary" : "ascii"); }

namespace {

class VtuEncodings : public ::testing::TestWithParam<VtuEncoding> {};

TEST_P(VtuEncodings, ParticlesReadBackByMeshioWithTheValuesWritten) {
  // 4096 grains: each scalar array is exactly one full 32 KiB block, each
  // vector three (the header's partial-block size is 0); 5000 would end in a
  // partial block, which the mesh test below covers.
  const fs::path dir = fresh_test_directory("test_io", "meshio_particles");
  const Particles p = random_particles(4096);
  write_particles_vtu((dir / "p.vtu").string(), p, 0.125, GetParam());
  const std::string text = file_contents(dir / "p.vtu");
  const bool binary = GetParam() == VtuEncoding::binary;
  EXPECT_EQ(text.find("format=\"appended\"") != std::string::npos, binary);
  EXPECT_EQ(text.find("compressor=\"vtkZLibDataCompressor\"") != std::string::npos, binary);
  for (const VtkDump& d : {meshio_read(dir / "p.vtu"), vtk_check(dir / "p.vtu")}) {
    ASSERT_EQ(d.status, 0);
    EXPECT_EQ(d.points, 4096);
    EXPECT_EQ(d.cells, 4096);
    // Equal doubles: the binary values are the bytes in memory, the ASCII ones
    // shortest round-trip decimals; either way nothing is lost.
    EXPECT_EQ(d.arrays.at("PointData diameter"), std::vector<double>(p.diameter.begin(), p.diameter.end()));
    EXPECT_EQ(d.arrays.at("PointData mass"), std::vector<double>(p.mass.begin(), p.mass.end()));
    EXPECT_EQ(d.arrays.at("PointData velocity"), interleave(p.vx, p.vy, p.vz));
    EXPECT_EQ(d.arrays.at("PointData force"), interleave(p.fx, p.fy, p.fz));
    EXPECT_EQ(d.arrays.at("Points Points"), interleave(p.x, p.y, p.z));
    const auto& conn = d.arrays.at("Cells connectivity");
    ASSERT_EQ(conn.size(), 4096u);
    for (std::size_t i = 0; i < conn.size(); ++i) ASSERT_EQ(conn[i], static_cast<double>(i));
  }
  const VtkDump m = meshio_read(dir / "p.vtu");
  EXPECT_EQ(m.cell_types, std::vector<std::string>{"vertex"});
  EXPECT_EQ(m.arrays.at("FieldData TimeValue"), std::vector<double>{0.125});
  fs::remove_all(dir);
}

TEST_P(VtuEncodings, MeshReadsBackByMeshioWithTheValuesWritten) {
  // 6 x 5 x 4 cells: 600 tetrahedra, so connectivity is 19200 bytes and the
  // 210 nodes' vectors 5040: one partial block each. Every field and the
  // connectivity, through meshio and VTK, in both encodings.
  const fs::path dir = fresh_test_directory("test_io", "meshio_mesh");
  const BoxMesh mesh(Vec3(0, 0, 0), Vec3(0.06, 0.05, 0.04), {6, 5, 4});
  const auto nodes = static_cast<std::size_t>(mesh.num_nodes());
  const auto elements = static_cast<std::size_t>(mesh.num_elements());
  std::vector<double> velocity(3 * nodes), pressure(nodes), source(3 * nodes), porosity(elements);
  for (std::size_t n = 0; n < nodes; ++n) {
    const Vec3 x = mesh.node(static_cast<Index>(n));
    velocity[3 * n] = std::sin(40.0 * x.z());
    velocity[3 * n + 2] = -1e-3 * x.x();
    pressure[n] = 9.81e3 * (0.04 - x.z()) + 1.0 / 3.0;
    source[3 * n + 2] = -std::exp(-x.squaredNorm() / 1e-3);
  }
  for (std::size_t e = 0; e < elements; ++e) porosity[e] = 1.0 - 1e-3 * std::sqrt(static_cast<double>(e));
  const std::vector<Field> point_data{Field::vector_interleaved("velocity", velocity), Field::scalar("pressure", pressure),
                                      Field::vector_interleaved("source_term", source)};
  const std::vector<Field> cell_data{Field::scalar("porosity", porosity)};
  write_mesh_vtu((dir / "m.vtu").string(), mesh, point_data, cell_data, 2.5, GetParam());
  for (const VtkDump& d : {meshio_read(dir / "m.vtu"), vtk_check(dir / "m.vtu")}) {
    ASSERT_EQ(d.status, 0);
    EXPECT_EQ(d.points, 210);  // 7 x 6 x 5 nodes
    EXPECT_EQ(d.cells, 600);
    EXPECT_EQ(d.arrays.at("PointData velocity"), velocity);
    EXPECT_EQ(d.arrays.at("PointData pressure"), pressure);
    EXPECT_EQ(d.arrays.at("PointData source_term"), source);
    EXPECT_EQ(d.arrays.at("CellData porosity"), porosity);
    const auto& conn = d.arrays.at("Cells connectivity");
    ASSERT_EQ(conn.size(), 4 * elements);
    for (std::size_t e = 0; e < elements; ++e) {
      for (std::size_t a = 0; a < 4; ++a) ASSERT_EQ(conn[4 * e + a], mesh.element_nodes(static_cast<Index>(e))[a]);
    }
  }
  EXPECT_EQ(meshio_read(dir / "m.vtu").cell_types, std::vector<std::string>{"tetra"});
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(BinaryAndAscii, VtuEncodings, ::testing::Values(VtuEncoding::binary, VtuEncoding::ascii),
                         [](const auto& encoding) { return encoding.param == VtuEncoding::binary ? "binary" : "ascii"; });

TEST(VtuWriter, BinarySnapshotIsUnderFourTenthsOfTheAsciiOne) {
  // Random doubles hardly compress (their low mantissa bits are noise), so the
  // gain is 8 bytes a value against ~22 characters, plus the index arrays,
  // which zlib shrinks ~100x. Measured: 358298 / 1038625 bytes = 0.345.
  const Particles p = random_particles(4096);
  const double binary = static_cast<double>(particles_vtu(p, 0.0, VtuEncoding::binary).size());
  const double ascii = static_cast<double>(particles_vtu(p, 0.0, VtuEncoding::ascii).size());
  EXPECT_LT(binary / ascii, 0.4) << binary << " vs " << ascii << " bytes";
}

TEST(VtuWriter, FieldOfWrongSizeIsRefusedNamingIt) {
  const BoxMesh mesh(Vec3(0, 0, 0), Vec3(1, 1, 1), {1, 1, 1});
  const std::vector<double> short_field(3);
  const std::vector<Field> point_data{Field::scalar("pressure", short_field)};
  try {
    (void)mesh_vtu(mesh, point_data, {}, 0.0);
    FAIL() << "no error";
  } catch (const SolverError& e) {
    EXPECT_NE(std::string(e.what()).find("pressure"), std::string::npos);
  }
}

TEST(PvdWriter, CollectionReadsBackWithEveryDataset) {
  const fs::path dir = fresh_test_directory("test_io", "pvd");
  PvdCollection pvd((dir / "particles.pvd").string());
  const Particles p = three_particles();
  for (int i = 0; i < 3; ++i) {
    const std::string file = "particles_" + std::to_string(i) + ".vtu";
    write_particles_vtu((dir / file).string(), p, 0.1 * i);
    pvd.add(0.1 * i, file);
  }
  const VtkDump d = vtk_check(dir / "particles.pvd");
  ASSERT_EQ(d.status, 0);
  EXPECT_EQ(d.datasets, (std::vector<std::string>{"0 particles_0.vtu", "0.1 particles_1.vtu", "0.2 particles_2.vtu"}));
  pvd.truncate_after(0.15);
  EXPECT_EQ(pvd.entries().size(), 2u);
  fs::remove_all(dir);
}

TEST(VtkCheck, RejectsATruncatedFile) {
  // The reader is what the other tests trust: it must fail on a cut file.
  const fs::path dir = fresh_test_directory("test_io", "vtk_check");
  const std::string full = particles_vtu(three_particles(), 0.0);
  std::ofstream(dir / "cut.vtu") << full.substr(0, full.size() / 2);
  EXPECT_NE(vtk_check(dir / "cut.vtu").status, 0);
  fs::remove_all(dir);
}

TEST(CsvSeries, EveryRowIsInTheFileAsSoonAsItIsAppendedAndRestartCarriesTheEarlierRows) {
  const fs::path dir = fresh_test_directory("test_io", "csv");
  CsvSeries csv((dir / "probes.csv").string(), {"time", "step", "mean_z"});
  EXPECT_EQ(file_contents(dir / "probes.csv"), "time,step,mean_z\n");
  const std::vector<std::vector<double>> rows{{0.0, 0, 0.07}, {0.01, 1, 0.0699}, {0.02, 2, 0.0697}};
  csv.append(rows[0]);
  EXPECT_EQ(file_contents(dir / "probes.csv"), "time,step,mean_z\n0,0,0.07\n");
  for (std::size_t r = 1; r < rows.size(); ++r) csv.append(rows[r]);
  EXPECT_EQ(file_contents(dir / "probes.csv"), "time,step,mean_z\n0,0,0.07\n0.01,1,0.0699\n0.02,2,0.0697\n");
  EXPECT_THROW(csv.append(std::vector<double>{1.0}), SolverError);
  // A resumed run at step 2 takes rows 0 and 1; a cut last line is never carried.
  std::ofstream(dir / "old.csv", std::ios::app) << file_contents(dir / "probes.csv") << "0.03,3,0.06";
  CsvSeries resumed((dir / "resumed.csv").string(), {"time", "step", "mean_z"});
  EXPECT_EQ(resumed.carry_rows((dir / "old.csv").string(), "step", 2.0), 2);
  EXPECT_EQ(file_contents(dir / "resumed.csv"), "time,step,mean_z\n0,0,0.07\n0.01,1,0.0699\n");
  CsvSeries other((dir / "other.csv").string(), {"time", "step", "max_z"});
  EXPECT_EQ(other.carry_rows((dir / "old.csv").string(), "step", 2.0), -1);  // other columns: nothing
  fs::remove_all(dir);
}

TEST(Progress, LineNamesStepTimeRateAndTimeLeft) {
  EXPECT_EQ(format_progress(1200, 0.012, 1.0, 340.0, 291.0),
            "step 1200  t = 0.012 s of 1 s (1.2%)  340 steps/s  left 0:04:51");
  EXPECT_EQ(format_duration(3725.0), "1:02:05");
  EXPECT_EQ(format_progress(1, 0.0, 1.0, 0.0, -1.0).substr(0, 6), "step 1");
}

TEST(Progress, LogModePrintsPlainLinesAtTheWallCadence) {
  std::FILE* out = std::tmpfile();
  ProgressReporter progress(out, 1.0, false, 10.0);
  // Constant cost: 100 steps and 0.01 s simulated per wall second.
  for (int s = 0; s <= 25; ++s) progress.update_at(100 * s, 0.01 * s, static_cast<double>(s));
  EXPECT_EQ(progress.lines_printed(), 2);  // at 10 s and 20 s of wall time
  EXPECT_NEAR(progress.steps_per_second(), 100.0, 1e-9);
  EXPECT_NEAR(progress.eta_seconds(), 80.0, 1e-9);  // (1 - 0.2) s left at 0.01 s per wall second
  progress.finish_at(2500, 0.25, 25.0);
  std::rewind(out);
  std::string text(4096, '\0');
  text.resize(std::fread(text.data(), 1, text.size(), out));
  std::fclose(out);
  EXPECT_EQ(text.find('\r'), std::string::npos);
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 3);
}

TEST(Progress, TerminalModeRewritesOneLine) {
  std::FILE* out = std::tmpfile();
  ProgressReporter progress(out, 1.0, true);
  for (int s = 0; s <= 10; ++s) progress.update_at(s, 0.1 * s, 0.3 * s);
  progress.finish_at(10, 1.0, 3.0);
  std::rewind(out);
  std::string text(4096, '\0');
  text.resize(std::fread(text.data(), 1, text.size(), out));
  std::fclose(out);
  EXPECT_GE(std::count(text.begin(), text.end(), '\r'), 10);
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1);  // only the final line ends
  EXPECT_EQ(text.back(), '\n');
}

}  // namespace
}  // namespace fdem
