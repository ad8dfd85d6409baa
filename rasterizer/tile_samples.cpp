#include "rasterizer/tile_samples.h"

#include <algorithm>
#include <bit>

#include "pipeline/core/parallel.h"

namespace patchsim {

TileSamples::TileSamples(const TileGrid& grid, const Camera& camera,
                         const SampleGenerator& samples, int threads)
    : grid_(grid), begin_(grid.tileCount() + 1, 0) {
    const int spp = samples.samplesPerPixel();
    for (int ty = 0; ty < grid.tilesY(); ++ty)
        for (int tx = 0; tx < grid.tilesX(); ++tx) {
            const TileRect r = grid.rect(tx, ty);
            begin_[grid.index(tx, ty) + 1] =
                std::uint32_t((r.x1 - r.x0) * (r.y1 - r.y0) * spp);
        }
    for (std::size_t t = 0; t < grid.tileCount(); ++t) begin_[t + 1] += begin_[t];
    samples_.resize(begin_.back());
    // Per worker: the tile's samples before ordering, and their sort keys.
    const std::size_t workers = std::size_t(resolveThreadCount(threads));
    std::vector<std::vector<TileSample>> unordered(workers);
    std::vector<std::vector<std::uint64_t>> keys(workers);
    parallelFor(grid.tileCount(), threads, [&](int worker, std::size_t t) {
        const int tx = int(t % std::size_t(grid.tilesX())), ty = int(t / std::size_t(grid.tilesX()));
        const TileRect r = grid.rect(tx, ty);
        std::vector<TileSample>& made = unordered[std::size_t(worker)];
        made.clear();
        for (int y = r.y0; y < r.y1; ++y)
            for (int x = r.x0; x < r.x1; ++x)
                for (int s = 0; s < spp; ++s) {
                    const Sample smp = samples.sample(x, y, s);
                    const auto record = std::uint32_t(
                        (std::size_t(y) * std::size_t(grid.width) + std::size_t(x)) *
                            std::size_t(spp) +
                        std::size_t(s));
                    made.push_back({smp.time,
                                    rasterToScreen(camera, Vec2(float(x), float(y)) + smp.pixelOffset),
                                    concentricDisk(smp.lens), smp.lens, record});
                }
        orderByTime(made, keys[std::size_t(worker)], samples_.data() + begin_[t]);
    });
}

void TileSamples::orderByTime(const std::vector<TileSample>& made, std::vector<std::uint64_t>& keys,
                              TileSample* out) {
    // Sort 8-byte keys, not 32-byte samples: a time in [0, 1] orders as its bit pattern, and the
    // position in `made` grows with the record index, so the key order is (time, record). Adding
    // +0 turns a -0 time into +0, whose bits sort first.
    keys.clear();
    for (std::size_t i = 0; i < made.size(); ++i)
        keys.push_back(std::uint64_t(std::bit_cast<std::uint32_t>(made[i].time + 0.0f)) << 32 | i);
    std::sort(keys.begin(), keys.end());
    for (const std::uint64_t key : keys) *out++ = made[std::size_t(key & 0xffffffffu)];
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
