#include "rasterizer/visibility_buffer.h"

#include <algorithm>
#include <new>

#include "pipeline/core/parallel.h"

namespace patchsim {

// Uninitialised storage: the constructor's workers construct every record, so the first touch of
// a frame's worth of memory is spread over them.
VisibilityRecord* VisibilityBuffer::allocate(std::size_t records) {
    const std::size_t bytes =
        std::max<std::size_t>(records * sizeof(VisibilityRecord), sizeof(VisibilityRecord));
    return static_cast<VisibilityRecord*>(::operator new[](bytes));
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
