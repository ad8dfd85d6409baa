#include "rasterizer/transparent_layers.h"

#include <cmath>

namespace patchsim {

TransparentLayers::TransparentLayers(std::size_t samples, int maxLayers)
    : maxLayers_(maxLayers), block_(samples, 0), count_(samples, 0), pools_(kPools) {}

const LayerFragment* TransparentLayers::layers(std::size_t sample) const {
    const std::uint32_t b = block_[sample];
    if (b == 0) return nullptr;
    const std::vector<LayerFragment>& pool = pools_[b >> 24];
    return pool.data() + std::size_t((b & 0xffffffu) - 1) * std::size_t(maxLayers_);
}

bool TransparentLayers::offer(std::size_t sample, int pool, const LayerFragment& f) {
    if (block_[sample] == 0) {
        std::vector<LayerFragment>& p = pools_[std::size_t(pool)];
        const std::size_t blocks = p.size() / std::size_t(maxLayers_);
        p.resize(p.size() + std::size_t(maxLayers_));
        block_[sample] = (std::uint32_t(pool) << 24) | std::uint32_t(blocks + 1);
    }
    LayerFragment* slots = const_cast<LayerFragment*>(layers(sample));
    const int n = count_[sample];
    for (int i = 0; i < n; ++i) {
        LayerFragment& s = slots[i];
        const float tolerance =
            1e-6f * std::max(std::abs(s.record.depth), std::abs(f.record.depth));
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
