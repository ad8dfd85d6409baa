#include "rasterizer/tile_samples.h"

#include <algorithm>

#include "pipeline/core/parallel.h"

namespace patchsim {

TileSamples::TileSamples(const TileGrid& grid, const Camera& camera, const SampleGenerator& samples,
                         int threads)
    : grid_(grid), begin_(grid.tileCount() + 1, 0) {
    const int spp = samples.samplesPerPixel();
    for (int ty = 0; ty < grid.tilesY(); ++ty)
        for (int tx = 0; tx < grid.tilesX(); ++tx) {
            const TileRect r = grid.rect(tx, ty);
            begin_[grid.index(tx, ty) + 1] = std::uint32_t((r.x1 - r.x0) * (r.y1 - r.y0) * spp);
        }
    for (std::size_t t = 0; t < grid.tileCount(); ++t) begin_[t + 1] += begin_[t];
    samples_.resize(begin_.back());
    parallelFor(grid.tileCount(), threads, [&](int, std::size_t t) {
        const int tx = int(t % std::size_t(grid.tilesX())),
                  ty = int(t / std::size_t(grid.tilesX()));
        const TileRect r = grid.rect(tx, ty);
        TileSample* out = samples_.data() + begin_[t];
        for (int y = r.y0; y < r.y1; ++y)
            for (int x = r.x0; x < r.x1; ++x)
                for (int s = 0; s < spp; ++s) {
                    const Sample smp = samples.sample(x, y, s);
                    const auto record =
                        std::uint32_t((std::size_t(y) * std::size_t(grid.width) + std::size_t(x)) *
                                          std::size_t(spp) +
                                      std::size_t(s));
                    *out++ = {smp.time,
                              rasterToScreen(camera, Vec2(float(x), float(y)) + smp.pixelOffset),
                              concentricDisk(smp.lens), smp.lens, record};
                }
        std::sort(samples_.data() + begin_[t], out, [](const TileSample& a, const TileSample& b) {
            return a.time < b.time || (a.time == b.time && a.record < b.record);
        });
    });
}

std::span<const TileSample> TileSamples::tile(int tx, int ty) const {
    const std::size_t t = grid_.index(tx, ty);
    return {samples_.data() + begin_[t], samples_.data() + begin_[t + 1]};
}

std::span<const TileSample> TileSamples::inTime(int tx, int ty, TimeRange times) const {
    const std::span<const TileSample> all = tile(tx, ty);
    if (times.isEmpty()) return {};
    const auto first = std::lower_bound(all.begin(), all.end(), times.lower,
                                        [](const TileSample& s, float t) { return s.time < t; });
    const auto last = std::upper_bound(first, all.end(), times.upper,
                                       [](float t, const TileSample& s) { return t < s.time; });
    return {first, last};
}

}  // namespace patchsim
