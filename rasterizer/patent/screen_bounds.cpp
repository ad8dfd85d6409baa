#include "rasterizer/patent/screen_bounds.h"

#include <algorithm>
#include <cmath>

#include "rasterizer/common/conservative_margins.h"

namespace patchsim {

namespace {

// z = -1 plane bounds to raster pixels, widened by the margin.
ScreenBounds toRaster(const float lo[2], const float hi[2], const Camera& camera) {
    const float tanX = camera.tanHalfFovY() * camera.aspect(), tanY = camera.tanHalfFovY();
    ScreenBounds b;
    b.x0 = (lo[0] / tanX + 1.0f) * 0.5f * float(camera.width());
    b.x1 = (hi[0] / tanX + 1.0f) * 0.5f * float(camera.width());
    b.y0 = (1.0f - hi[1] / tanY) * 0.5f * float(camera.height());
    b.y1 = (1.0f - lo[1] / tanY) * 0.5f * float(camera.height());
    b.x0 -= kScreenBoundsMarginPixels;
    b.y0 -= kScreenBoundsMarginPixels;
    b.x1 += kScreenBoundsMarginPixels;
    b.y1 += kScreenBoundsMarginPixels;
    return b;
}

}  // namespace

ScreenBounds screenBounds(const PatchHierarchy& h, int boundsLevel, const Camera& camera,
                          const std::vector<ScreenMovingBox>& nodes) {
    const int level = std::min(boundsLevel, h.depth());
    float lo[2] = {1e30f, 1e30f}, hi[2] = {-1e30f, -1e30f};
    for (int node = PatchHierarchy::firstLeaf(level); node < PatchHierarchy::firstLeaf(level + 1);
         ++node) {
        const ScreenMovingBox& s = nodes[std::size_t(node)];
        if (s.empty) continue;
        if (!s.bounded) return {0, 0, float(camera.width()), float(camera.height()), true};
        for (int k = 0; k < 2; ++k) {
            lo[k] = std::min({lo[k], s.lower0[k], s.lower1[k]});
            hi[k] = std::max({hi[k], s.upper0[k], s.upper1[k]});
        }
    }
    return toRaster(lo, hi, camera);
}

ScreenBounds screenBounds(const PatchHierarchy& h, int boundsLevel, const Camera& camera,
                          const LensModel& lens) {
    const int level = std::min(boundsLevel, h.depth());
    float lo[2] = {1e30f, 1e30f}, hi[2] = {-1e30f, -1e30f};
    for (int node = PatchHierarchy::firstLeaf(level); node < PatchHierarchy::firstLeaf(level + 1);
         ++node) {
        const LBBox& box = h.node(node);
        if (box.empty()) continue;
        for (const Box3* b : {&box.bounds0, &box.bounds1}) {
            for (int c = 0; c < 8; ++c) {
                const Vec3 p = b->corner(c);
                const float depth = -p.z;
                if (!(depth >= camera.nearPlane()) || !std::isfinite(depth))
                    return {0, 0, float(camera.width()), float(camera.height()), true};
                const float blur = lens.radius * std::abs(1.0f / depth - 1.0f / lens.focusDistance);
                const float s[2] = {p.x / depth, p.y / depth};
                for (int k = 0; k < 2; ++k) {
                    lo[k] = std::min(lo[k], s[k] - blur);
                    hi[k] = std::max(hi[k], s[k] + blur);
                }
            }
        }
    }
    return toRaster(lo, hi, camera);
}

TileRange tilesCovering(const ScreenBounds& b, const TileGrid& grid) {
    const int t = grid.tileSize;
    // A bound far off screen (a box that nearly reaches the camera plane, or opened to the
    // largest float by a narrow node format) is clamped in float first: converting a float
    // beyond int's range is undefined, and on x86 gives INT_MIN, which would empty the range.
    const auto tile = [t](float pixel, int pixels) {
        if (std::isnan(pixel)) return -1;  // the range is refused below
        return int(std::floor(std::clamp(pixel, -1.0f, float(pixels) + 1.0f))) / t;
    };
    TileRange r;
    r.x0 = std::clamp(tile(b.x0, grid.width), 0, grid.tilesX());
    r.y0 = std::clamp(tile(b.y0, grid.height), 0, grid.tilesY());
    r.x1 = std::clamp(tile(b.x1, grid.width) + 1, 0, grid.tilesX());
    r.y1 = std::clamp(tile(b.y1, grid.height) + 1, 0, grid.tilesY());
    if (!(b.x0 <= b.x1) || !(b.y0 <= b.y1) || b.x1 < 0 || b.y1 < 0 || b.x0 > float(grid.width) ||
        b.y0 > float(grid.height))
        r.x1 = r.x0;  // nothing on screen
    return r;
}

}  // namespace patchsim
