#pragma once
// Z culling (US 8,791,945, step 6): what the z-buffer already holds bounds the work for a tile.
// The tile's far plane moves in to the deepest depth any of its samples may still see (a sample
// without a hit sees to the camera's far plane: TileRays::farthestDepthBound, kept as hits are
// written); each ray ends at its own sample's current depth, slightly widened so that a hit at
// exactly that depth still reaches the (depth, patch, triangle) tie-break of the visibility
// buffer.

#include "rasterizer/common/conservative_margins.h"

namespace patchsim {

// The ray parameter of a depth bound, for a ray with the given depth per unit of parameter.
inline float rayEndAtDepth(float depth, float depthPerLambda) {
    return depth / depthPerLambda * (1.0f + kDepthTieWidening);
}

}  // namespace patchsim
