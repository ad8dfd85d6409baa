#pragma once
// Per-pixel and per-tile work of the patch rasterizer, for heat maps (SPEC section 6).
//
// Representation
// --------------
// One counter array per quantity, row-major over pixels (or over tiles of the rasterizer's tile
// size). A pixel's entries are written only by the worker that owns its tile, so the arrays are
// filled without locks and the same for any thread count. Allocated only when heat maps are
// requested; the rasterizer skips all of it when given no PixelWork.

#include <cstdint>
#include <vector>

namespace patchsim {

struct PixelWork {
    int width = 0, height = 0, tileSize = 1;
    std::vector<std::uint32_t> samplesTested, raysCast, rayBoxTests, rayTriangleTests,
        visibilitySamples;
    std::vector<std::uint32_t> tileTests;  // per tile: frustum tests of that tile (one per group)

    PixelWork(int w, int h, int tile)
        : width(w),
          height(h),
          tileSize(tile),
          samplesTested(std::size_t(w) * std::size_t(h)),
          raysCast(samplesTested.size()),
          rayBoxTests(samplesTested.size()),
          rayTriangleTests(samplesTested.size()),
          visibilitySamples(samplesTested.size()),
          tileTests(std::size_t(tilesX()) * std::size_t(tilesY())) {}
    int tilesX() const { return (width + tileSize - 1) / tileSize; }
    int tilesY() const { return (height + tileSize - 1) / tileSize; }
    std::size_t pixel(int x, int y) const {
        return std::size_t(y) * std::size_t(width) + std::size_t(x);
    }
    std::size_t tile(int tx, int ty) const {
        return std::size_t(ty) * std::size_t(tilesX()) + std::size_t(tx);
    }
};

}  // namespace patchsim
