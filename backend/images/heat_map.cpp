#include "backend/images/heat_map.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>

#include "backend/images/image.h"
#include "backend/images/image_io_module.h"
#include "core/error.h"

namespace patchsim {

namespace {

// Control points of the "inferno" colour map (matplotlib), sRGB.
constexpr float kInferno[9][3] = {
    {0.001f, 0.000f, 0.014f}, {0.122f, 0.047f, 0.282f}, {0.335f, 0.060f, 0.428f},
    {0.533f, 0.134f, 0.416f}, {0.729f, 0.212f, 0.333f}, {0.891f, 0.347f, 0.198f},
    {0.977f, 0.550f, 0.039f}, {0.969f, 0.791f, 0.180f}, {0.988f, 0.998f, 0.645f}};

std::string formatValue(float v) {
    char text[32];
    std::snprintf(text, sizeof text,
                  std::abs(v) >= 1000 || (v != 0 && std::abs(v) < 0.01f) ? "%.3g" : "%.2f",
                  double(v));
    return text;
}

constexpr int kLegendHeight = 44;
constexpr const char* kFont = "DejaVuSans";

}  // namespace

HeatColor heatColor(float t) {
    t = std::clamp(std::isfinite(t) ? t : 0.0f, 0.0f, 1.0f) * 8.0f;
    const int i = std::min(int(t), 7);
    const float f = t - float(i);
    return {kInferno[i][0] + f * (kInferno[i + 1][0] - kInferno[i][0]),
            kInferno[i][1] + f * (kInferno[i + 1][1] - kInferno[i][1]),
            kInferno[i][2] + f * (kInferno[i + 1][2] - kInferno[i][2])};
}

namespace {

// An 8-bit RGB picture the heat map is drawn into.
struct Canvas {
    int width, height;
    std::vector<std::uint8_t> rgb;

    Canvas(int w, int h) : width(w), height(h), rgb(std::size_t(w) * std::size_t(h) * 3, 0) {}
    void set(int x, int y, const HeatColor& c) {
        std::uint8_t* p = &rgb[(std::size_t(y) * std::size_t(width) + std::size_t(x)) * 3];
        for (const float v : {c.r, c.g, c.b})
            *p++ = std::uint8_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
    }
    void text(const std::string& path, int x, int y, const std::string& words, int size,
              bool alignRight = false) {
        TextRequest request;
        request.rgb = rgb.data();
        request.width = width;
        request.height = height;
        request.x = x;
        request.y = y;
        request.text = words;
        request.size = size;
        request.font = kFont;
        request.alignRight = alignRight;
        std::string error;
        if (!imageIo().drawText(request, error)) throw InputError(path, "", error);
    }
};

}  // namespace

void writeHeatMap(const HeatMapGrid& grid, const std::string& path) {
    const int width = std::max(grid.cellsX * grid.cellPixels, 200);
    const int mapHeight = grid.cellsY * grid.cellPixels;
    Canvas image(width, mapHeight + kLegendHeight);
    float lo = 0, hi = 0;
    if (!grid.values.empty()) {
        lo = *std::min_element(grid.values.begin(), grid.values.end());
        hi = *std::max_element(grid.values.begin(), grid.values.end());
    }
    const float range = hi > lo ? hi - lo : 1.0f;
    for (int y = 0; y < mapHeight; ++y) {
        for (int x = 0; x < grid.cellsX * grid.cellPixels; ++x) {
            const float v =
                grid.values[std::size_t(y / grid.cellPixels) * std::size_t(grid.cellsX) +
                            std::size_t(x / grid.cellPixels)];
            image.set(x, y, heatColor((v - lo) / range));
        }
    }
    // Legend: the colour bar from min to max, labelled.
    const int barY = mapHeight + 22, barHeight = 10, barX0 = 4, barX1 = width - 4;
    for (int x = barX0; x < barX1; ++x) {
        const HeatColor c = heatColor(float(x - barX0) / float(barX1 - barX0 - 1));
        for (int y = barY; y < barY + barHeight; ++y) image.set(x, y, c);
    }
    image.text(path, barX0, mapHeight + 15, grid.title, 12);
    image.text(path, barX0, mapHeight + kLegendHeight - 1, formatValue(lo), 10);
    image.text(path, barX1, mapHeight + kLegendHeight - 1, formatValue(hi), 10, true);
    writeRgb8(path, image.width, image.height, image.rgb.data());
}

namespace {

// One quantity (or ratio of two) per pixel and summed per tile.
void addMaps(const PixelCounters& pixels, const char* file, const std::string& title,
             const std::vector<std::uint32_t>& numerator,
             const std::vector<std::uint32_t>* denominator, const std::string& dir,
             OutputSet& outputs, std::vector<std::string>& written) {
    const TileGrid& g = pixels.grid();
    HeatMapGrid pixel{title + " per pixel", g.width, g.height, 1, {}};
    HeatMapGrid tile{title + " per tile", g.tilesX(), g.tilesY(), g.tileSize, {}};
    std::vector<double> tileNum(g.tileCount()), tileDen(tileNum.size());
    for (int y = 0; y < g.height; ++y) {
        for (int x = 0; x < g.width; ++x) {
            const std::size_t p = pixels.pixel(x, y);
            const double num = numerator[p];
            const double den = denominator ? double((*denominator)[p]) : 1.0;
            pixel.values.push_back(denominator ? (den > 0 ? float(num / den) : 0.0f) : float(num));
            const std::size_t t = g.index(x / g.tileSize, y / g.tileSize);
            tileNum[t] += num;
            tileDen[t] += den;
        }
    }
    for (std::size_t t = 0; t < tileNum.size(); ++t)
        tile.values.push_back(denominator ? (tileDen[t] > 0 ? float(tileNum[t] / tileDen[t]) : 0.0f)
                                          : float(tileNum[t]));
    for (const auto* grid : {&pixel, &tile}) {
        const std::string path =
            dir + "/heat_" + file + (grid == &pixel ? "_pixel.png" : "_tile.png");
        writeHeatMap(*grid, outputs.file(path, "--heatmaps"));
        written.push_back(path);
    }
}

}  // namespace

std::vector<std::string> heatMapFileNames() {
    std::vector<std::string> files;
    for (const auto& q : kPixelQuantities)
        for (const char* grid : {"_pixel.png", "_tile.png"})
            files.push_back(std::string("heat_") + q.file + grid);
    for (const char* grid : {"_pixel.png", "_tile.png"})
        files.push_back(std::string("heat_ste") + grid);
    files.push_back("heat_tile_tests_tile.png");
    return files;
}

std::vector<std::string> writeHeatMaps(const PixelCounters& pixels, const std::string& dir,
                                       OutputSet& outputs) {
    std::vector<std::string> written;
    for (std::size_t q = 0; q < kPixelQuantities.size(); ++q)
        addMaps(pixels, kPixelQuantities[q].file, kPixelQuantities[q].title, pixels.values(q),
                nullptr, dir, outputs, written);
    addMaps(pixels, "ste", "sample test efficiency",
            pixels.values(pixelQuantity("visibility_samples")),
            &pixels.values(pixelQuantity("samples_tested")), dir, outputs, written);
    const TileGrid& g = pixels.grid();
    HeatMapGrid tiles{"tile tests per tile", g.tilesX(), g.tilesY(), g.tileSize, {}};
    for (std::uint32_t v : pixels.tileTests()) tiles.values.push_back(float(v));
    const std::string path = dir + "/heat_tile_tests_tile.png";
    writeHeatMap(tiles, outputs.file(path, "--heatmaps"));
    written.push_back(path);
    return written;
}

}  // namespace patchsim
