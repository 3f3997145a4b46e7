#pragma once

#include <atomic>
#include <cstddef>

/// Peak memory of one build, measured the same way for every structure sg-bench builds.
///
/// Our structures allocate through operator new (std::vector, std::unique_ptr): sg-bench
/// replaces the global operator new and delete with ones that, while a BuildMemoryWindow is
/// open, add and subtract each block's usable size (malloc_usable_size) and keep the highest
/// sum. Embree allocates through its own allocator and reports every allocation to its memory
/// monitor callback, which embree_structure.cpp keeps the highest sum of in the same way (the
/// bytes Embree asks for, where ours count the usable size of each block, a few bytes more).
/// The input mesh is allocated before the window opens and is counted for nobody. Counting
/// our allocations costs two atomic operations each, so sg-bench opens a window on an untimed
/// build only (Embree's monitor is called per memory block, and keeps its peak on every build).
///
/// Not counted: memory a builder keeps from one build to the next and reuses (the kd-tree's
/// per-thread sweep buffers, about 8 bytes per triangle of the largest node sorted so far);
/// where such a buffer grows in the window, the free of its older block lowers the sum.
namespace sg::bench {

/// Raises `peak` to `value` if it is below (concurrent callers: the highest value wins).
inline void raise_peak(std::atomic<long long>& peak, long long value) noexcept
{
    long long seen = peak.load(std::memory_order_relaxed);
    while (value > seen && !peak.compare_exchange_weak(seen, value, std::memory_order_relaxed)) {
    }
}

/// Opens a counting window over the whole process: the sum and its peak start at 0, free heap
/// is returned to the system (malloc_trim), and the kernel's record of the process's resident
/// high-water mark is reset (/proc/self/clear_refs), where Linux allows it: the process's
/// maximum resident size as getrusage reports it is then the one since the window opened.
/// One window at a time.
class BuildMemoryWindow {
public:
    BuildMemoryWindow() noexcept;
    ~BuildMemoryWindow();
    BuildMemoryWindow(const BuildMemoryWindow&) = delete;
    BuildMemoryWindow& operator=(const BuildMemoryWindow&) = delete;

    /// Highest sum of the bytes allocated through operator new and not yet freed since the
    /// window opened (blocks freed in the window that were allocated before it lower the
    /// sum: see above).
    [[nodiscard]] std::size_t peak_bytes() const noexcept;
    /// The process's resident high-water mark (VmHWM) since the window opened, or since the
    /// process started where it could not be reset; 0 where /proc is not readable.
    [[nodiscard]] static std::size_t process_high_water_bytes() noexcept;
    /// True if the high-water mark was reset when the window opened.
    [[nodiscard]] bool high_water_reset() const noexcept { return high_water_reset_; }

private:
    bool high_water_reset_ = false;
};

}  // namespace sg::bench
