#pragma once
// Z culling (US 8,791,945, step 6): what the z-buffer already holds bounds the work for a tile.
// The tile's far plane moves in to the deepest depth any of its samples may still see (a sample
// without a hit sees to the camera's far plane); each ray ends at its own sample's current depth,
// slightly widened so that a hit at exactly that depth still reaches the (depth, patch, triangle)
// tie-break of the visibility buffer.

#include <cstdint>
#include <vector>

#include "rasterizer/conservative_margins.h"
#include "rasterizer/tile_grid.h"
#include "rasterizer/visibility_buffer.h"

namespace patchsim {

// The deepest depth bound over the tile's samples.
float tileDepthBound(const VisibilityBuffer& buffer, const TileRect& tile);

// The tiles' depth bounds, kept up to date as samples are written instead of rescanned for every
// group that visits a tile: a tile is rescanned only when a sample that held its bound got nearer.
// A tile is only touched by the worker that owns it.
class TileDepthBounds {
  public:
    TileDepthBounds(const TileGrid& grid, const VisibilityBuffer& buffer);
    float bound(int tx, int ty);
    // A sample of the tile, whose depth bound was `previous`, got nearer.
    void lowered(int tx, int ty, float previous) {
        const std::size_t t = grid_.index(tx, ty);
        if (previous >= bound_[t]) stale_[t] = 1;
    }

  private:
    TileGrid grid_;
    const VisibilityBuffer& buffer_;
    std::vector<float> bound_;
    std::vector<std::uint8_t> stale_;
};

// The ray parameter of a depth bound, for a ray with the given depth per unit of parameter.
inline float rayEndAtDepth(float depth, float depthPerLambda) {
    return depth / depthPerLambda * (1.0f + kDepthTieWidening);
}

}  // namespace patchsim
