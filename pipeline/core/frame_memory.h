#pragma once
// Memory for a frame's largest buffers (the visibility buffer: 32 bytes a sample, 39 MB for the
// default film), backed by 2 MiB pages where the operating system offers them.
//
// Why: a buffer that large is a fresh mapping every frame, and touching it the first time costs
// one page fault per 4 KiB page: about 9,600 faults for the default film. On a virtual machine
// each fault can be a trap to the hypervisor: on the AMD guest of docs/PERFORMANCE.md ("Frame
// memory in huge pages") the faults took two fifths of a one-thread render. Aligning the buffer to
// 2 MiB and advising transparent huge pages (Linux's madvise(MADV_HUGEPAGE)) cuts the faults
// 512-fold. Where the advice is not available, or PATCHSIM_HUGE_PAGES=off is set in the
// environment, the memory is ordinary pages, and nothing else changes: the contents are the
// caller's to construct either way.

#include <cstddef>
#include <memory>

namespace patchsim {

inline constexpr std::size_t kHugePageBytes = std::size_t(2) << 20;

struct FrameMemoryRelease {
    void operator()(void* p) const;
};

// Uninitialised storage of at least `bytes` bytes (at least one byte), aligned to 64 bytes, and to
// kHugePageBytes when `bytes` is at least that. Throws std::bad_alloc when there is no memory.
std::unique_ptr<void, FrameMemoryRelease> allocateFrameMemory(std::size_t bytes);

// Whether allocateFrameMemory advises huge pages for a buffer of `bytes` bytes on this host: Linux
// with transparent huge pages not switched off (by the kernel or by PATCHSIM_HUGE_PAGES=off), and
// a buffer of at least one huge page.
bool frameMemoryAdvisesHugePages(std::size_t bytes);

}  // namespace patchsim
