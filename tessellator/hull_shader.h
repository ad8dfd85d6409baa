#pragma once
// The hull shader's constant function (HS): per-edge tessellation factors and the inside factors
// derived from them, in the way D3D11's HLSL-generated factor processing does it
// (ProcessQuadTessFactors / ProcessTriTessFactors, two-axis for quads): factors below 1 or NaN
// become 1, edges are rounded (pow2 rounds up to a power of two, integer rounds up) and clamped
// to the partitioning's range, inside factors are the reduction (min, max or average) of the
// opposite edges, and an odd inside factor below 3 is raised so the picture frame does not snap.
// An edge factor <= 0 or NaN is passed through unchanged so the tessellator culls the patch.

#include "tessellator/d3d11_tessellator.h"

namespace patchsim {

struct HullShaderConfig {
    Partitioning partitioning = Partitioning::Integer;
    InsideReduction insideReduction = InsideReduction::Average;
};

// `edges` in D3D11 order (quad: u=0, v=0, u=1, v=1; triangle: u=0, v=0, w=0).
QuadTessFactors processQuadFactors(const float edges[4], const HullShaderConfig& config);
TriTessFactors processTriFactors(const float edges[3], const HullShaderConfig& config);

}  // namespace patchsim
