#include "rasterizer/common/pixel_counters.h"

namespace patchsim {

PixelCounters::PixelCounters(const TileGrid& grid) : grid_(grid), tileTests_(grid.tileCount()) {
    for (auto& v : values_) v.assign(std::size_t(grid.width) * std::size_t(grid.height), 0);
}

}  // namespace patchsim
