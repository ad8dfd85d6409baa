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

}  // namespace patchsim
