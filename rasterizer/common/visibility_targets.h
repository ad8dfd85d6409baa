#pragma once
// Where visibility samples go, for every visibility method: the nearest opaque hit per sample,
// every transparent hit (when the scene has transparency), and optionally per-pixel work for heat
// maps. `pool` names the transparent-layer pool the calling worker owns.

#include "rasterizer/common/pixel_counters.h"
#include "rasterizer/common/transparent_layers.h"
#include "rasterizer/common/visibility_buffer.h"

namespace patchsim {

struct VisibilityTargets {
    VisibilityBuffer* opaque = nullptr;
    TransparentLayers* transparent = nullptr;
    PixelCounters* pixels = nullptr;
    int pool = 0;
};

}  // namespace patchsim
