#include "rasterizer/common/visibility_buffer.h"

#include <algorithm>
#include <new>

#include "core/parallel.h"

namespace patchsim {

VisibilityBuffer::VisibilityBuffer(int width, int height, int spp, float farDepth, int threads)
    : width_(width),
      height_(height),
      spp_(spp),
      far_(farDepth),
      size_(std::size_t(width) * std::size_t(height) * std::size_t(spp)),
      memory_(allocateFrameMemory(size_ * sizeof(VisibilityRecord))) {
    constexpr std::size_t kChunk = std::size_t(1) << 16;
    parallelFor((size_ + kChunk - 1) / kChunk, threads, [&](int, std::size_t c) {
        const std::size_t first = c * kChunk, last = std::min(size_, first + kChunk);
        for (std::size_t i = first; i < last; ++i) ::new (data() + i) VisibilityRecord();
    });
}

}  // namespace patchsim
