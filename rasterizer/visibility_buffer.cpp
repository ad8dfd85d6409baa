#include "rasterizer/visibility_buffer.h"

#include <algorithm>
#include <new>

#ifdef __linux__
#include <sys/mman.h>
#endif

#include "pipeline/core/parallel.h"

namespace patchsim {

namespace {

constexpr std::size_t kHugePage = std::size_t(2) << 20;

}  // namespace

// Uninitialised storage (the constructor's workers construct every record), on huge pages where
// the system gives them on request: a frame's records are tens of megabytes, and faulting them
// in 4 KiB at a time is a cost of its own.
VisibilityRecord* VisibilityBuffer::allocate(std::size_t records) {
    const std::size_t bytes =
        std::max<std::size_t>(records * sizeof(VisibilityRecord), sizeof(VisibilityRecord));
    void* p = ::operator new[](bytes, std::align_val_t(kHugePage));
#ifdef __linux__
    if (bytes >= kHugePage) madvise(p, bytes / kHugePage * kHugePage, MADV_HUGEPAGE);
#endif
    return static_cast<VisibilityRecord*>(p);
}

VisibilityBuffer::VisibilityBuffer(int width, int height, int spp, float farDepth, int threads)
    : width_(width),
      height_(height),
      spp_(spp),
      far_(farDepth),
      size_(std::size_t(width) * std::size_t(height) * std::size_t(spp)),
      records_(allocate(size_)) {
    constexpr std::size_t kChunk = std::size_t(1) << 16;
    parallelFor((size_ + kChunk - 1) / kChunk, threads, [&](int, std::size_t c) {
        const std::size_t first = c * kChunk, last = std::min(size_, first + kChunk);
        for (std::size_t i = first; i < last; ++i) ::new (&records_[i]) VisibilityRecord();
    });
}

}  // namespace patchsim
