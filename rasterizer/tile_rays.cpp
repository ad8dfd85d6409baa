#include "rasterizer/tile_rays.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "rasterizer/pixel_counters.h"
#include "rasterizer/ray_stream.h"
#include "rasterizer/z_culling.h"

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
constexpr int kFloatArrays = 24;
constexpr int kIntArrays = 8;

}  // namespace

TileRays::TileRays(const TileRayFrame& frame) : frame_(frame) {
    const int spp = frame.samplesPerPixel;
    const int s = frame.tileSize;
    capacity_ = roundUpToLanes(s * s * spp);
    depthPerLambda_ = frame.lens.radius > 0 ? frame.lens.focusDistance : 1.0f;
    lambdaMin_ = frame.camera->nearPlane() / depthPerLambda_;
    farDepth_ = frame.camera->farPlane();
    buckets_ = frame.motion ? std::clamp(spp, 1, kMaxTimeBuckets) : 1;
    bucketBegin_.assign(std::size_t(buckets_) + 1, 0);
    for (int y = 0; y < s; ++y)
        for (int x = 0; x < s; ++x) morton_.push_back(std::uint16_t(y * s + x));
    std::sort(morton_.begin(), morton_.end(), [s](std::uint16_t a, std::uint16_t b) {
        return mortonCode(a % unsigned(s), a / unsigned(s)) <
               mortonCode(b % unsigned(s), b / unsigned(s));
    });
    stagedSamples_.resize(std::size_t(s * s * spp));
    stagedDisk_.resize(stagedSamples_.size());
    stagedRecord_.resize(stagedSamples_.size());

    const auto n = std::size_t(capacity_);
    floats_ = hwy::AllocateAligned<float>(n * kFloatArrays);
    float** floatArrays[kFloatArrays] = {
        &time,     &weight0,  &originX,  &originY,   &directionX, &directionY, &slabA[0], &slabA[1],
        &slabA[2], &slabB[0], &slabB[1], &slabB[2],  &slabC[0],   &slabC[1],   &shearX,   &shearY,
        &shearZ,   &lensU,    &lensV,    &bestDepth, &bestB1,     &bestB2,     &rayEnd,   nullptr};
    for (int a = 0; a < kFloatArrays; ++a)
        if (floatArrays[a]) *floatArrays[a] = floats_.get() + std::size_t(a) * n;
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
    lists_ = hwy::AllocateAligned<std::int32_t>(listStride_ * std::size_t(2 * kMaxStreamLevels));
}

void TileRays::indexRange(TimeRange times, int& first, int& last) const {
    if (times.isEmpty()) {
        first = last = 0;
        return;
    }
    first = bucketBegin_[std::size_t(bucketOf(std::max(times.lower, 0.0f)))];
    last = bucketBegin_[std::size_t(bucketOf(std::min(times.upper, 1.0f))) + 1];
}

void TileRays::gather(const TileRect& rect) {
    const int s = frame_.tileSize, spp = frame_.samplesPerPixel;
    const auto width = std::size_t(frame_.camera->width());
    count_ = 0;
    for (std::uint16_t local : morton_) {
        const int x = rect.x0 + local % s, y = rect.y0 + local / s;
        if (x >= rect.x1 || y >= rect.y1) continue;
        const auto at = std::size_t(count_);
        frame_.samples.pixel(x, y, &stagedSamples_[at], &stagedDisk_[at]);
        const std::size_t first = (std::size_t(y) * width + std::size_t(x)) * std::size_t(spp);
        for (int k = 0; k < spp; ++k)
            stagedRecord_[at + std::size_t(k)] = std::uint32_t(first + std::size_t(k));
        count_ += spp;
    }
}

// A stable counting sort by time bucket (within a bucket the Morton pixel order stays), into the
// arrays the vector setup reads: time, raster position, lens point, record, lens sample.
void TileRays::orderByBucket() {
    std::fill(bucketBegin_.begin(), bucketBegin_.end(), 0);
    for (int i = 0; i < count_; ++i)
        ++bucketBegin_[std::size_t(bucketOf(stagedSamples_[std::size_t(i)].time)) + 1];
    for (int b = 0; b < buckets_; ++b)
        bucketBegin_[std::size_t(b) + 1] += bucketBegin_[std::size_t(b)];
    const auto spp = std::uint32_t(frame_.samplesPerPixel);
    const auto width = std::uint32_t(frame_.camera->width());
    std::vector<int>& next = bucketBegin_;  // advanced while filling, then restored
    for (int j = 0; j < count_; ++j) {
        const Sample& smp = stagedSamples_[std::size_t(j)];
        const int i = next[std::size_t(bucketOf(smp.time))]++;
        const std::uint32_t rec = stagedRecord_[std::size_t(j)];
        const std::uint32_t pixel = rec / spp;
        const Vec2 raster = Vec2(float(pixel % width), float(pixel / width)) + smp.pixelOffset;
        time[i] = smp.time;
        directionX[i] = raster.x;
        directionY[i] = raster.y;
        originX[i] = stagedDisk_[std::size_t(j)].x;
        originY[i] = stagedDisk_[std::size_t(j)].y;
        record[i] = rec;
        lensU[i] = smp.lens.x;
        lensV[i] = smp.lens.y;
    }
    for (int b = buckets_; b > 0; --b) next[std::size_t(b)] = next[std::size_t(b) - 1];
    next[0] = 0;
}

void TileRays::setFlags() {
    allAlongZ_ = true;
    anyParallel_ = false;
    for (int i = 0; i < count_; ++i) {
        allAlongZ_ = allAlongZ_ && axisX[i] == 1 && axisY[i] == 0 && axisZ[i] == 2;
        anyParallel_ = anyParallel_ || parallelAxes[i] != 0;
    }
    for (int b = 0; b < padded_ / kMaxLanes; ++b) changed[b] = 0;
}

void TileRays::load(const TileRect& rect, const VisibilityBuffer& buffer) {
    gather(rect);
    orderByBucket();
    padded_ = roundUpToLanes(count_);
    // Dead samples: in no time range (NaN fails every comparison), never hit, depth bound 0.
    for (int i = count_; i < padded_; ++i) {
        time[i] = directionX[i] = directionY[i] = originX[i] = originY[i] =
            std::numeric_limits<float>::quiet_NaN();
        record[i] = 0;
    }
    const Camera& camera = *frame_.camera;
    computeRayConstants(*this, {float(camera.width()), float(camera.height()), camera.tanHalfFovY(),
                                camera.aspect(), frame_.lens.focusDistance, frame_.lens.radius});
    const std::vector<VisibilityRecord>& records = buffer.records();
    for (int i = 0; i < count_; ++i) {
        const VisibilityRecord& r = records[record[i]];
        bestDepth[i] = r.depth;
        bestPatch[i] = r.patch;
        bestTriangle[i] = r.triangle;
        bestB1[i] = r.b1;
        bestB2[i] = r.b2;
    }
    for (int i = count_; i < padded_; ++i) {
        axisX[i] = 1;
        axisY[i] = 0;
        axisZ[i] = 2;
        parallelAxes[i] = 0;
        bestDepth[i] = 0;
        bestPatch[i] = -1;
    }
    setFlags();
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
    std::vector<VisibilityRecord>& records = buffer.mutableRecords();
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
    const auto width = std::uint32_t(buffer.width());
    const auto spp = std::uint32_t(frame_.samplesPerPixel);
    for (int i = 0; i < count_; ++i) {
        const std::uint32_t pixel = record[i] / spp;
        for (std::size_t q = 0; q < std::size_t(SampleWork::kCount); ++q)
            pixels->add(int(pixel % width), int(pixel / width), q, work[q][i]);
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

ShearedRay TileRays::shearedRay(int i) const {
    return shearRay(ray(i));
}

}  // namespace patchsim
