#pragma once
// The samples of one screen tile as rays, laid out for SIMD (US 8,791,945, step 7): made once per
// tile and frame, then traced by every group whose bounds cover the tile (ray_stream.h).
//
// Representation
// --------------
// Structure of arrays: each per-sample quantity is one array, so `kMaxLanes` consecutive samples
// load as one vector. The arrays are padded to a multiple of `kMaxLanes` with dead samples (time
// NaN, in no time range; no hit, depth 0).
//
// Order: by time bucket first. With motion, bucket k of B (B = samples per pixel, at most
// kMaxTimeBuckets) holds the times in [k/B, (k+1)/B); stratified sampling puts one sample of each
// pixel in each bucket. The samples of a time range therefore lie in one index range and those
// outside it cost nothing. Within a bucket, samples follow their pixels in Morton order, then
// their sample index, so the rays that meet a small box sit in few vectors. Without motion there
// is one bucket. The order depends only on the sample set, never on the geometry or the threads.
//
// Per sample: the ray (time t; origin on the lens plane z = 0; direction, whose z is
// the same for every camera ray), the constants of the 12-multiply-add moving-box test (1/d per
// axis, from which a = (1 - t)/d and b = t/d follow in two multiplies, and c = -o/d, 0 along z),
// the shear of the watertight triangle test (axes kx, ky, kz and sx, sy, sz), which axes the ray
// runs parallel to, its visibility-buffer record and lens sample, and the nearest hit so far
// (depth, patch, triangle, barycentrics) with the ray end z culling derives from it. Per batch of
// kMaxLanes samples: whether every ray shears along z (the fast path of the triangle test), whether
// any runs parallel to an axis, and which samples got a nearer hit during the tile (written back to
// the visibility buffer at the end).

#include <hwy/aligned_allocator.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "core/camera.h"
#include "core/memory_trace.h"
#include "core/rasterizer_options.h"
#include "core/ray.h"
#include "core/samples.h"
#include "core/time_range.h"
#include "rasterizer/common/tile_grid.h"
#include "rasterizer/common/visibility_buffer.h"
#include "rasterizer/common/watertight_triangle.h"
#include "rasterizer/patent/moving_box_ray.h"

namespace patchsim {

class PixelCounters;

// The widest vector the ray kernels use (16 floats: AVX-512); narrower targets split a batch.
inline constexpr int kMaxLanes = 16;
inline constexpr int kMaxTimeBuckets = 256;

// What every tile of a frame shares.
struct TileRayFrame {
    const Camera* camera;
    LensModel lens;
    SampleSource samples;
    int samplesPerPixel = 1;
    bool motion = false;  // samples vary in time: order them by time bucket
    int tileSize = 8;
    bool countPerSample = false;  // keep per-sample work for heat maps
    // The visibility buffer holds no hits yet: a tile's samples start without one instead of
    // reading the buffer.
    bool bufferStartsEmpty = false;
    // Nothing moves and there is no lens (Effects::screenPlaneSamples): each sample also keeps
    // its sub-pixel position for the edge-function test (screen_pass.h).
    bool screenPlane = false;
    // A lens and nothing moving (Effects::lensPlaneSamples): each sample also keeps its screen
    // position for the lens edge test (lens_pass.h).
    bool lensPlane = false;
};

// The camera as the ray setup needs it (rasterToScreen, makeCameraRay).
struct RayCameraConstants {
    float width, height, tanHalfFovY, aspect;
    float focusDistance, lensRadius;  // lensRadius 0: a pinhole
};

// Per-sample work for heat maps (the quantities of pixel_counters.h).
enum class SampleWork : std::uint8_t { Tested, Rays, BoxTests, TriangleTests, Visible, kCount };

class TileRays {
  public:
    // Allocates for the frame's largest tile; nothing is allocated per tile afterwards.
    explicit TileRays(const TileRayFrame& frame);
    // What that allocation comes to for tiles of `tileSize` pixels at `samplesPerPixel` (with
    // per-sample work kept, with the tile's samples generated rather than read from a table, and
    // with sub-pixel positions or screen positions kept, `planeSamples`):
    // each rasterizer worker holds one, so a frame's memory budget counts it once per worker.
    static std::uint64_t bytesFor(int tileSize, int samplesPerPixel, bool countPerSample,
                                  bool generatesSamples, bool planeSamples);

    // Makes the rays of tile `rect`; each sample's nearest hit so far comes from `buffer` (unless
    // the frame says it starts empty).
    void load(const TileRect& rect, const VisibilityBuffer& buffer);
    // Writes the samples that got a nearer hit back to `buffer`, and per-sample work to `pixels`.
    void store(VisibilityBuffer& buffer, PixelCounters* pixels) const;

    int count() const { return count_; }  // live samples
    const TileRect& rect() const { return rect_; }
    int samplesPerPixel() const { return frame_.samplesPerPixel; }
    // Without motion (one bucket): the first of pixel (x, y)'s samples, which are consecutive.
    int firstSampleOf(int x, int y) const {
        return rankOf_[std::size_t((y - rect_.y0) * frame_.tileSize + (x - rect_.x0))] *
               frame_.samplesPerPixel;
    }
    int padded() const { return padded_; }    // a multiple of kMaxLanes
    int buckets() const { return buckets_; }  // time buckets
    // The bucket of time t; monotone in t, so every sample of a bucket below bucketOf(tmin) has a
    // time below tmin.
    int bucketOf(float t) const {
        return buckets_ == 1 ? 0 : std::clamp(int(t * float(buckets_)), 0, buckets_ - 1);
    }
    // Samples [bucketBegin(b), bucketBegin(b + 1)) are bucket b's.
    int bucketBegin(int b) const { return bucketBegin_[std::size_t(b)]; }
    // The index range [first, last) holding every sample with time in `times`.
    void indexRange(TimeRange times, int& first, int& last) const;
    // The deepest depth bound (nearest hit, or the far plane) over the tile's samples; cached
    // until a nearer hit is written.
    float farthestDepthBound();
    void depthBoundsChanged() { farthestStale_ = true; }

    // The ray constants shared by every sample of the frame.
    float depthPerLambda() const { return depthPerLambda_; }
    float lambdaMin() const { return lambdaMin_; }
    // 1 / direction z, which every camera ray shares.
    float inverseZ() const { return 1.0f / -depthPerLambda_; }
    float farDepth() const { return farDepth_; }
    // The shear sz of a ray that shears along z: 1 / dz, which every camera ray shares.
    float shearAlongZ() const { return 1.0f / -depthPerLambda_; }
    // The slab-test ray of sample i (for the rare ray parallel to an axis).
    SlabRay slabRay(int i) const;
    // The scalar ray of sample i.
    Ray ray(int i) const;

    // Per sample (see the essay above).
    float* time;
    float* originX;
    float* originY;
    float* directionX;
    float* directionY;
    float* inverseX;  // 1 / direction, or 0 where the ray runs parallel to the axis
    float* inverseY;
    float* slabC[2];
    float* shearX;
    float* shearY;
    float* shearZ;
    std::int32_t* axisX;
    std::int32_t* axisY;
    std::int32_t* axisZ;
    std::int32_t* parallelAxes;  // bit k: the direction's k component is ~0
    std::uint32_t* record;
    float* lensU;
    float* lensV;
    float* bestDepth;
    std::int32_t* bestPatch;
    std::uint32_t* bestTriangle;
    float* bestB1;
    float* bestB2;
    // The ray parameter the current pass may hit up to. load() ends each ray at its sample's
    // depth bound (rayEndAtDepth of the nearest hit, or of the far plane), and a pass that finds a
    // nearer hit shortens it to that hit's end, so with z culling it stays the depth bound's end
    // and a pass starts from it as it stands; without, each pass sets its own.
    float* rayEnd;
    // With TileRayFrame::screenPlane: the sample's raster position on the sub-pixel grid
    // (screen_triangle.h), padded like the other arrays, with room for a vector read past the end.
    float* subpixelX = nullptr;  // integers below 2^24, exact in float
    float* subpixelY = nullptr;
    // With TileRayFrame::lensPlane: the sample's position on the plane z = -1 (rasterToScreen's,
    // as the ray's), padded the same way; its lens point is the ray's origin (originX, originY).
    float* screenX = nullptr;
    float* screenY = nullptr;
    std::uint32_t* work[std::size_t(SampleWork::kCount)];  // only with countPerSample

    // Whether every ray shears along z (the fast path of the triangle test), and whether any
    // runs parallel to an axis (those take the scalar box test).
    bool allShearAlongZ() const { return allAlongZ_; }
    // Whether every sample's time is 0 (nothing varies over the shutter): a vertex blended to it
    // is its t=0 position.
    bool allAtShutterOpen() const { return allAtOpen_; }
    // Whether every ray starts at the origin, +0 to the bit (a pinhole camera): a vertex moved to
    // it is the vertex itself.
    bool allAtOrigin() const { return allAtOrigin_; }
    bool anyParallel() const { return anyParallel_; }
    // Per batch of kMaxLanes samples: bit j, sample j of the batch got a nearer hit in this tile.
    std::uint16_t* changed;
    // When the hardware models memory: where the passes' z reads and visibility writes are
    // recorded (the ray kernels mark reads, commitPass the writes).
    RegionTraceWriter* trace = nullptr;
    void traceReads(int first, int last, TimeRange times) const {
        for (int i = first; i < last; ++i)
            if (times.contains(time[i])) trace->read(record[i]);
    }
    // Ends a pass over samples [first, last): the samples it improved (passImproved) are marked
    // changed, and counted as visible in the per-sample work; returns how many.
    std::int64_t commitPass(int first, int last);

    // The rays of one level of a descent that met one box: their sample indices and, beside
    // them, the per-ray data of the box test, packed in the same order. The next level loads
    // that data as vectors instead of gathering it through the indices; the ray end is not
    // carried, since a hit found after the list was written may shorten it. In a tile whose rays
    // all start at the origin (allAtOrigin) c is a zero, and its arrays are left unwritten.
    struct RayList {
        std::int32_t* index;
        float* time;
        float* inverseX;
        float* inverseY;
        float* slabC[2];
    };

    // Scratch of the ray kernels: two ray lists per level of a descent, one per child (each
    // array with room for a vector written past the end), and per batch the samples a pass
    // improved.
    RayList levelList(int level, int child) {
        const auto slot = std::size_t(2 * level + child);
        float* floats = listFloats_.get() + slot * kListFloatArrays * listStride_;
        return {lists_.get() + slot * listStride_,
                floats,
                floats + listStride_,
                floats + 2 * listStride_,
                {floats + 3 * listStride_, floats + 4 * listStride_}};
    }
    std::uint16_t* passImproved() { return improved_.get(); }
    // A leaf's distinct vertices sheared for a vector of rays: 3 x kMaxLanes floats each.
    float* vertexScratch() { return vertices_.get(); }

  private:
    // The tile's pixels in Morton order, and the samples of the k-th.
    int pixelCount(const TileRect& rect);
    void pixelSamples(int k, const Sample*& samples, const Vec2*& disk);
    void orderByBucket(const TileRect& rect);
    bool placeOnePerBucket(int pixels);
    void place(int i, int k, int j);
    void startHits(const VisibilityBuffer& buffer);
    void summarize();

    TileRayFrame frame_;
    TileRect rect_{};
    float depthPerLambda_ = 1, lambdaMin_ = 0, farDepth_ = 0;
    int capacity_ = 0, count_ = 0, padded_ = 0, buckets_ = 1;
    float farthest_ = 0;
    bool farthestStale_ = true;
    bool allAlongZ_ = true, anyParallel_ = false, allAtOpen_ = false, allAtOrigin_ = false;
    std::vector<int> bucketBegin_;       // buckets + 1
    std::vector<std::uint16_t> morton_;  // the tile's pixels (y * tileSize + x) in Morton order
    // The current tile's pixels (x, y) in Morton order, and each sample's bucket in that order.
    std::vector<std::array<int, 2>> pixels_;
    struct PixelSamples {
        const Sample* samples;
        const Vec2* disk;
        Vec2 corner;                // the pixel's top-left corner in raster space
        std::uint32_t firstRecord;  // its first sample's visibility-buffer index
    };
    std::vector<PixelSamples> pixelSamples_;  // by Morton rank
    std::vector<std::uint16_t> rankOf_;       // a pixel's Morton rank, by y * tileSize + x
    std::vector<std::uint16_t> bucket_;
    // The generator's samples of the tile (a table's are read in place).
    std::vector<Sample> generated_;
    std::vector<Vec2> generatedDisk_;
    hwy::AlignedFreeUniquePtr<float[]> floats_;
    hwy::AlignedFreeUniquePtr<float[]> subpixels_;
    hwy::AlignedFreeUniquePtr<std::int32_t[]> ints_;
    hwy::AlignedFreeUniquePtr<std::uint32_t[]> counts_;
    hwy::AlignedFreeUniquePtr<std::uint16_t[]> changed_, improved_;
    static constexpr std::size_t kListFloatArrays = 5;  // RayList's float arrays
    hwy::AlignedFreeUniquePtr<std::int32_t[]> lists_;
    hwy::AlignedFreeUniquePtr<float[]> listFloats_;
    hwy::AlignedFreeUniquePtr<float[]> vertices_;
    std::size_t listStride_ = 0;
};

// From each sample's time, raster position (staged in directionX/Y) and lens point on the disk
// (staged in originX/Y) to its ray and the constants of its tests (tile_ray_setup.cpp, SIMD).
void computeRayConstants(TileRays& rays, const RayCameraConstants& camera);

}  // namespace patchsim
