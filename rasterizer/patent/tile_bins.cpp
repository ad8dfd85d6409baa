#include "rasterizer/patent/tile_bins.h"

#include <algorithm>

namespace patchsim {

namespace {

// The part of `range` on the grid.
TileRange clipped(TileRange range, const TileGrid& grid) {
    return {std::max(range.x0, 0), std::max(range.y0, 0), std::min(range.x1, grid.tilesX()),
            std::min(range.y1, grid.tilesY())};
}

}  // namespace

TileBins::TileBins(const TileGrid& grid, const std::vector<TileRange>& covered)
    : begin_(grid.tileCount() + 1, 0) {
    for (const TileRange& range : covered) {
        const TileRange r = clipped(range, grid);
        for (int ty = r.y0; ty < r.y1; ++ty)
            for (int tx = r.x0; tx < r.x1; ++tx) ++begin_[grid.index(tx, ty) + 1];
    }
    for (std::size_t t = 0; t < grid.tileCount(); ++t) begin_[t + 1] += begin_[t];
    groups_.resize(begin_.back());
    std::vector<std::uint32_t> next(begin_.begin(), begin_.end() - 1);
    for (std::size_t g = 0; g < covered.size(); ++g) {
        const TileRange r = clipped(covered[g], grid);
        for (int ty = r.y0; ty < r.y1; ++ty)
            for (int tx = r.x0; tx < r.x1; ++tx)
                groups_[next[grid.index(tx, ty)]++] = std::uint32_t(g);
    }
}

}  // namespace patchsim
