#include "build_memory.hpp"

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>

#include <malloc.h>

namespace sg::bench {
namespace {

std::atomic<bool> counting{false};
std::atomic<long long> current{0};
std::atomic<long long> peak{0};

void on_allocate(void* p) noexcept
{
    if (!p || !counting.load(std::memory_order_relaxed)) return;
    const auto size = static_cast<long long>(malloc_usable_size(p));
    raise_peak(peak, current.fetch_add(size, std::memory_order_relaxed) + size);
}

void on_free(void* p) noexcept
{
    if (!p || !counting.load(std::memory_order_relaxed)) return;
    current.fetch_sub(static_cast<long long>(malloc_usable_size(p)), std::memory_order_relaxed);
}

void* allocate(std::size_t size)
{
    void* p = std::malloc(size == 0 ? 1 : size);
    if (!p) throw std::bad_alloc();
    on_allocate(p);
    return p;
}

void* allocate_aligned(std::size_t size, std::align_val_t alignment)
{
    void* p = nullptr;
    const auto a = std::max(static_cast<std::size_t>(alignment), sizeof(void*));
    if (posix_memalign(&p, a, size == 0 ? 1 : size) != 0) throw std::bad_alloc();
    on_allocate(p);
    return p;
}

void release(void* p) noexcept
{
    on_free(p);
    std::free(p);
}

}  // namespace

BuildMemoryWindow::BuildMemoryWindow() noexcept
{
    current.store(0);
    peak.store(0);
    (void)malloc_trim(0);
    // "5" resets the peak resident set size the kernel reports as VmHWM (Linux 4.0 on).
    if (std::FILE* f = std::fopen("/proc/self/clear_refs", "w")) {
        high_water_reset_ = std::fputs("5", f) >= 0;
        high_water_reset_ = std::fclose(f) == 0 && high_water_reset_;
    }
    counting.store(true);
}

BuildMemoryWindow::~BuildMemoryWindow() { counting.store(false); }

std::size_t BuildMemoryWindow::peak_bytes() const noexcept
{
    return static_cast<std::size_t>(std::max(0LL, peak.load()));
}

std::size_t BuildMemoryWindow::process_high_water_bytes() noexcept
{
    std::FILE* f = std::fopen("/proc/self/status", "r");
    if (!f) return 0;
    char line[256];
    std::size_t kib = 0;
    while (std::fgets(line, sizeof line, f))
        if (std::strncmp(line, "VmHWM:", 6) == 0) {
            kib = std::strtoull(line + 6, nullptr, 10);
            break;
        }
    std::fclose(f);
    return kib * 1024;
}

}  // namespace sg::bench

// The replaced global allocation functions of the sg-bench executable: every form, so that no
// block is allocated by one allocator and freed by another (AddressSanitizer brings its own
// of each form that is not replaced).
void* operator new(std::size_t size) { return sg::bench::allocate(size); }
void* operator new[](std::size_t size) { return sg::bench::allocate(size); }
void* operator new(std::size_t size, std::align_val_t alignment)
{
    return sg::bench::allocate_aligned(size, alignment);
}
void* operator new[](std::size_t size, std::align_val_t alignment)
{
    return sg::bench::allocate_aligned(size, alignment);
}
void operator delete(void* p) noexcept { sg::bench::release(p); }
void operator delete[](void* p) noexcept { sg::bench::release(p); }
void operator delete(void* p, std::size_t) noexcept { sg::bench::release(p); }
void operator delete[](void* p, std::size_t) noexcept { sg::bench::release(p); }
void operator delete(void* p, std::align_val_t) noexcept { sg::bench::release(p); }
void operator delete[](void* p, std::align_val_t) noexcept { sg::bench::release(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { sg::bench::release(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { sg::bench::release(p); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept
{
    try {
        return sg::bench::allocate(size);
    } catch (...) {
        return nullptr;
    }
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept
{
    try {
        return sg::bench::allocate(size);
    } catch (...) {
        return nullptr;
    }
}
void* operator new(std::size_t size, std::align_val_t alignment, const std::nothrow_t&) noexcept
{
    try {
        return sg::bench::allocate_aligned(size, alignment);
    } catch (...) {
        return nullptr;
    }
}
void* operator new[](std::size_t size, std::align_val_t alignment, const std::nothrow_t&) noexcept
{
    try {
        return sg::bench::allocate_aligned(size, alignment);
    } catch (...) {
        return nullptr;
    }
}
void operator delete(void* p, const std::nothrow_t&) noexcept { sg::bench::release(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { sg::bench::release(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept
{
    sg::bench::release(p);
}
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept
{
    sg::bench::release(p);
}
