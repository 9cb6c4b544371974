#pragma once
// GrainArray: the storage of one per-grain quantity (a column of Particles, a
// DEM factor). Why not a plain std::vector<double>: the DEM's fused pass
// streams ~24 such arrays at once, and glibc serves every allocation above
// 128 KiB with its own mmap, page-aligned plus 16 bytes. Element i of every
// array then falls in the same L1 set (64 sets of 8 ways on the hosts here:
// the set is the address mod 4 KiB) and in one or two L2 sets, so the
// streams evict each other: scene P's free-falling 28224 grains ran at
// 6.3e7 particle-steps/s against 4.7e8 with the same code and the arrays
// off the page grid (dem_steps, AMD EPYC host, 2026-12-06; benchmarks/README.md).
// So each large array starts at its own cache line within a 4 KiB page:
// successive allocations take line offsets 37 apart modulo 64, which keeps
// any 64 of them on distinct sets. Small arrays (below kStaggerFrom) live
// in the heap at varied addresses anyway and take no padding.
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <new>
#include <vector>

namespace fdem {

template <class T>
struct StaggeredAllocator {
  using value_type = T;
  static constexpr std::size_t kPage = 4096, kLine = 64;
  static constexpr std::size_t kStaggerFrom = 16 * 1024;  // bytes

  StaggeredAllocator() noexcept = default;
  template <class U>
  StaggeredAllocator(const StaggeredAllocator<U>&) noexcept {}  // NOLINT: allocators convert implicitly

  T* allocate(std::size_t n) {
    constexpr auto kLargest = static_cast<std::size_t>(std::numeric_limits<std::ptrdiff_t>::max());
    if (n > (kLargest - kPage) / sizeof(T)) throw std::bad_array_new_length();
    const std::size_t bytes = n * sizeof(T);
    if (bytes < kStaggerFrom) return static_cast<T*>(::operator new(bytes, std::align_val_t{kLine}));
    // A page-aligned block one page longer; the data starts at the next
    // offset, less than a page in, so deallocate finds the block's start by
    // rounding down to the page.
    void* block = ::operator new(bytes + kPage, std::align_val_t{kPage});
    return reinterpret_cast<T*>(static_cast<std::byte*>(block) + next_offset());
  }

  void deallocate(T* data, std::size_t n) noexcept {
    if (n * sizeof(T) < kStaggerFrom) {
      ::operator delete(data, std::align_val_t{kLine});
      return;
    }
    const auto address = reinterpret_cast<std::uintptr_t>(data);
    ::operator delete(reinterpret_cast<void*>(address - address % kPage), std::align_val_t{kPage});
  }

  friend bool operator==(const StaggeredAllocator&, const StaggeredAllocator&) noexcept { return true; }

 private:
  static std::size_t next_offset() {
    static std::atomic<std::size_t> count{0};
    return (count.fetch_add(1, std::memory_order_relaxed) * 37 % (kPage / kLine)) * kLine;
  }
};

using GrainArray = std::vector<double, StaggeredAllocator<double>>;

}  // namespace fdem
