#pragma once
// Heat maps of the rasterizer's work (DESIGN.md section 6): per pixel and per tile, written as PNG
// with a colour scale (perceptually ordered, dark = little work, bright = much) and a legend bar
// labelled with the quantity, its minimum and its maximum. Text is drawn by OpenImageIO.

#include <string>
#include <vector>

#include "core/output_set.h"
#include "rasterizer/common/pixel_counters.h"

namespace patchsim {

struct HeatMapGrid {
    std::string title;  // e.g. "rays cast per pixel"
    int cellsX = 0, cellsY = 0;
    int cellPixels = 1;  // each cell is drawn as a square of this many pixels
    std::vector<float> values;
};

// Colour of a value in [0, 1] on the scale.
struct HeatColor {
    float r, g, b;
};
HeatColor heatColor(float t);

void writeHeatMap(const HeatMapGrid& grid, const std::string& path);

// Every heat map of a frame's work into `dir`: heat_<quantity>_pixel.png and _tile.png for each
// per-pixel quantity (rasterizer/common/pixel_counters.h) and for the sample test efficiency, and
// the tile tests per tile. Returns the files written. Files go through `outputs` (written when it
// commits).
std::vector<std::string> writeHeatMaps(const PixelCounters& pixels, const std::string& dir,
                                       OutputSet& outputs);

// The name of every file writeHeatMaps writes ("heat_rays_cast_pixel.png", ...).
std::vector<std::string> heatMapFileNames();

}  // namespace patchsim
