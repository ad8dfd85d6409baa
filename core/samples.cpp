#include "core/samples.h"

#include <algorithm>
#include <cmath>

#include "core/parallel.h"

namespace patchsim {

std::uint64_t mix64(std::uint64_t x) {
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

namespace {

float toUnit(std::uint64_t bits) {
    // 24 random bits: exactly representable, strictly below 1.
    return float(bits >> 40) * (1.0f / 16777216.0f);
}

// The smallest all-ones mask covering [0, n).
std::uint32_t maskCovering(std::uint32_t n) {
    std::uint32_t w = n - 1;
    w |= w >> 1;
    w |= w >> 2;
    w |= w >> 4;
    w |= w >> 8;
    w |= w >> 16;
    return w;
}

}  // namespace

SampleGenerator::SampleGenerator(std::uint64_t seed, int samplesPerPixel, const Effects& effects,
                                 SamplePattern pattern, float stillTime)
    : seed_(seed),
      spp_(samplesPerPixel),
      // A count below 1 makes no samples; the divisor must still not be 0.
      count_(std::uint32_t(std::max(samplesPerPixel, 1))),
      gridDivisor_(1),
      effects_(effects),
      pattern_(pattern) {
    recipe_.count = count_.divisor();
    recipe_.permutationMask = maskCovering(count_.divisor());
    const int side = int(std::lround(std::sqrt(double(samplesPerPixel))));
    if (side * side == samplesPerPixel) {
        recipe_.gridSide = std::uint32_t(side);
        gridDivisor_ = FixedDivisor(std::uint32_t(side));
    }
    recipe_.jitter = pattern != SamplePattern::Grid;
    recipe_.timeSamples = effects.timeSamples();
    recipe_.lensSamples = effects.defocus;
    // Grid times and lens coordinates reach both ends of [0, 1].
    recipe_.spread = recipe_.jitter ? float(recipe_.count)
                                    : float(std::max<std::uint32_t>(recipe_.count - 1, 1));
    recipe_.stillTime = stillTime;
}

// A random permutation of [0, n) evaluated at one index (cycle-walking hash permutation of
// Kensler's "Correlated multi-jittered sampling").
std::uint32_t SampleGenerator::permute(std::uint32_t i, std::uint32_t key) const {
    const std::uint32_t w = recipe_.permutationMask;
    do {
        i ^= key;
        i *= 0xe170893d;
        i ^= key >> 16;
        i ^= (i & w) >> 4;
        i ^= key >> 8;
        i *= 0x0929eb3f;
        i ^= key >> 23;
        i ^= (i & w) >> 1;
        i *= 1 | key >> 27;
        i *= 0x6935fa69;
        i ^= (i & w) >> 11;
        i *= 0x74dcb303;
        i ^= (i & w) >> 2;
        i *= 0x9e501cc3;
        i ^= (i & w) >> 2;
        i *= 0xc860a3df;
        i &= w;
        i ^= i >> 5;
    } while (i >= count_.divisor());
    return count_.remainder(i + key);
}

SampleGenerator::PixelStreams SampleGenerator::pixelStreams(int x, int y) const {
    // Interleaved: every pixel draws from the streams of pixel (0, 0).
    if (pattern_ == SamplePattern::Interleaved) x = y = 0;
    const std::uint64_t pixelKey =
        mix64(seed_ ^ mix64((std::uint64_t(std::uint32_t(x)) << 32) | std::uint32_t(y)));
    PixelStreams p;
    for (std::uint64_t d = 0; d < 12; ++d)
        p.dimension[d] = mix64(pixelKey ^ (d * 0xd1b54a32d192ed03ull));
    return p;
}

Sample SampleGenerator::sampleOf(const PixelStreams& p, int index) const {
    const bool grid = pattern_ == SamplePattern::Grid;
    auto jitter = [&](int dimension) {
        return grid ? 0.0f : toUnit(mix64(p.dimension[dimension] ^ std::uint64_t(index)));
    };
    const auto n = std::uint32_t(spp_);
    const auto i = std::uint32_t(index);
    // Stratum of this sample in a dimension: a per-pixel permutation of the sample index.
    auto stratum = [&](int dimension) {
        return float(permute(i, std::uint32_t(p.dimension[dimension] >> 32)));
    };
    Sample s;
    if (recipe_.gridSide > 0) {
        const std::uint32_t cell = permute(i, std::uint32_t(p.dimension[1]));
        const float side = float(recipe_.gridSide);
        s.pixelOffset = {(float(gridDivisor_.remainder(cell)) + jitter(2)) / side,
                         (float(gridDivisor_.quotient(cell)) + jitter(3)) / side};
    } else {
        s.pixelOffset = {(stratum(4) + jitter(2)) / float(n), (stratum(5) + jitter(3)) / float(n)};
    }
    const float spread = recipe_.spread;
    s.time = effects_.timeSamples() ? (stratum(6) + jitter(7)) / spread : recipe_.stillTime;
    s.lens = effects_.defocus
                 ? Vec2((stratum(8) + jitter(9)) / spread, (stratum(10) + jitter(11)) / spread)
                 : Vec2(0.5f, 0.5f);
    // Guard against rounding up to 1 in the divisions above.
    s.pixelOffset = glm::min(s.pixelOffset, Vec2(0.99999994f));
    s.time = std::min(s.time, 1.0f);
    s.lens = glm::min(s.lens, Vec2(1.0f));
    return s;
}

Sample SampleGenerator::sample(int x, int y, int index) const {
    return sampleOf(pixelStreams(x, y), index);
}

void SampleGenerator::pixelSamples(int x, int y, Sample* out) const {
    if (spp_ < 1) return;
    makePixelSamples(kernelRecipe(), pixelStreams(x, y).dimension, out);
}

Vec2 concentricDisk(const Vec2& u) {
    const Vec2 o = 2.0f * u - Vec2(1.0f);
    if (o.x == 0 && o.y == 0) return Vec2(0);
    constexpr float kPiOver4 = 0.78539816339f;
    float r, theta;
    if (std::abs(o.x) > std::abs(o.y)) {
        r = o.x;
        theta = kPiOver4 * (o.y / o.x);
    } else {
        r = o.y;
        theta = 2 * kPiOver4 - kPiOver4 * (o.x / o.y);
    }
    return r * Vec2(std::cos(theta), std::sin(theta));
}

void SampleSource::prefetch(int x0, int x1, int y) const {
    if (!table || x0 >= x1) return;
    constexpr std::size_t kLine = 64;
    const auto spp = std::size_t(table->samplesPerPixel());
    const auto* samples = reinterpret_cast<const char*>(table->pixel(x0, y));
    const auto* disk = reinterpret_cast<const char*>(table->disk(x0, y));
    const std::size_t pixels = std::size_t(x1 - x0);
    for (std::size_t b = 0; b < pixels * spp * sizeof(Sample); b += kLine)
        __builtin_prefetch(samples + b);
    for (std::size_t b = 0; b < pixels * spp * sizeof(Vec2); b += kLine)
        __builtin_prefetch(disk + b);
}

SampleTable::SampleTable(const SampleGenerator& generator, int width, int height, int threads)
    : width_(width),
      spp_(generator.samplesPerPixel()),
      samples_(std::size_t(width) * std::size_t(height) * std::size_t(spp_)),
      disk_(samples_.size()) {
    parallelFor(std::size_t(height), threads, [&](int, std::size_t row) {
        const int y = int(row);
        for (int x = 0; x < width; ++x) {
            const std::size_t first = index(x, y);
            generator.pixelSamples(x, y, &samples_[first]);
            for (int s = 0; s < spp_; ++s)
                disk_[first + std::size_t(s)] =
                    concentricDisk(samples_[first + std::size_t(s)].lens);
        }
    });
}

void SampleSource::pixel(int x, int y, Sample* samples, Vec2* disk, const Sample*& pixelSamples,
                         const Vec2*& pixelDisk) const {
    if (table) {
        pixelSamples = table->pixel(x, y);
        pixelDisk = table->disk(x, y);
        return;
    }
    generator->pixelSamples(x, y, samples);
    for (int s = 0; s < generator->samplesPerPixel(); ++s)
        disk[s] = concentricDisk(samples[s].lens);
    pixelSamples = samples;
    pixelDisk = disk;
}

}  // namespace patchsim
