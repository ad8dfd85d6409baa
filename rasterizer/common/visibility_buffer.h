#pragma once
// The per-sample visibility buffer (z-buffer) shared by every visibility method.
//
// Representation
// --------------
// One record per sample, pixel-major: sample s of pixel (x, y) is record (y * width + x) * spp + s.
// A record is the nearest visibility sample so far (DESIGN.md section 4.8): depth (camera -z),
// patch, triangle, the barycentric weights of the triangle's vertices 1 and 2, and the sample's
// time t and lens position (u, v), so the back end shades it at its time without going back to the
// sample set. 32 bytes. Hits compare by (depth, patch, triangle), so the buffer's final content
// does not depend on the order hits arrive in, and a sample exactly on an edge shared by two
// triangles resolves the same way in every method.

#include <cstdint>
#include <limits>
#include <memory>
#include <new>
#include <span>
#include <type_traits>

#include "core/frame_memory.h"
#include "core/math.h"

namespace patchsim {

struct VisibilityRecord {
    float depth = std::numeric_limits<float>::infinity();
    std::int32_t patch = -1;
    std::uint32_t triangle = 0;
    float b1 = 0, b2 = 0;
    float time = 0;         // shutter time of the sample
    Vec2 lens{0.5f, 0.5f};  // lens sample in [0,1)^2; (0.5, 0.5) is the centre

    bool hit() const { return patch >= 0; }
    bool nearerThan(const VisibilityRecord& o) const {
        if (depth != o.depth) return depth < o.depth;
        if (patch != o.patch) return std::uint32_t(patch) < std::uint32_t(o.patch);
        return triangle < o.triangle;
    }
};

static_assert(sizeof(VisibilityRecord) == 32, "the film's memory budget counts 32 bytes a sample");
static_assert(std::is_trivially_destructible_v<VisibilityRecord>);

class VisibilityBuffer {
  public:
    // `threads` workers write the empty records (the first touch of a frame's worth of memory is
    // a large serial cost otherwise).
    VisibilityBuffer(int width, int height, int spp, float farDepth, int threads = 1);

    int width() const { return width_; }
    int height() const { return height_; }
    int samplesPerPixel() const { return spp_; }
    std::size_t index(int x, int y, int s) const {
        return (std::size_t(y) * std::size_t(width_) + std::size_t(x)) * std::size_t(spp_) +
               std::size_t(s);
    }
    const VisibilityRecord& at(int x, int y, int s) const { return data()[index(x, y, s)]; }
    VisibilityRecord& at(int x, int y, int s) { return data()[index(x, y, s)]; }
    // Current depth bound for z culling: the record's depth, or the far plane before any hit.
    float depthBound(int x, int y, int s) const { return depthBound(data()[index(x, y, s)]); }
    float depthBound(const VisibilityRecord& r) const { return r.depth < far_ ? r.depth : far_; }
    void offer(int x, int y, int s, const VisibilityRecord& hit) {
        VisibilityRecord& r = data()[index(x, y, s)];
        if (hit.nearerThan(r)) r = hit;
    }
    std::span<const VisibilityRecord> records() const { return {data(), size_}; }
    std::span<VisibilityRecord> mutableRecords() { return {data(), size_}; }

  private:
    // Records live in frame memory (huge pages where offered) the constructor's workers construct
    // them in; VisibilityRecord is trivially destructible, so releasing the memory ends them.
    VisibilityRecord* data() const { return static_cast<VisibilityRecord*>(memory_.get()); }
    int width_, height_, spp_;
    float far_;
    std::size_t size_;
    std::unique_ptr<void, FrameMemoryRelease> memory_;
};

}  // namespace patchsim
