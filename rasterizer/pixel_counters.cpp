#include "rasterizer/pixel_counters.h"

namespace patchsim {

PixelCounters::PixelCounters(const TileGrid& grid) : grid_(grid), tileTests_(grid.tileCount()) {
    for (auto& v : values_) v.assign(std::size_t(grid.width) * std::size_t(grid.height), 0);
}

void PixelCounters::record(int x, int y, const RasterWork& before, const RasterWork& after) {
    const std::size_t p = pixel(x, y);
    for (std::size_t q = 0; q < kPixelQuantities.size(); ++q)
        values_[q][p] +=
            std::uint32_t(kPixelQuantities[q].of(after) - kPixelQuantities[q].of(before));
}

}  // namespace patchsim
