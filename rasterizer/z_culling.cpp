#include "rasterizer/z_culling.h"

#include <algorithm>

namespace patchsim {

float tileDepthBound(const VisibilityBuffer& buffer, const TileRect& tile) {
    float deepest = 0;
    for (int y = tile.y0; y < tile.y1; ++y)
        for (int x = tile.x0; x < tile.x1; ++x)
            for (int s = 0; s < buffer.samplesPerPixel(); ++s)
                deepest = std::max(deepest, buffer.depthBound(x, y, s));
    return deepest;
}

TileDepthBounds::TileDepthBounds(const TileGrid& grid, const VisibilityBuffer& buffer)
    : grid_(grid), buffer_(buffer), bound_(grid.tileCount(), 0.0f), stale_(grid.tileCount(), 1) {}

float TileDepthBounds::bound(int tx, int ty) {
    const std::size_t t = grid_.index(tx, ty);
    if (stale_[t]) {
        bound_[t] = tileDepthBound(buffer_, grid_.rect(tx, ty));
        stale_[t] = 0;
    }
    return bound_[t];
}

}  // namespace patchsim
