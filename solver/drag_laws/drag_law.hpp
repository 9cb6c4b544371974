#pragma once
// What a drag law is to the solver: a closure for the force coefficient K of
//   f_D = V_p K (u - v),  V_p = pi d^3 / 6                              (Eq. 11)
// split in two by what changes when. Over a fluid step the porosity eps, the
// diameter d and the fluid are frozen, so a law folds everything that
// depends on them alone into four per-particle coefficients once a step
// (fold); in every DEM subcycle it turns those and the squared slip speed
// |u - v|^2 into c = V_p K (coefficient). Both work on blocks of eight
// particles, so the subcycle kernel (drag_kernel.hpp) vectorises them; the
// scalar force_coefficient() of coupling/drag.hpp runs the same two
// functions on a one-particle block, so each formula is written once, in its
// law's file. A law may also give the kernel a subcycle_coefficients, the
// same formula for a group of blocks, evaluated faster within a bound its
// file states and a test checks (ergun_wen_yu.hpp: the power in single
// precision and from a lane's reference by a series, within 2.04e-7).
// The laws and their names are listed in drag_law_table.cpp.
#include <array>
#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace fdem {

/// Fluid properties the closures need.
struct FluidProperties {
  double density = 1000.0;    // rho_f [kg/m^3]
  double viscosity = 1.0e-3;  // mu_f [Pa s]
};

/// Particles per block: the widest vector of doubles (AVX-512), so no lane of
/// a block is ever left to scalar code.
inline constexpr std::size_t drag_block_size = 8;
using DragLanes = std::array<double, drag_block_size>;
/// Blocks the subcycle kernel hands a law at once (drag_kernel.hpp), so a
/// long per-lane polynomial (Wen & Yu's power) runs for all of them in one
/// stretch of code, where the core overlaps their latency chains.
inline constexpr std::size_t drag_group_size = 16;
using DragGroupLanes = std::array<DragLanes, drag_group_size>;

/// A law's per-step coefficients of one block; their meaning is the law's
/// (its file says). Lanes without drag (outside the mesh, padding) must give c = 0.
struct alignas(64) FoldedDrag {
  std::array<DragLanes, 4> k;
};

/// Frozen over a fluid step, then the step's drag sums: eight particles a
/// block, all their data in eleven consecutive cache lines (aligned, so the
/// vector loops need no peeling).
struct alignas(64) DragBlock {
  DragLanes ux, uy, uz;           // fluid velocity at the particle [m/s]
  FoldedDrag folded;              // the law's per-step coefficients
  DragLanes sum_x, sum_y, sum_z;  // drag summed over the subcycles [N]
  /// What a law's subcycle_coefficients keeps of a lane from one subcycle
  /// to the next within the fluid step, two floats a lane in one cache
  /// line, zero at the step's start (ergun_wen_yu.hpp: the reference of
  /// its power).
  std::array<std::array<float, drag_block_size>, 2> memory;
};
static_assert(sizeof(DragBlock) == 11 * 64, "a block's data: eleven cache lines");

/// One subcycle's drag over all blocks (drag_kernel.hpp).
struct DragSubcycle {
  std::span<DragBlock> blocks;
  std::size_t particles = 0;
  std::span<const double> vx, vy, vz;  // particle velocities [m/s]
  std::span<double> fx, fy, fz;        // forces the drag is added to; empty: not applied (particle_to_fluid)
};

/// One registered drag law: a row of drag_law_table.cpp.
struct DragLawEntry {
  std::string_view name;  // the scene's effects.drag
  std::string_view doc;   // one line: the closure and its source
  /// Per fluid step: eps (0 where a lane has no fluid: outside the mesh or
  /// padding) and d [m] of a block to its folded coefficients.
  void (*fold)(const DragLanes& porosity, const DragLanes& diameter, const FluidProperties& fluid, FoldedDrag& out);
  /// Per subcycle: squared slip speeds [m^2/s^2] to c = V_p K [kg/s].
  void (*coefficient)(const FoldedDrag& folded, const DragLanes& slip_squared, DragLanes& c);
  /// The subcycle kernel compiled for this law (drag_kernel.hpp).
  void (*subcycle)(const DragSubcycle& step);
  /// How far (relative) the kernel's c may be from coefficient()'s: the
  /// bound of the law's faster subcycle_coefficients, 0 when the kernel
  /// evaluates the law as written (then only rounding separates them).
  double subcycle_error = 0.0;
};

/// Every registered law, in registration order (the order is the checkpoint
/// fingerprint's code of a law: rows are only ever appended).
std::span<const DragLawEntry> drag_laws();
/// The law of that name, or nullptr.
const DragLawEntry* find_drag_law(std::string_view name);
/// The law of that name; throws std::invalid_argument naming the known laws.
const DragLawEntry& drag_law(std::string_view name);
/// The law's position in the table.
std::size_t drag_law_index(const DragLawEntry& law);
/// "ergun_wen_yu, stokes, ..." for messages.
std::string drag_law_names();

}  // namespace fdem
