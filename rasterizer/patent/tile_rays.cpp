#include "rasterizer/patent/tile_rays.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include "rasterizer/common/pixel_counters.h"
#include "rasterizer/common/screen_triangle.h"
#include "rasterizer/common/z_culling.h"
#include "rasterizer/patent/ray_stream.h"

namespace patchsim {

namespace {

std::uint32_t mortonCode(std::uint32_t x, std::uint32_t y) {
    std::uint32_t code = 0;
    for (int bit = 0; bit < 16; ++bit)
        code |= ((x >> bit) & 1u) << (2 * bit) | ((y >> bit) & 1u) << (2 * bit + 1);
    return code;
}

int roundUpToLanes(int n) {
    return (n + kMaxLanes - 1) / kMaxLanes * kMaxLanes;
}

// The float arrays of TileRays, in the order they are carved out of one allocation.
constexpr int kFloatArrays = 18;
constexpr int kIntArrays = 8;

}  // namespace

TileRays::TileRays(const TileRayFrame& frame) : frame_(frame) {
    const int spp = frame.samplesPerPixel;
    const int s = frame.tileSize;
    capacity_ = roundUpToLanes(s * s * spp);
    depthPerLambda_ = frame.lens.radius > 0 ? frame.lens.focusDistance : 1.0f;
    lambdaMin_ = frame.camera->nearPlane() / depthPerLambda_;
    farDepth_ = frame.camera->farPlane();
    // A screen-plane frame tests a pixel's samples together, whatever their times.
    buckets_ = frame.motion && !frame.screenPlane ? std::clamp(spp, 1, kMaxTimeBuckets) : 1;
    bucketBegin_.assign(std::size_t(buckets_) + 1, 0);
    for (int y = 0; y < s; ++y)
        for (int x = 0; x < s; ++x) morton_.push_back(std::uint16_t(y * s + x));
    std::sort(morton_.begin(), morton_.end(), [s](std::uint16_t a, std::uint16_t b) {
        return mortonCode(a % unsigned(s), a / unsigned(s)) <
               mortonCode(b % unsigned(s), b / unsigned(s));
    });
    bucket_.resize(std::size_t(s * s * spp));
    pixels_.reserve(std::size_t(s * s));
    pixelSamples_.resize(std::size_t(s * s));
    rankOf_.resize(std::size_t(s * s));
    if (!frame.samples.table) {
        generated_.resize(bucket_.size());
        generatedDisk_.resize(bucket_.size());
    }

    const auto n = std::size_t(capacity_);
    floats_ = hwy::AllocateAligned<float>(n * kFloatArrays);
    float** floatArrays[kFloatArrays] = {&time,     &originX,  &originY,  &directionX, &directionY,
                                         &inverseX, &inverseY, &slabC[0], &slabC[1],   &shearX,
                                         &shearY,   &shearZ,   &lensU,    &lensV,      &bestDepth,
                                         &bestB1,   &bestB2,   &rayEnd};
    for (int a = 0; a < kFloatArrays; ++a) *floatArrays[a] = floats_.get() + std::size_t(a) * n;
    if (frame.screenPlane || frame.lensPlane) {
        subpixels_ = hwy::AllocateAligned<float>(2 * (n + kMaxLanes));
        std::fill_n(subpixels_.get(), 2 * (n + kMaxLanes), 0.0f);  // vector reads past the end
        (frame.screenPlane ? subpixelX : screenX) = subpixels_.get();
        (frame.screenPlane ? subpixelY : screenY) = subpixels_.get() + n + kMaxLanes;
    }
    ints_ = hwy::AllocateAligned<std::int32_t>(n * kIntArrays);
    std::int32_t** intArrays[kIntArrays] = {&axisX,     &axisY,  &axisZ,  &parallelAxes,
                                            &bestPatch, nullptr, nullptr, nullptr};
    for (int a = 0; a < kIntArrays; ++a)
        if (intArrays[a]) *intArrays[a] = ints_.get() + std::size_t(a) * n;
    // Unsigned views of the spare int arrays.
    record = reinterpret_cast<std::uint32_t*>(ints_.get() + 5 * n);
    bestTriangle = reinterpret_cast<std::uint32_t*>(ints_.get() + 6 * n);
    for (auto& w : work) w = nullptr;
    if (frame.countPerSample) {
        counts_ = hwy::AllocateAligned<std::uint32_t>(n * std::size_t(SampleWork::kCount));
        for (std::size_t q = 0; q < std::size_t(SampleWork::kCount); ++q)
            work[q] = counts_.get() + q * n;
    }
    const std::size_t batches = n / kMaxLanes;
    changed_ = hwy::AllocateAligned<std::uint16_t>(batches);
    changed = changed_.get();
    improved_ = hwy::AllocateAligned<std::uint16_t>(batches);
    listStride_ = n + kMaxLanes;
    const auto listSlots = std::size_t(2 * kMaxStreamLevels);
    lists_ = hwy::AllocateAligned<std::int32_t>(listStride_ * listSlots);
    listFloats_ = hwy::AllocateAligned<float>(listStride_ * listSlots * kListFloatArrays);
    vertices_ = hwy::AllocateAligned<float>(std::size_t(3 * 3 * kMaxLeafTriangles * kMaxLanes));
}

std::uint64_t TileRays::bytesFor(int tileSize, int samplesPerPixel, bool countPerSample,
                                 bool generatesSamples, bool planeSamples) {
    const auto pixels = std::uint64_t(tileSize) * std::uint64_t(tileSize);
    const std::uint64_t samples = pixels * std::uint64_t(samplesPerPixel);
    const std::uint64_t n = (samples + kMaxLanes - 1) / kMaxLanes * kMaxLanes;
    const std::uint64_t listStride = n + kMaxLanes, listSlots = 2 * kMaxStreamLevels;
    std::uint64_t bytes = n * (kFloatArrays * sizeof(float) + kIntArrays * sizeof(std::int32_t));
    if (countPerSample) bytes += n * std::uint64_t(SampleWork::kCount) * sizeof(std::uint32_t);
    bytes += 2 * (n / kMaxLanes) * sizeof(std::uint16_t);  // changed_, improved_
    bytes += listStride * listSlots * (sizeof(std::int32_t) + kListFloatArrays * sizeof(float));
    bytes += std::uint64_t(3 * 3 * kMaxLeafTriangles * kMaxLanes) * sizeof(float);  // vertices_
    bytes += samples * sizeof(std::uint16_t);                                       // bucket_
    if (generatesSamples) bytes += samples * (sizeof(Sample) + sizeof(Vec2));
    if (planeSamples) bytes += 2 * (n + kMaxLanes) * sizeof(float);  // subpixelX/Y or screenX/Y
    bytes +=
        pixels * (2 * sizeof(std::uint16_t) + sizeof(std::array<int, 2>) + sizeof(PixelSamples));
    bytes += std::uint64_t(kMaxTimeBuckets + 1) * sizeof(int);  // bucketBegin_
    return bytes;
}

std::int64_t TileRays::commitPass(int first, int last) {
    const std::uint16_t* improved = improved_.get();
    std::int64_t visible = 0;
    for (int b = first / kMaxLanes; b < (last + kMaxLanes - 1) / kMaxLanes; ++b) {
        if (!improved[b]) continue;
        visible += std::popcount(improved[b]);
        changed[b] |= improved[b];
        if (trace != nullptr)
            for (unsigned rest = improved[b]; rest; rest &= rest - 1)
                trace->wrote(
                    record[std::size_t(b) * kMaxLanes + std::size_t(std::countr_zero(rest))]);
        if (work[0] != nullptr)
            for (unsigned rest = improved[b]; rest; rest &= rest - 1)
                ++work[std::size_t(SampleWork::Visible)]
                      [std::size_t(b) * kMaxLanes + std::size_t(std::countr_zero(rest))];
    }
    if (visible) depthBoundsChanged();
    return visible;
}

void TileRays::indexRange(TimeRange times, int& first, int& last) const {
    if (times.isEmpty()) {
        first = last = 0;
        return;
    }
    first = bucketBegin_[std::size_t(bucketOf(std::max(times.lower, 0.0f)))];
    last = bucketBegin_[std::size_t(bucketOf(std::min(times.upper, 1.0f))) + 1];
}

int TileRays::pixelCount(const TileRect& rect) {
    const int s = frame_.tileSize;
    pixels_.clear();
    for (std::uint16_t local : morton_) {
        const int x = rect.x0 + local % s, y = rect.y0 + local / s;
        if (x >= rect.x1 || y >= rect.y1) continue;
        rankOf_[local] = std::uint16_t(pixels_.size());
        pixels_.push_back({x, y});
    }
    return int(pixels_.size());
}

void TileRays::pixelSamples(int k, const Sample*& samples, const Vec2*& disk) {
    const std::size_t at = std::size_t(k) * std::size_t(frame_.samplesPerPixel);
    Sample* generated = generated_.empty() ? nullptr : &generated_[at];
    Vec2* generatedDisk = generatedDisk_.empty() ? nullptr : &generatedDisk_[at];
    frame_.samples.pixel(pixels_[std::size_t(k)][0], pixels_[std::size_t(k)][1], generated,
                         generatedDisk, samples, disk);
}

// Sample i of the order is sample j of pixel k. Inlined into the loops that place every sample:
// a call per sample was 3 to 7% of a one-thread `default` row (docs/PERFORMANCE.md).
[[gnu::always_inline]] inline void TileRays::place(int i, int k, int j) {
    const PixelSamples& p = pixelSamples_[std::size_t(k)];
    const Sample& smp = p.samples[j];
    const Vec2 raster = p.corner + smp.pixelOffset;
    time[i] = smp.time;
    directionX[i] = raster.x;
    directionY[i] = raster.y;
    originX[i] = p.disk[j].x;
    originY[i] = p.disk[j].y;
    record[i] = p.firstRecord + std::uint32_t(j);
    lensU[i] = smp.lens.x;
    lensV[i] = smp.lens.y;
    if (frame_.screenPlane) {
        subpixelX[i] = float(sampleSubpixel(int(p.corner.x), smp.pixelOffset.x));
        subpixelY[i] = float(sampleSubpixel(int(p.corner.y), smp.pixelOffset.y));
    }
}

// A stable counting sort of the tile's samples by time bucket (within a bucket the Morton pixel
// order stays), into the arrays the vector setup reads: time, raster position, lens point,
// record, lens sample.
void TileRays::orderByBucket(const TileRect& rect) {
    const int spp = frame_.samplesPerPixel;
    const int pixels = pixelCount(rect);
    count_ = pixels * spp;
    const auto width = std::uint32_t(frame_.camera->width());
    // The samples are read row by row (the order they lie in memory), each pixel's kept at its
    // Morton rank.
    for (int y = rect.y0; y < rect.y1; ++y)
        for (int x = rect.x0; x < rect.x1; ++x) {
            const int k = rankOf_[std::size_t((y - rect.y0) * frame_.tileSize + (x - rect.x0))];
            PixelSamples& p = pixelSamples_[std::size_t(k)];
            pixelSamples(k, p.samples, p.disk);
            p.corner = Vec2(float(x), float(y));
            p.firstRecord = (std::uint32_t(y) * width + std::uint32_t(x)) * std::uint32_t(spp);
        }
    if (buckets_ == 1) {  // the pixel order is the order
        bucketBegin_ = {0, count_};
        for (int k = 0; k < pixels; ++k)
            for (int j = 0; j < spp; ++j) place(k * spp + j, k, j);
        return;
    }
    if (placeOnePerBucket(pixels)) return;
    std::fill(bucketBegin_.begin(), bucketBegin_.end(), 0);
    for (int k = 0; k < pixels; ++k) {
        const Sample* samples = pixelSamples_[std::size_t(k)].samples;
        for (int j = 0; j < spp; ++j) {
            const int b = bucketOf(samples[j].time);
            bucket_[std::size_t(k * spp + j)] = std::uint16_t(b);
            ++bucketBegin_[std::size_t(b) + 1];
        }
    }
    for (int b = 0; b < buckets_; ++b)
        bucketBegin_[std::size_t(b) + 1] += bucketBegin_[std::size_t(b)];
    std::vector<int>& next = bucketBegin_;  // advanced while filling, then restored
    for (int k = 0; k < pixels; ++k)
        for (int j = 0; j < spp; ++j) place(next[bucket_[std::size_t(k * spp + j)]]++, k, j);
    for (int b = buckets_; b > 0; --b) next[std::size_t(b)] = next[std::size_t(b) - 1];
    next[0] = 0;
}

// With as many buckets as samples per pixel, stratified times put one sample of every pixel in
// each bucket. The stable sort's order is then known without counting: bucket b holds one sample
// of each pixel, in Morton order, so pixel k's sample in bucket b goes to b * pixels + k. Returns
// false, after placing some samples that orderByBucket's counting sort then overwrites, when a
// pixel has two samples in one bucket (jitter that rounds up to the next stratum's edge).
bool TileRays::placeOnePerBucket(int pixels) {
    const int spp = frame_.samplesPerPixel;
    if (buckets_ != spp || spp > 64) return false;
    const std::uint64_t everyBucket = spp == 64 ? ~std::uint64_t(0) : (std::uint64_t(1) << spp) - 1;
    for (int k = 0; k < pixels; ++k) {
        const Sample* samples = pixelSamples_[std::size_t(k)].samples;
        std::uint64_t seen = 0;
        for (int j = 0; j < spp; ++j) {
            const int b = bucketOf(samples[j].time);
            seen |= std::uint64_t(1) << b;
            place(b * pixels + k, k, j);
        }
        if (seen != everyBucket) return false;
    }
    for (int b = 0; b <= buckets_; ++b) bucketBegin_[std::size_t(b)] = b * pixels;
    return true;
}

void TileRays::startHits(const VisibilityBuffer& buffer) {
    if (frame_.bufferStartsEmpty) {
        const VisibilityRecord none;
        std::fill_n(bestDepth, count_, none.depth);
        std::fill_n(bestPatch, count_, none.patch);
        std::fill_n(bestTriangle, count_, none.triangle);
        std::fill_n(bestB1, count_, none.b1);
        std::fill_n(bestB2, count_, none.b2);
        return;
    }
    const std::span<const VisibilityRecord> records = buffer.records();
    for (int i = 0; i < count_; ++i) {
        const VisibilityRecord& r = records[record[i]];
        bestDepth[i] = r.depth;
        bestPatch[i] = r.patch;
        bestTriangle[i] = r.triangle;
        bestB1[i] = r.b1;
        bestB2[i] = r.b2;
    }
}

void TileRays::summarize() {
    // Branch-free accumulations, so the loop vectorizes.
    int offAxis = 0, parallel = 0, moving = 0;
    std::uint32_t originBits = 0;
    for (int i = 0; i < count_; ++i) {
        offAxis |= (axisX[i] ^ 1) | axisY[i] | (axisZ[i] ^ 2);
        parallel |= parallelAxes[i];
        moving |= time[i] != 0.0f;
        originBits |=
            std::bit_cast<std::uint32_t>(originX[i]) | std::bit_cast<std::uint32_t>(originY[i]);
    }
    allAtOrigin_ = originBits == 0;
    allAlongZ_ = offAxis == 0;
    anyParallel_ = parallel != 0;
    allAtOpen_ = moving == 0;
}

void TileRays::load(const TileRect& rect, const VisibilityBuffer& buffer) {
    // The tile's rows of samples and of visibility records are short runs far apart, which the
    // hardware prefetcher finds too late: ask for them now (the records are written back at the
    // end).
    for (int y = rect.y0; y < rect.y1; ++y) {
        frame_.samples.prefetch(rect.x0, rect.x1, y);
        const auto* records = reinterpret_cast<const char*>(&buffer.at(rect.x0, y, 0));
        const std::size_t bytes = std::size_t(rect.x1 - rect.x0) *
                                  std::size_t(frame_.samplesPerPixel) * sizeof(VisibilityRecord);
        for (std::size_t b = 0; b < bytes; b += 64) __builtin_prefetch(records + b, 1);
    }
    rect_ = rect;
    orderByBucket(rect);
    padded_ = roundUpToLanes(count_);
    // Dead samples: in no time range (NaN fails every comparison), never hit, depth bound 0.
    for (int i = count_; i < padded_; ++i) {
        time[i] = directionX[i] = directionY[i] = originX[i] = originY[i] =
            std::numeric_limits<float>::quiet_NaN();
        record[i] = 0;
        if (frame_.screenPlane) subpixelX[i] = subpixelY[i] = 0.0f;
        if (frame_.lensPlane) screenX[i] = screenY[i] = 0.0f;
    }
    const Camera& camera = *frame_.camera;
    computeRayConstants(*this, {float(camera.width()), float(camera.height()), camera.tanHalfFovY(),
                                camera.aspect(), frame_.lens.focusDistance, frame_.lens.radius});
    startHits(buffer);
    for (int i = count_; i < padded_; ++i) {
        axisX[i] = 1;
        axisY[i] = 0;
        axisZ[i] = 2;
        parallelAxes[i] = 0;
        bestDepth[i] = 0;
        bestPatch[i] = -1;
    }
    for (int i = 0; i < padded_; ++i) {
        const float bound = bestDepth[i] < farDepth_ ? bestDepth[i] : farDepth_;
        rayEnd[i] = rayEndAtDepth(bound, depthPerLambda_);
    }
    summarize();
    std::fill(changed, changed + padded_ / kMaxLanes, std::uint16_t(0));
    if (frame_.countPerSample)
        for (auto* w : work) std::fill(w, w + padded_, 0u);
    farthestStale_ = true;
}

float TileRays::farthestDepthBound() {
    if (farthestStale_) {
        farthest_ = farthestBoundOf(bestDepth, padded_, farDepth_);
        farthestStale_ = false;
    }
    return farthest_;
}

void TileRays::store(VisibilityBuffer& buffer, PixelCounters* pixels) const {
    const std::span<VisibilityRecord> records = buffer.mutableRecords();
    for (int b = 0; b < padded_ / kMaxLanes; ++b) {
        if (!changed[b]) continue;
        for (int lane = 0; lane < kMaxLanes; ++lane) {
            if (!(changed[b] >> lane & 1)) continue;
            const int i = b * kMaxLanes + lane;
            VisibilityRecord& r = records[record[i]];
            r.depth = bestDepth[i];
            r.patch = bestPatch[i];
            r.triangle = bestTriangle[i];
            r.b1 = bestB1[i];
            r.b2 = bestB2[i];
            r.time = time[i];
            r.lens = {lensU[i], lensV[i]};
        }
    }
    if (!pixels || !frame_.countPerSample) return;
    // Each per-sample count's heat map.
    constexpr std::size_t kQuantity[] = {
        pixelQuantity("samples_tested"), pixelQuantity("rays_cast"), pixelQuantity("ray_box_tests"),
        pixelQuantity("ray_triangle_tests"), pixelQuantity("visibility_samples")};
    static_assert(std::size(kQuantity) == std::size_t(SampleWork::kCount));
    const auto width = std::uint32_t(buffer.width());
    const auto spp = std::uint32_t(frame_.samplesPerPixel);
    for (int i = 0; i < count_; ++i) {
        const std::uint32_t pixel = record[i] / spp;
        for (std::size_t q = 0; q < std::size_t(SampleWork::kCount); ++q)
            pixels->add(int(pixel % width), int(pixel / width), kQuantity[q], work[q][i]);
    }
}

SlabRay TileRays::slabRay(int i) const {
    return makeSlabRay(ray(i));
}

Ray TileRays::ray(int i) const {
    Ray r;
    r.origin = {originX[i], originY[i], 0.0f};
    r.direction = {directionX[i], directionY[i], -depthPerLambda_};
    r.time = time[i];
    r.depthPerLambda = depthPerLambda_;
    r.lambdaMin = lambdaMin_;
    r.lambdaMax = rayEnd[i];
    return r;
}

}  // namespace patchsim
