#include "pipeline/timing/depth_compression.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <string>

namespace patchsim {

namespace {

constexpr int kMaxTerms = 6;
constexpr std::uint64_t kCoefficientBits = 32, kWidthFieldBits = 5, kRawBits = 32;

int termCount(DepthCompression scheme) {
    return scheme == DepthCompression::Plane ? 3 : 6;
}

std::array<double, kMaxTerms> termsOf(const DepthSample& s) {
    return {1.0, double(s.x), double(s.y), double(s.time), double(s.u), double(s.v)};
}

// Least squares for w = 1/depth over `hits`, the coefficients rounded to float as a block header
// stores them. Terms that do not vary over the block (every time 0 in a static frame) are left
// at 0: their column is the constant's.
std::array<float, kMaxTerms> fit(const std::vector<const DepthSample*>& hits, int terms) {
    double a[kMaxTerms][kMaxTerms + 1] = {};
    double diagonal[kMaxTerms] = {};
    for (const DepthSample* s : hits) {
        const auto f = termsOf(*s);
        const double w = 1.0 / double(s->depth);
        for (int i = 0; i < terms; ++i) {
            for (int j = 0; j < terms; ++j) a[i][j] += f[std::size_t(i)] * f[std::size_t(j)];
            a[i][terms] += f[std::size_t(i)] * w;
        }
    }
    for (int i = 0; i < terms; ++i) diagonal[i] = a[i][i];
    // Gauss-Jordan elimination with partial pivoting; a pivot that vanishes against its column's
    // own sum of squares marks a term the block cannot tell from the others.
    std::array<bool, kMaxTerms> used{};
    std::array<int, kMaxTerms> pivotRow{};
    int row = 0;
    for (int col = 0; col < terms && row < terms; ++col) {
        int best = row;
        for (int r = row + 1; r < terms; ++r)
            if (std::abs(a[r][col]) > std::abs(a[best][col])) best = r;
        if (!(std::abs(a[best][col]) > 1e-9 * diagonal[col])) continue;
        std::swap(a[best], a[row]);
        for (int r = 0; r < terms; ++r) {
            if (r == row) continue;
            const double k = a[r][col] / a[row][col];
            for (int c = col; c <= terms; ++c) a[r][c] -= k * a[row][c];
        }
        used[std::size_t(col)] = true;
        pivotRow[std::size_t(col)] = row++;
    }
    std::array<float, kMaxTerms> coefficients{};
    for (int col = 0; col < terms; ++col)
        if (used[std::size_t(col)]) {
            const int r = pivotRow[std::size_t(col)];
            coefficients[std::size_t(col)] = float(a[r][terms] / a[r][col]);
        }
    return coefficients;
}

std::int64_t floatBits(float f) {
    std::uint32_t u;
    std::memcpy(&u, &f, sizeof u);
    return std::int64_t(u);
}

// The bits of one cluster: its header and its hits' residuals at the widest one's width.
std::uint64_t clusterBits(const std::vector<const DepthSample*>& hits, int terms) {
    if (hits.empty()) return 0;
    const std::array<float, kMaxTerms> c = fit(hits, terms);
    std::uint64_t widest = 0;
    for (const DepthSample* s : hits) {
        const auto f = termsOf(*s);
        double w = 0;
        for (int i = 0; i < terms; ++i) w += double(c[std::size_t(i)]) * f[std::size_t(i)];
        const float predicted = w > 0 ? float(1.0 / w) : 0.0f;
        const std::int64_t r = floatBits(s->depth) - floatBits(predicted);
        widest = std::max(widest, std::uint64_t(r < 0 ? -r : r));
    }
    const std::uint64_t width = widest == 0 ? 0 : std::uint64_t(std::bit_width(widest)) + 1;
    return std::uint64_t(terms) * kCoefficientBits + kWidthFieldBits + width * hits.size();
}

std::uint64_t selectorBits(std::size_t groups, std::size_t samples) {
    if (groups <= 1) return 0;
    return std::uint64_t(std::bit_width(groups - 1)) * samples;
}

// The bits of the block's hits under a predictor of `terms` terms: one surface, or two.
std::uint64_t predictedBits(const std::vector<DepthSample>& samples,
                            const std::vector<const DepthSample*>& hits, bool anyClear, int terms) {
    // Two surfaces are split at the middle of the inverse depths.
    std::uint64_t best = selectorBits(anyClear ? 2 : 1, samples.size()) + clusterBits(hits, terms);
    float lo = 1.0f / hits.front()->depth, hi = lo;
    for (const DepthSample* s : hits) {
        lo = std::min(lo, 1.0f / s->depth);
        hi = std::max(hi, 1.0f / s->depth);
    }
    const float middle = lo + 0.5f * (hi - lo);
    std::vector<const DepthSample*> near, far;
    for (const DepthSample* s : hits) (1.0f / s->depth >= middle ? near : far).push_back(s);
    if (!near.empty() && !far.empty())
        best = std::min(best, selectorBits(anyClear ? 3 : 2, samples.size()) +
                                  clusterBits(near, terms) + clusterBits(far, terms));
    return best;
}

}  // namespace

const char* depthCompressionName(DepthCompression c) {
    switch (c) {
        case DepthCompression::None:
            return "none";
        case DepthCompression::Plane:
            return "plane";
        case DepthCompression::TimePlane:
            return "time_plane";
    }
    return "?";
}

bool parseDepthCompression(const std::string& name, DepthCompression& out) {
    for (DepthCompression c :
         {DepthCompression::None, DepthCompression::Plane, DepthCompression::TimePlane})
        if (name == depthCompressionName(c)) {
            out = c;
            return true;
        }
    return false;
}

std::uint64_t compressedBlockBits(const std::vector<DepthSample>& samples,
                                  DepthCompression scheme) {
    const std::uint64_t raw = kRawBits * samples.size();
    if (scheme == DepthCompression::None) return raw;
    std::vector<const DepthSample*> hits;
    for (const DepthSample& s : samples)
        if (s.hit) hits.push_back(&s);
    if (hits.empty()) return 0;  // a clear block: the tile table says so
    const bool anyClear = hits.size() < samples.size();
    // time_plane chooses, per block, the static plane or the time-dependent predictor (a mode
    // bit): a static block pays no header for terms that do not vary.
    if (scheme == DepthCompression::TimePlane)
        return std::min(raw, 1 + std::min(compressedBlockBits(samples, DepthCompression::Plane),
                                          predictedBits(samples, hits, anyClear, 6)));
    return std::min(raw, predictedBits(samples, hits, anyClear, termCount(scheme)));
}

std::vector<double> DepthCompressionReport::blockScales() const {
    std::vector<double> scales(blockBits.size());
    for (std::size_t b = 0; b < blockBits.size(); ++b)
        scales[b] = double(blockBits[b]) / double(kRawBits * blockSamples[b]);
    return scales;
}

DepthCompressionReport compressDepth(const VisibilityBuffer& buffer,
                                     const SampleGenerator& generator, int surfaceTile,
                                     DepthCompression scheme) {
    DepthCompressionReport report;
    report.scheme = scheme;
    const int w = buffer.width(), h = buffer.height(), spp = buffer.samplesPerPixel();
    std::vector<Sample> pixel(static_cast<std::size_t>(spp));
    std::vector<DepthSample> block;
    for (int by = 0; by < h; by += surfaceTile)
        for (int bx = 0; bx < w; bx += surfaceTile) {
            block.clear();
            for (int y = by; y < std::min(by + surfaceTile, h); ++y)
                for (int x = bx; x < std::min(bx + surfaceTile, w); ++x) {
                    generator.pixelSamples(x, y, pixel.data());
                    for (int s = 0; s < spp; ++s) {
                        const VisibilityRecord& r = buffer.at(x, y, s);
                        const Sample& p = pixel[std::size_t(s)];
                        block.push_back({r.hit(), r.depth, float(x) + p.pixelOffset.x,
                                         float(y) + p.pixelOffset.y, r.time, r.lens.x, r.lens.y});
                    }
                }
            const std::uint64_t bits = compressedBlockBits(block, scheme);
            report.blockBits.push_back(bits);
            report.blockSamples.push_back(std::uint32_t(block.size()));
            if (bits == 0) {
                ++report.clearBlocks;
                continue;
            }
            report.compressedBits += bits;
            report.uncompressedBits += kRawBits * block.size();
        }
    return report;
}

}  // namespace patchsim
