#pragma once
// Per-pixel and per-tile work of the rasterizer, for heat maps (DESIGN.md section 6).
//
// Representation
// --------------
// `kPixelQuantities` names each per-pixel quantity once: its heat-map file and title; the
// rasterizer counts each per sample (rasterizer/patent/tile_rays.h, `SampleWork`) and adds a tile's
// counts to its pixels when the tile is done. A PixelCounters holds one row-major array per
// quantity, plus a per-tile count of tile tests. A pixel's entries are written only by the worker
// that owns its tile, so the arrays fill without locks and the same for any thread count.
// Allocated only when heat maps are asked for; the rasterizer skips all of it when it has none.

#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

#include "rasterizer/common/tile_grid.h"

namespace patchsim {

struct PixelQuantity {
    const char* file;   // heat_<file>_pixel.png
    const char* title;  // "<title> per pixel"
};

// "visibility samples" counts nearer opaque hits and transparent fragments alike.
inline constexpr std::array<PixelQuantity, 5> kPixelQuantities{{
    {"samples_tested", "samples tested"},
    {"rays_cast", "rays cast"},
    {"ray_box_tests", "ray-box tests"},
    {"ray_triangle_tests", "ray-triangle tests"},
    {"visibility_samples", "visibility samples"},
}};
// The index of the quantity with heat-map file name `file` (compile-time).
constexpr std::size_t pixelQuantity(std::string_view file) {
    for (std::size_t q = 0; q < kPixelQuantities.size(); ++q)
        if (file == kPixelQuantities[q].file) return q;
    throw "no such pixel quantity";
}

class PixelCounters {
  public:
    explicit PixelCounters(const TileGrid& grid);

    const TileGrid& grid() const { return grid_; }
    // Adds `value` to quantity `quantity` (an index into kPixelQuantities) of pixel (x, y).
    void add(int x, int y, std::size_t quantity, std::uint32_t value) {
        values_[quantity][pixel(x, y)] += value;
    }
    void countTileTest(int tx, int ty) { ++tileTests_[grid_.index(tx, ty)]; }

    const std::vector<std::uint32_t>& values(std::size_t quantity) const {
        return values_[quantity];
    }
    const std::vector<std::uint32_t>& tileTests() const { return tileTests_; }
    // For putting a frame together from the rows several processes counted.
    std::vector<std::uint32_t>& mutableValues(std::size_t quantity) { return values_[quantity]; }
    std::vector<std::uint32_t>& mutableTileTests() { return tileTests_; }
    std::size_t pixel(int x, int y) const {
        return std::size_t(y) * std::size_t(grid_.width) + std::size_t(x);
    }

  private:
    TileGrid grid_;
    std::array<std::vector<std::uint32_t>, kPixelQuantities.size()> values_;
    std::vector<std::uint32_t> tileTests_;
};

}  // namespace patchsim
