#include "rasterizer/patent/tile_rays.h"

#include <gtest/gtest.h>
#include <malloc.h>

#include <algorithm>
#include <cstring>
#include <random>
#include <vector>

#include "rasterizer/common/watertight_triangle.h"
#include "rasterizer/common/z_culling.h"
#include "rasterizer/patent/moving_box_ray.h"

namespace patchsim {
namespace {

// A wide field of view, so rays at the frame's sides are not z-dominant (their shear takes
// another axis).
Camera testCamera(int width, int height, float fov) {
    CameraDesc desc;
    desc.open = {{0, 0, 5}, {0, 0, 0}, {0, 1, 0}};
    desc.close = desc.open;
    desc.fovYDegrees = fov;
    return Camera(desc, {}, width, height);
}

bool sameBits(float a, float b) {
    return std::memcmp(&a, &b, sizeof a) == 0;
}

// A tile grid whose last column and row are partial tiles.
const TileGrid kGrid{19, 13, 8};

struct Frame {
    Camera camera;
    SampleGenerator generator;
    TileRayFrame tiles;
    Frame(SamplePattern pattern, bool motion, float lensRadius, float fov = 40.0f,
          const TileGrid& grid = kGrid, int spp = 9)
        : camera(testCamera(grid.width, grid.height, fov)),
          generator(11, spp, Effects{motion, false, lensRadius > 0, false}, pattern),
          tiles{&camera, {lensRadius, 4.0f}, {&generator, nullptr}, spp, motion, grid.tileSize,
                false} {}
};

std::uint32_t mortonOf(int x, int y) {
    std::uint32_t code = 0;
    for (int bit = 0; bit < 8; ++bit)
        code |= std::uint32_t(((x >> bit) & 1) << (2 * bit) | ((y >> bit) & 1) << (2 * bit + 1));
    return code;
}

// The tile `r` just loaded into `rays` holds each of its samples once (marked in `seen`, by
// record), with `expected`'s time and lens point, ordered by time bucket, then Morton pixel, then
// sample index; each bucket's samples lie in its index range; the samples past the live ones are
// dead.
template <class ExpectedSample>
void expectOrderedByBucketThenMortonPixel(const TileRays& rays, const TileRect& r, int spp,
                                          const ExpectedSample& expected, std::vector<int>& seen) {
    ASSERT_EQ(rays.count(), (r.x1 - r.x0) * (r.y1 - r.y0) * spp);
    ASSERT_EQ(rays.padded() % kMaxLanes, 0);
    std::uint64_t previousKey = 0;
    for (int i = 0; i < rays.count(); ++i) {
        const int pixel = int(rays.record[i]) / spp, s = int(rays.record[i]) % spp;
        const int x = pixel % kGrid.width, y = pixel / kGrid.width;
        ASSERT_TRUE(x >= r.x0 && x < r.x1 && y >= r.y0 && y < r.y1);
        ++seen[rays.record[i]];
        const Sample e = expected(x, y, s);
        EXPECT_EQ(rays.time[i], e.time);
        EXPECT_EQ(rays.lensU[i], e.lens.x);
        EXPECT_EQ(rays.lensV[i], e.lens.y);
        const int bucket = rays.bucketOf(rays.time[i]);
        EXPECT_TRUE(i >= rays.bucketBegin(bucket) && i < rays.bucketBegin(bucket + 1))
            << "sample " << i << " outside bucket " << bucket << "'s range";
        // Bucket, then Morton pixel within the tile, then sample index.
        const std::uint64_t key = std::uint64_t(bucket) << 40 |
                                  std::uint64_t(mortonOf(x - r.x0, y - r.y0)) << 8 |
                                  std::uint64_t(s);
        EXPECT_GT(key + 1, previousKey) << "sample " << i;
        previousKey = key + 1;
    }
    for (int i = rays.count(); i < rays.padded(); ++i)
        EXPECT_TRUE(std::isnan(rays.time[i])) << "a dead sample has no time";
}

TEST(TileRays, EverySampleOnceInItsTileByTimeBucketThenMortonPixel) {
    for (SamplePattern pattern : {SamplePattern::Stratified, SamplePattern::Grid})
        for (bool motion : {true, false}) {
            Frame f(pattern, motion, 0.2f);
            const VisibilityBuffer buffer(kGrid.width, kGrid.height, 9, f.camera.farPlane());
            TileRays rays(f.tiles);
            EXPECT_EQ(rays.buckets(), motion ? 9 : 1);
            std::vector<int> seen(buffer.records().size(), 0);
            const auto expected = [&](int x, int y, int s) { return f.generator.sample(x, y, s); };
            for (int ty = 0; ty < kGrid.tilesY(); ++ty)
                for (int tx = 0; tx < kGrid.tilesX(); ++tx) {
                    const TileRect r = kGrid.rect(tx, ty);
                    rays.load(r, buffer);
                    expectOrderedByBucketThenMortonPixel(rays, r, 9, expected, seen);
                }
            for (int n : seen) ASSERT_EQ(n, 1);
        }
}

// Stratified times put one sample of each pixel in each bucket, and the tile's order is then
// placed without counting; a pixel with two samples in one bucket (and none in another) takes
// the counting sort, whichever of the tile's pixels it is.
TEST(TileRays, APixelWithTwoSamplesInOneBucketKeepsTheOrder) {
    Frame f(SamplePattern::Stratified, true, 0.2f);
    SampleTable table(f.generator, kGrid.width, kGrid.height, 1);
    TileRayFrame tiles = f.tiles;
    tiles.samples.table = &table;
    const VisibilityBuffer buffer(kGrid.width, kGrid.height, 9, f.camera.farPlane());
    TileRays rays(tiles);
    const auto expected = [&](int x, int y, int s) { return table.pixel(x, y)[s]; };
    // The first, a middle (Morton rank 27 of 64) and the last pixel of tile (1, 0), a whole tile;
    // one pixel at a time.
    const TileRect r = kGrid.rect(1, 0);
    ASSERT_EQ((r.x1 - r.x0) * (r.y1 - r.y0), 64);
    for (const auto& [x, y] : {std::pair{8, 0}, std::pair{13, 3}, std::pair{15, 7}}) {
        ASSERT_TRUE(x >= r.x0 && x < r.x1 && y >= r.y0 && y < r.y1);
        // The table's own storage, edited for the test: sample 0 moves into sample 1's bucket.
        auto* samples = const_cast<Sample*>(table.pixel(x, y));
        const float before = samples[0].time;
        samples[0].time = samples[1].time;
        ASSERT_EQ(rays.bucketOf(samples[0].time), rays.bucketOf(samples[1].time));
        std::vector<int> seen(buffer.records().size(), 0);
        rays.load(r, buffer);
        expectOrderedByBucketThenMortonPixel(rays, r, 9, expected, seen);
        EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), rays.count());
        samples[0].time = before;
    }
}

// The vector setup makes exactly the rays, slab constants and shears the scalar functions make
// one sample at a time, including rays running parallel to an axis (grid samples on the centre
// lines) and rays that shear along x or y (a wide field of view).
TEST(TileRays, RaysEqualTheScalarRaysBitForBit) {
    // An even width and grid offsets of 0 and 1/2: some samples lie on the vertical centre line.
    const TileGrid grid{20, 14, 8};
    for (float lens : {0.0f, 0.3f})
        for (float fov : {40.0f, 140.0f}) {
            Frame f(SamplePattern::Grid, true, lens, fov, grid, 4);
            const VisibilityBuffer buffer(grid.width, grid.height, 4, f.camera.farPlane());
            TileRays rays(f.tiles);
            int parallel = 0, offAxis = 0;
            for (int ty = 0; ty < grid.tilesY(); ++ty)
                for (int tx = 0; tx < grid.tilesX(); ++tx) {
                    rays.load(grid.rect(tx, ty), buffer);
                    for (int i = 0; i < rays.count(); ++i) {
                        const int pixel = int(rays.record[i] / 4), s = int(rays.record[i] % 4);
                        const Sample smp =
                            f.generator.sample(pixel % grid.width, pixel / grid.width, s);
                        const Vec2 raster =
                            Vec2(float(pixel % grid.width), float(pixel / grid.width)) +
                            smp.pixelOffset;
                        const Ray expected =
                            makeCameraRay(f.camera, rasterToScreen(f.camera, raster),
                                          concentricDisk(smp.lens), smp.time, f.tiles.lens);
                        const Ray made = rays.ray(i);
                        for (int k = 0; k < 3; ++k) {
                            ASSERT_TRUE(sameBits(made.origin[k], expected.origin[k]));
                            ASSERT_TRUE(sameBits(made.direction[k], expected.direction[k]));
                        }
                        const SlabRay slab = makeSlabRay(expected);
                        // a and b follow from 1/d as the kernels compute them.
                        const float inverse[3] = {rays.inverseX[i], rays.inverseY[i],
                                                  rays.inverseZ()};
                        for (int k = 0; k < 3; ++k) {
                            ASSERT_TRUE(sameBits((1.0f - rays.time[i]) * inverse[k], slab.a[k]));
                            ASSERT_TRUE(sameBits(rays.time[i] * inverse[k], slab.b[k])) << k;
                        }
                        ASSERT_TRUE(sameBits(rays.slabC[0][i], slab.c[0]));
                        ASSERT_TRUE(sameBits(rays.slabC[1][i], slab.c[1]));
                        ASSERT_EQ(rays.parallelAxes[i] != 0,
                                  slab.parallel[0] || slab.parallel[1] || slab.parallel[2]);
                        const ShearedRay shear = shearRay(expected);
                        ASSERT_EQ(rays.axisX[i], shear.kx);
                        ASSERT_EQ(rays.axisY[i], shear.ky);
                        ASSERT_EQ(rays.axisZ[i], shear.kz);
                        ASSERT_TRUE(sameBits(rays.shearX[i], shear.sx));
                        ASSERT_TRUE(sameBits(rays.shearY[i], shear.sy));
                        ASSERT_TRUE(sameBits(rays.shearZ[i], shear.sz));
                        parallel += rays.parallelAxes[i] != 0;
                        offAxis += shear.kz != 2;
                    }
                }
            if (lens == 0.0f) {
                EXPECT_GT(parallel, 0) << "pinhole rays on the centre line run parallel to x";
            }
            if (fov > 90.0f) {
                EXPECT_GT(offAxis, 0) << "a wide view has rays that shear along x or y";
            }
        }
}

TEST(TileRays, ATimeRangeHoldsEverySampleInsideIt) {
    Frame f(SamplePattern::Stratified, true, 0.0f);
    const VisibilityBuffer buffer(kGrid.width, kGrid.height, 9, f.camera.farPlane());
    TileRays rays(f.tiles);
    rays.load(kGrid.rect(1, 0), buffer);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-0.1f, 1.1f);
    for (int trial = 0; trial < 500; ++trial) {
        TimeRange range{u(rng), u(rng)};
        int first, last;
        rays.indexRange(range, first, last);
        for (int i = 0; i < rays.count(); ++i) {
            if (range.contains(rays.time[i])) {
                ASSERT_TRUE(i >= first && i < last) << trial;
            }
        }
        if (range.isEmpty()) {
            EXPECT_EQ(first, last);
        }
    }
}

// The tile's far bound is the deepest of its samples' depth bounds (a sample without a hit sees
// to the far plane), and it follows hits written into the tile.
TEST(TileRays, FarthestBoundIsTheDeepestSampleStillOpen) {
    Frame f(SamplePattern::Stratified, false, 0.0f);
    const float far = f.camera.farPlane();
    VisibilityBuffer buffer(kGrid.width, kGrid.height, 9, far);
    TileRays rays(f.tiles);
    rays.load(kGrid.rect(0, 0), buffer);
    EXPECT_EQ(rays.farthestDepthBound(), far);  // nothing drawn
    VisibilityRecord hit;
    hit.patch = 0;
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x)
            for (int s = 0; s < 9; ++s) {
                hit.depth = 3.0f + float(x + y + s);
                buffer.offer(x, y, s, hit);
            }
    rays.load(kGrid.rect(0, 0), buffer);
    EXPECT_EQ(rays.farthestDepthBound(), 3.0f + 7 + 7 + 8);
    rays.bestDepth[0] = 2.0f * far;  // beyond the far plane: bounded by it
    rays.depthBoundsChanged();
    EXPECT_EQ(rays.farthestDepthBound(), far);
    rays.load(kGrid.rect(1, 1), buffer);  // another tile, still open
    EXPECT_EQ(rays.farthestDepthBound(), far);
}

// A loaded ray ends at its sample's depth bound: the nearest hit so far, or the far plane
// (z_culling.h), to the bit; a pass with z culling starts from that end.
TEST(TileRays, EveryRayStartsEndingAtItsDepthBound) {
    for (float lensRadius : {0.0f, 0.2f}) {
        Frame f(SamplePattern::Stratified, true, lensRadius);
        const float far = f.camera.farPlane();
        VisibilityBuffer buffer(kGrid.width, kGrid.height, 9, far);
        VisibilityRecord hit;
        hit.patch = 0;
        for (int s = 0; s < 9; s += 2) {
            hit.depth = 1.5f + float(s);
            buffer.offer(3, 2, s, hit);
        }
        TileRays rays(f.tiles);
        rays.load(kGrid.rect(0, 0), buffer);
        int hits = 0;
        for (int i = 0; i < rays.count(); ++i) {
            const float depth = buffer.records()[rays.record[i]].depth;
            hits += depth < far;
            const float end = rayEndAtDepth(depth < far ? depth : far, rays.depthPerLambda());
            EXPECT_TRUE(sameBits(rays.rayEnd[i], end)) << "sample " << i;
        }
        EXPECT_EQ(hits, 5);
    }
}

// Only the samples that got a nearer hit in the tile are written back, with their time and lens.
// The heap's bytes in use (small blocks and mapped ones): glibc's count, independent of the
// estimate under test.
std::uint64_t heapBytesInUse() {
    const struct mallinfo2 info = mallinfo2();
    return std::uint64_t(info.uordblks) + std::uint64_t(info.hblkhd);
}

TEST(TileRays, BytesForIsWhatConstructionAllocates) {
    {  // A sanitizer's allocator keeps its own books, which mallinfo2 does not see.
        const std::uint64_t before = heapBytesInUse();
        const std::vector<char> probe(std::size_t(1) << 20, 1);
        if (heapBytesInUse() - before < probe.size())
            GTEST_SKIP() << "the allocator does not report its bytes in use (a sanitizer build)";
    }
    struct Shape {
        int tileSize, spp;
        bool counting, generated, screenPlane;
    };
    for (const Shape shape :
         {Shape{32, 16, false, true, false}, Shape{64, 8, true, true, true},
          Shape{16, 64, true, false, false}, Shape{128, 4, false, false, true}}) {
        const TileGrid grid{2 * shape.tileSize, shape.tileSize, shape.tileSize};
        Frame f(SamplePattern::Stratified, true, 0.2f, 40.0f, grid, shape.spp);
        f.tiles.countPerSample = shape.counting;
        f.tiles.screenPlane = shape.screenPlane;
        const SampleTable table(f.generator, grid.width, grid.height, 1);
        if (!shape.generated) f.tiles.samples.table = &table;
        const std::uint64_t before = heapBytesInUse();
        const auto rays = std::make_unique<TileRays>(f.tiles);
        const std::uint64_t allocated = heapBytesInUse() - before;
        const std::uint64_t estimate = TileRays::bytesFor(shape.tileSize, shape.spp, shape.counting,
                                                          shape.generated, shape.screenPlane);
        SCOPED_TRACE(testing::Message() << shape.tileSize << " px at " << shape.spp << " spp");
        // Each allocation carries a few bytes of the allocator's own (and an aligned one up to
        // a page): far less than the smallest per-sample array the estimate could leave out.
        const std::uint64_t samples = std::uint64_t(shape.tileSize * shape.tileSize * shape.spp);
        EXPECT_GE(allocated, estimate);
        EXPECT_LT(allocated - estimate, samples * sizeof(std::uint16_t));
    }
}

TEST(TileRays, StoreWritesBackOnlyChangedSamples) {
    Frame f(SamplePattern::Stratified, true, 0.2f);
    VisibilityBuffer buffer(kGrid.width, kGrid.height, 9, f.camera.farPlane());
    TileRays rays(f.tiles);
    rays.load(kGrid.rect(0, 0), buffer);
    rays.bestDepth[5] = 2.5f;
    rays.bestPatch[5] = 7;
    rays.bestTriangle[5] = 3;
    rays.changed[0] = 1u << 5;
    rays.bestDepth[6] = 1.0f;  // not marked changed: not written
    rays.bestPatch[6] = 8;
    rays.store(buffer, nullptr);
    int written = 0;
    for (const VisibilityRecord& r : buffer.records()) written += r.hit();
    EXPECT_EQ(written, 1);
    const VisibilityRecord& r = buffer.records()[rays.record[5]];
    EXPECT_EQ(r.depth, 2.5f);
    EXPECT_EQ(r.patch, 7);
    EXPECT_EQ(r.triangle, 3u);
    EXPECT_EQ(r.time, rays.time[5]);
    EXPECT_EQ(r.lens, Vec2(rays.lensU[5], rays.lensV[5]));
}

}  // namespace
}  // namespace patchsim
