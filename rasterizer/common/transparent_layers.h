#pragma once
// Transparent fragments kept per sample for the output merger (DESIGN.md section 6).
//
// Representation
// --------------
// Up to K fragments per sample (default 16), unsorted, in blocks of K slots. A sample gets a block
// the first time a transparent fragment reaches it, from one of the set's pools; a pool is written
// by one worker only (the worker, or the band of rows, that owns the pool), so no locks are
// needed. A block is named by a 32-bit handle, pool << 24 | block + 1, so a set has at most
// kMaxPools pools of 2^24 - 1 blocks each. The blend sorts a sample's fragments, so which pool or
// slot holds them does not change an image. When a sample's block is full, the
// farthest fragment is dropped (counted as overflow), so the sample keeps its K nearest fragments
// whatever order they arrive in. Fragments of the same object within a relative depth of
// kSameSurfaceDepth are one surface seen twice (a ray through an edge that two triangles share):
// only the nearer in (depth, patch, triangle) order is kept.

#include <cstdint>
#include <vector>

#include "core/memory_trace.h"
#include "rasterizer/common/frame_partition.h"
#include "rasterizer/common/visibility_buffer.h"

namespace patchsim {

struct LayerFragment {
    VisibilityRecord record;
    std::int32_t object = -1;
};

class TransparentLayers {
  public:
    static constexpr int kMaxPools = 256;

    // `pools` workers (or bands) may offer fragments at once, each from its own pool.
    TransparentLayers(std::size_t samples, int maxLayers, int pools = FramePartition::kClasses);
    int pools() const { return int(pools_.size()); }

    // Offers a fragment to `sample` from pool `pool`; returns false when a fragment was dropped.
    bool offer(std::size_t sample, int pool, const LayerFragment& fragment);
    int maxLayers() const { return maxLayers_; }
    int count(std::size_t sample) const { return count_[sample]; }
    const LayerFragment* layers(std::size_t sample) const;

  private:
    LayerFragment* block(std::uint32_t handle);

    int maxLayers_;
    std::vector<std::uint32_t> block_;  // pool << 24 | (block + 1); 0: none yet
    std::vector<std::uint8_t> count_;
    std::vector<std::vector<LayerFragment>> pools_;
};

// Offers `fragment` to `sample`'s layers and, when the hardware models memory (`trace`), records
// the offer and whether it added a layer (core/memory_trace.h). Returns false when a fragment
// was dropped, as TransparentLayers::offer does.
inline bool offerToLayers(TransparentLayers& layers, std::size_t sample, int pool,
                          const LayerFragment& fragment, RegionTraceWriter* trace) {
    if (trace == nullptr) return layers.offer(sample, pool, fragment);
    const int before = layers.count(sample);
    const bool kept = layers.offer(sample, pool, fragment);
    trace->offered(sample, layers.count(sample) > before);
    return kept;
}

}  // namespace patchsim
