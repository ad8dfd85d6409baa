#include "rasterizer/common/transparent_layers.h"

#include <algorithm>
#include <cmath>

#include "rasterizer/common/conservative_margins.h"

namespace patchsim {

TransparentLayers::TransparentLayers(std::size_t samples, int maxLayers, int pools)
    : maxLayers_(maxLayers),
      block_(samples, 0),
      count_(samples, 0),
      pools_(std::size_t(std::clamp(pools, 1, kMaxPools))) {}

LayerFragment* TransparentLayers::block(std::uint32_t handle) {
    return pools_[handle >> 24].data() +
           std::size_t((handle & 0xffffffu) - 1) * std::size_t(maxLayers_);
}

const LayerFragment* TransparentLayers::layers(std::size_t sample) const {
    const std::uint32_t h = block_[sample];
    if (h == 0) return nullptr;
    return pools_[h >> 24].data() + std::size_t((h & 0xffffffu) - 1) * std::size_t(maxLayers_);
}

bool TransparentLayers::offer(std::size_t sample, int pool, const LayerFragment& f) {
    if (block_[sample] == 0) {
        std::vector<LayerFragment>& p = pools_[std::size_t(pool)];
        const std::size_t blocks = p.size() / std::size_t(maxLayers_);
        p.resize(p.size() + std::size_t(maxLayers_));
        block_[sample] = (std::uint32_t(pool) << 24) | std::uint32_t(blocks + 1);
    }
    LayerFragment* slots = block(block_[sample]);
    const int n = count_[sample];
    for (int i = 0; i < n; ++i) {
        LayerFragment& s = slots[i];
        const float tolerance =
            kSameSurfaceDepth * std::max(std::abs(s.record.depth), std::abs(f.record.depth));
        if (s.object == f.object && std::abs(s.record.depth - f.record.depth) <= tolerance) {
            if (f.record.nearerThan(s.record)) s = f;
            return true;
        }
    }
    if (n < maxLayers_) {
        slots[n] = f;
        ++count_[sample];
        return true;
    }
    int farthest = 0;
    for (int i = 1; i < n; ++i)
        if (slots[farthest].record.nearerThan(slots[i].record)) farthest = i;
    if (f.record.nearerThan(slots[farthest].record)) slots[farthest] = f;
    return false;
}

}  // namespace patchsim
