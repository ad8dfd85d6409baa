#pragma once
// The screen's tiles (US 8,791,945: bounds are walked in tiles).
//
// Representation
// --------------
// Square tiles of `tileSize` pixels from the top-left corner; the last column and row may be cut
// by the screen's edge. Tile (tx, ty) covers pixels [tx*s, min((tx+1)*s, width)) x
// [ty*s, min((ty+1)*s, height)). Tiles are numbered row-major.

#include <algorithm>
#include <cstddef>

namespace patchsim {

struct TileRect {
    int x0, y0, x1, y1;  // pixels, [x0, x1) x [y0, y1)
};

// A range of tiles [x0, x1) x [y0, y1); empty when x0 >= x1 or y0 >= y1.
struct TileRange {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    bool empty() const { return x0 >= x1 || y0 >= y1; }
};

struct TileGrid {
    int width = 0, height = 0, tileSize = 1;

    int tilesX() const { return (width + tileSize - 1) / tileSize; }
    int tilesY() const { return (height + tileSize - 1) / tileSize; }
    std::size_t tileCount() const { return std::size_t(tilesX()) * std::size_t(tilesY()); }
    std::size_t index(int tx, int ty) const {
        return std::size_t(ty) * std::size_t(tilesX()) + std::size_t(tx);
    }
    TileRect rect(int tx, int ty) const {
        return {tx * tileSize, ty * tileSize, std::min((tx + 1) * tileSize, width),
                std::min((ty + 1) * tileSize, height)};
    }
};

}  // namespace patchsim
