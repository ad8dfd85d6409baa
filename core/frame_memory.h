#pragma once
// Memory for a frame's buffers: the visibility buffer (32 bytes a sample, 39 MB for the default
// film) and the output planes (the image and its four AOVs, 2.1 MB), backed by 2 MiB pages where
// the operating system offers them, and kept from one frame for the next.
//
// Why huge pages: a frame's buffers are fresh memory, and touching it the first time costs one
// page fault per 4 KiB page. On a virtual machine each fault can be a trap to the hypervisor: on
// the AMD guest of docs/PERFORMANCE.md a fault costs about 9 us, so the visibility buffer's faults
// took two fifths of a one-thread render ("Frame memory in huge pages"), and the output planes'
// 530 faults about 5 ms of a 94 ms frame ("Frame memory kept for the next frame"). A buffer of
// at least kSmallestHugePageBuffer is aligned to 2 MiB, rounded up to whole huge pages and advised
// transparent huge pages (Linux's madvise(MADV_HUGEPAGE)): one fault per 2 MiB. The rounding
// costs at most one huge page a buffer, and only for a buffer of at least an eighth of one. Where
// the advice is not available, or PATCHSIM_HUGE_PAGES=off is set in the environment, the memory
// is ordinary pages, and nothing else changes: the contents are the caller's to construct either
// way.
//
// Why keep it: the kernel zeroes every fresh page, 49 MB a frame for the default film, about 5%
// of a frame's processor time. A block of at least kSmallestHugePageBuffer is kept when it is
// released, and a later request of the same size takes it back, faulted and zeroed already. A
// process that renders frame after frame (`sweep`, `explore`, the converged image's passes) so
// reuses one frame's buffers in the next. A request of a size the cache does not hold first gives
// every cached block back, so a frame of another shape never holds the last one's memory beside
// its own; the cache holds at most 16 blocks and 1 GiB.
//
// The storage comes from the aligned global operator new, so a program that replaces it (the
// poisoned-memory test) sees these buffers too.

#include <cstddef>
#include <memory>

#include "core/default_init_allocator.h"

namespace patchsim {

inline constexpr std::size_t kHugePageBytes = std::size_t(2) << 20;
// The smallest buffer given whole huge pages.
inline constexpr std::size_t kSmallestHugePageBuffer = kHugePageBytes / 8;

// Whether frame memory of `bytes` bytes is advised huge pages on this host: Linux with
// transparent huge pages not switched off (by the kernel or by PATCHSIM_HUGE_PAGES=off), and a
// buffer of at least kSmallestHugePageBuffer.
bool frameMemoryAdvisesHugePages(std::size_t bytes);

// Uninitialised storage of at least `bytes` bytes (at least one byte), aligned to 64 bytes, and to
// kHugePageBytes when huge pages are advised. Throws std::bad_alloc when there is no memory.
// releaseFrameBytes takes the same `bytes`.
void* allocateFrameBytes(std::size_t bytes);
void releaseFrameBytes(void* p, std::size_t bytes) noexcept;

// Gives the cached blocks back (for a long-lived process between jobs, and for tests that need
// fresh memory); and the bytes cached now.
void releaseCachedFrameMemory();
std::size_t cachedFrameMemoryBytes();

struct FrameMemoryRelease {
    std::size_t bytes = 0;
    void operator()(void* p) const { releaseFrameBytes(p, bytes); }
};

inline std::unique_ptr<void, FrameMemoryRelease> allocateFrameMemory(std::size_t bytes) {
    return {allocateFrameBytes(bytes), FrameMemoryRelease{bytes}};
}

// A container allocator over frame memory that leaves a sized construction unwritten (see
// default_init_allocator.h): for frame-sized planes whose every element the workers write.
template <class T>
class FrameAllocator : public DefaultInitAllocator<T> {
  public:
    template <class U>
    struct rebind {
        using other = FrameAllocator<U>;
    };

    using DefaultInitAllocator<T>::DefaultInitAllocator;

    T* allocate(std::size_t n) { return static_cast<T*>(allocateFrameBytes(n * sizeof(T))); }
    void deallocate(T* p, std::size_t n) noexcept { releaseFrameBytes(p, n * sizeof(T)); }
};

}  // namespace patchsim
