#pragma once
// Which groups cover each screen tile, in the order they are rasterized (sort-middle binning), so
// a tile can be finished in one go: its samples made once, then every group that covers it in
// patch order, while its rays and hits stay in the worker's cache.
//
// Representation
// --------------
// Compressed rows: for tile t (row-major), the group indices from `begin[t]` to `begin[t + 1]` in
// `groups`, ascending. A group index is its position in the frame's raster order.

#include <cstdint>
#include <span>
#include <vector>

#include "rasterizer/common/tile_grid.h"

namespace patchsim {

class TileBins {
  public:
    // `covered[g]`: the tiles group g's screen bounds cover, in raster order.
    TileBins(const TileGrid& grid, const std::vector<TileRange>& covered);

    std::span<const std::uint32_t> groupsOf(std::size_t tile) const {
        return {groups_.data() + begin_[tile], groups_.data() + begin_[tile + 1]};
    }
    std::size_t pairs() const { return groups_.size(); }  // (group, tile) pairs

  private:
    std::vector<std::uint32_t> begin_;  // tileCount + 1
    std::vector<std::uint32_t> groups_;
};

}  // namespace patchsim
