#include "pipeline/timing/memory_model.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>

#include "backend/image_space/sample_reprojection.h"
#include "core/counters.h"
#include "core/scene_reader.h"
#include "pipeline/driver/render.h"
#include "rasterizer/baselines/bounding_rasterizer.h"
#include "rasterizer/patent/raster_work.h"
#include "tessellator/front_end_work.h"
#include "tests/test_paths.h"

namespace patchsim {
namespace {

// A full-screen quad: one bilinear face 5 units in front of the camera, far wider than the view,
// nothing moving and no lens, so every sample is z-tested and written exactly once. With
// `inView` false the quad lies behind the camera: an empty frame.
SceneDesc fullScreenQuad(int width, int height, int spp, bool inView = true, float opacity = 1.0f) {
    const std::string cage = test::temporaryDirectory() + "/bilinear_quad.obj";
    std::ofstream(cage) << "v -40 -40 0\nv 40 -40 0\nv 40 40 0\nv -40 40 0\nf 1 2 3 4\n";
    const std::string film = "{\"width\": " + std::to_string(width) +
                             ", \"height\": " + std::to_string(height) +
                             ", \"spp\": " + std::to_string(spp) + "}";
    const std::string z = inView ? "-5" : "5";
    const std::string text =
        R"({"camera": {"position": [0, 0, 0], "look_at": [0, 0, -1], "fov_y_degrees": 60},
            "film": )" +
        film + R"(, "tessellation": {"partitioning": "integer", "factor": 4},
            "objects": [{"cage": ")" +
        cage + R"(", "material": {"opacity": )" + std::to_string(opacity) +
        R"(}, "open": {"translate": [0, 0, )" + z + "]}}]}";
    return parseScene(text, "quad.json", "");
}

RenderResult renderTraced(const SceneDesc& scene, int threads = 1, const char* method = "patch",
                          int maxLayers = 16) {
    RenderOptions options;
    options.method = &methodNamed(method);
    options.threads = threads;
    options.maxLayers = maxLayers;
    options.memoryTrace = true;
    CounterRegistry::instance().reset();
    return renderScene(scene, options);
}

MemoryConfig cachesOf(std::uint64_t depthBytes, std::uint64_t llcBytes) {
    MemoryConfig m;
    m.cache(CacheClient::Depth).geometry = {depthBytes, 64, 4, Replacement::Lru};
    m.cache(CacheClient::Visibility).geometry = {depthBytes, 64, 4, Replacement::Lru};
    m.cache(CacheClient::VertexInput).geometry = {2048, 64, 4, Replacement::Lru};
    m.cache(CacheClient::Image).geometry = {depthBytes, 64, 4, Replacement::Lru};
    m.cache(CacheClient::LastLevel).geometry = {llcBytes, 64, 16, Replacement::Lru};
    return m;
}

MemoryReport replay(const RenderResult& r, const MemoryConfig& m, int frames = 1) {
    return simulateMemory(*r.memoryTrace, m,
                          {r.patchOps.size(), r.patchOps.size() - 1, {}, frames});
}

TEST(SurfaceLayout, EverySampleHasItsOwnAddressAndABlockIsContiguous) {
    const SurfaceLayout layout(20, 12, 3, 8);  // 3 x 2 blocks, the last column and row partial
    std::set<std::uint64_t> seen;
    for (int y = 0; y < 12; ++y)
        for (int x = 0; x < 20; ++x)
            for (int s = 0; s < 3; ++s) {
                EXPECT_TRUE(seen.insert(layout.sampleIndex(x, y, s)).second);
                EXPECT_EQ(layout.depthAddress(x, y, s), layout.sampleIndex(x, y, s) * 4);
            }
    // Blocks of one pixel are the plain pixel-major order.
    const SurfaceLayout rows(20, 12, 3, 1);
    EXPECT_EQ(rows.sampleIndex(7, 5, 2), (5u * 20 + 7) * 3 + 2);
    // Block (1, 0) follows block (0, 0): 64 pixels of 3 samples.
    EXPECT_EQ(layout.sampleIndex(8, 0, 0), 64u * 3);
    EXPECT_EQ(layout.sampleIndex(1, 1, 2), (8u + 1) * 3 + 2);
    // The surfaces do not overlap: depth, then visibility, then the image.
    const std::uint64_t padded = 3 * 2 * 64 * 3;
    EXPECT_GE(layout.visibilityAddress(0, 0, 0), padded * kDepthBytes);
    EXPECT_GE(layout.imageAddress(0, 0), layout.visibilityAddress(0, 0, 0) + padded * 28);
    EXPECT_EQ(layout.imageAddress(19, 11) + kImagePixelBytes, layout.endAddress());
}

TEST(MemoryModel, AFullScreenStaticFrameWritesEachSurfaceByTheFormula) {
    const int w = 64, h = 48, spp = 4;
    const RenderResult r = renderTraced(fullScreenQuad(w, h, spp));
    ASSERT_TRUE(r.memoryTrace);
    const std::uint64_t samples = std::uint64_t(w) * h * spp, pixels = std::uint64_t(w) * h;
    // Every sample z-tested and written exactly once (one face in front of each).
    EXPECT_EQ(r.memoryTrace->samplesRead(), samples);
    EXPECT_EQ(r.memoryTrace->samplesWritten(), samples);
    // An LLC that holds every surface: nothing reaches DRAM before the final write-back, which
    // writes each surface's lines once; nothing is ever read from DRAM (the surfaces start
    // cleared).
    const MemoryReport m = replay(r, cachesOf(4096, 4u << 20));
    EXPECT_EQ(m.requested(MemoryClass::DepthReads), samples * 4);
    EXPECT_EQ(m.requested(MemoryClass::DepthWrites), samples * 4);
    EXPECT_EQ(m.requested(MemoryClass::VisibilityWrites), samples * 28);
    EXPECT_EQ(m.requested(MemoryClass::ResolveReads), samples * 32);
    EXPECT_EQ(m.requested(MemoryClass::ImageWrites), pixels * 8);
    EXPECT_EQ(m.dramReadBytes, 0u);
    EXPECT_EQ(m.dramWriteBytes, samples * 4 + samples * 28 + pixels * 8);
    // Line by line: a 64-byte line holds 4 pixels' depth, so the passes read the 768 lines of
    // depth once (one pass a tile, its reads in address order, a line's four pixels one access),
    // write them once, hitting the lines they read, and the resolve reads them once more.
    const CacheStats& depth = m.caches[std::size_t(CacheClient::Depth)];
    const std::uint64_t depthLines = samples * 4 / 64;
    EXPECT_EQ(depth.reads, 2 * depthLines);
    EXPECT_EQ(depth.writes, depthLines);
    EXPECT_EQ(depth.writeHits, depthLines);
    // Every access is some patch's.
    for (int c = 0; c < kCacheClients; ++c) {
        std::uint64_t sum = 0;
        for (const PatchMemory& p : m.patches) sum += p.lineAccesses[std::size_t(c)];
        EXPECT_EQ(sum, m.caches[std::size_t(c)].accesses()) << cacheClientName(CacheClient(c));
    }
    std::uint64_t dram = 0;
    for (const PatchMemory& p : m.patches) dram += p.dramBytes;
    EXPECT_EQ(dram, m.dramBytes());
    // With a small LLC, lines leave before the resolve, which fetches them again: each line is
    // still dirtied once and written once, and at most the two surfaces come back.
    const MemoryReport small = replay(r, cachesOf(4096, 16384));
    EXPECT_EQ(small.dramWriteBytes, m.dramWriteBytes);
    EXPECT_GT(small.dramReadBytes, 0u);
    EXPECT_LE(small.dramReadBytes, samples * 32);
}

// Every method that records its traffic writes each sample of the full-screen quad once: the same
// bytes reach DRAM whichever method found the hits; the bounding methods read more depth (they
// test every sample their bounds reach).
TEST(MemoryModel, EveryTracingMethodWritesTheQuadsSurfacesOnce) {
    const int w = 64, h = 48, spp = 4;
    const std::uint64_t samples = std::uint64_t(w) * h * spp, pixels = std::uint64_t(w) * h;
    // The image-space methods' sharp frame is the patch rasterizer's; a still frame runs no
    // filter, so they record no image-space pass.
    for (const char* method : {"patch", "triangle-bbox", "interval", "postprocess", "hybrid"}) {
        const RenderResult r = renderTraced(fullScreenQuad(w, h, spp), 2, method);
        ASSERT_TRUE(r.memoryTrace) << method;
        EXPECT_EQ(r.memoryTrace->samplesWritten(), samples) << method;
        EXPECT_GE(r.memoryTrace->samplesRead(), samples) << method;
        const MemoryReport m = replay(r, cachesOf(4096, 4u << 20));
        EXPECT_EQ(m.dramReadBytes, 0u) << method;
        EXPECT_EQ(m.dramWriteBytes, samples * 32 + pixels * 8) << method;
        EXPECT_FALSE(r.memoryTrace->imagePasses()) << method;
    }
    // Reprojection renders two sharp frames onto surfaces of their own: twice the surfaces'
    // bytes. A still frame resolves only the first (the close frame is not needed): one image.
    const RenderResult twice = renderTraced(fullScreenQuad(w, h, spp), 2, "reprojection");
    ASSERT_TRUE(twice.memoryTrace);
    ASSERT_EQ(twice.memoryTrace->laterFrames().size(), 1u);
    EXPECT_EQ(twice.memoryTrace->laterFrames()[0].samplesWritten(), samples);
    const MemoryReport both = replay(twice, cachesOf(4096, 4u << 20));
    EXPECT_EQ(both.dramReadBytes, 0u);
    EXPECT_FALSE(twice.memoryTrace->laterFrames()[0].resolved());
    EXPECT_EQ(both.dramWriteBytes, 2 * samples * 32 + pixels * 8);
    EXPECT_EQ(both.requested(MemoryClass::ResolveReads), samples * 32);
    // The t-fragment method records nothing yet, and its frame says so.
    const RenderResult tfragment = renderTraced(fullScreenQuad(16, 16, 2), 1, "tfragment");
    EXPECT_FALSE(tfragment.memoryTrace);
    HardwareConfig hw = defaultHardwareConfig();
    hw.memory = cachesOf(4096, 16384);
    EXPECT_TRUE(timeFrame(tfragment, hw).memoryNotModelled);
}

// Image-space passes, worked by hand on a bare 16 x 16 trace (no visibility passes): one pass
// reads the resolved image (8 bytes a pixel) and writes a plane of 4 bytes a pixel. Through the
// image cache, 32 lines read and 16 written; with an LLC that holds the frame the image is read
// where the resolve left it, and DRAM receives the image and the plane once each.
TEST(MemoryModel, ImageSpacePassesGoThroughTheImageCache) {
    MemoryTrace trace = MemoryTrace::tiles(16, 16, 16, 1);
    ImagePassTrace& passes = trace.startImagePasses();
    const std::uint16_t plane = passes.addPlane("copy", 256, 4);
    passes.beginPass("copy");
    for (std::size_t i = 0; i < 256; ++i) {
        passes.read(ImagePassTrace::resolvedImage(), i);
        passes.write(plane, i);
    }
    const MemoryReport m = simulateMemory(trace, cachesOf(4096, 4u << 20), {1, 0, {}});
    EXPECT_EQ(m.requested(MemoryClass::ImagePassReads), 256u * 8);
    EXPECT_EQ(m.requested(MemoryClass::ImagePassWrites), 256u * 4);
    const CacheStats& image = m.caches[std::size_t(CacheClient::Image)];
    EXPECT_EQ(image.reads, 32u);
    EXPECT_EQ(image.writes, 16u);
    EXPECT_EQ(image.writebacks, 16u);
    EXPECT_EQ(m.dramReadBytes, 0u);
    EXPECT_EQ(m.dramWriteBytes, 256u * (8 + 4));
    EXPECT_EQ(m.patches[0].lineAccesses[std::size_t(CacheClient::Image)], 48u);
    // An LLC of 16 lines lets the image go to DRAM before the pass, which reads it back.
    const MemoryReport small = simulateMemory(trace, cachesOf(4096, 1024), {1, 0, {}});
    EXPECT_GT(small.dramReadBytes, 0u);
    EXPECT_LE(small.dramReadBytes, 256u * 8);
    EXPECT_EQ(small.dramWriteBytes, 256u * (8 + 4));
    // Planes read together are separate streams: a second pass reading the image and the plane
    // at each pixel touches each of their lines once (32 + 16 line reads), not once a pixel.
    passes.beginPass("both");
    for (std::size_t i = 0; i < 256; ++i)
        passes.read(std::uint16_t(ImagePassTrace::resolvedImage() | plane), i);
    const MemoryReport two = simulateMemory(trace, cachesOf(4096, 4u << 20), {1, 0, {}});
    EXPECT_EQ(two.caches[std::size_t(CacheClient::Image)].reads, 32u + 32 + 16);
    EXPECT_EQ(two.requested(MemoryClass::ImagePassReads), 256u * 8 + 256 * (8 + 4));
}

// The post-process and the hybrid charge their sharp frame and their full-screen passes; the
// passes are the filter's own (the gather's taps are its gather samples; the hybrid's reveal
// reads and writes each masked pixel once), through the image cache, at the frame's last patch.
TEST(MemoryModel, TheImageSpaceMethodsChargeTheirFullScreenPasses) {
    SceneDesc scene = readSceneFile(test::sourcePath("scenes/motion.json"));
    scene.film.width = 64;
    scene.film.height = 48;
    scene.film.samplesPerPixel = 4;
    for (const char* method : {"postprocess", "hybrid"}) {
        const RenderResult r = renderTraced(scene, 2, method);
        const CounterValues c = CounterRegistry::instance().snapshot();
        ASSERT_TRUE(r.memoryTrace) << method;
        ASSERT_TRUE(r.memoryTrace->imagePasses()) << method;
        EXPECT_GT(r.memoryTrace->samplesWritten(), 0u) << method;
        const ImagePassTrace& passes = *r.memoryTrace->imagePasses();
        std::uint64_t reads = 0, writes = 0;
        for (const ImagePass& pass : passes.passes()) {
            reads += passes.passBytes(pass, false);
            writes += passes.passBytes(pass, true);
        }
        // The gather by hand: every pixel's NeighbourMax (4 bytes) and colour (8); a blurred
        // pixel's depth and velocity (8); a tap's colour, depth and velocity (16); the hybrid's
        // object and revealed colour (12) at the target and at each tap too.
        const auto gather = std::find_if(passes.passes().begin(), passes.passes().end(),
                                         [](const ImagePass& p) { return p.name == "gather"; });
        ASSERT_NE(gather, passes.passes().end());
        const std::uint64_t pixels = 64 * 48, composite = std::string(method) == "hybrid" ? 12 : 0;
        const auto blurred = std::uint64_t(c.byName("PP/Blurred pixels"));
        const auto taps = std::uint64_t(c.byName("PP/Gather samples"));
        EXPECT_GT(blurred, 0u) << method;
        EXPECT_EQ(passes.passBytes(*gather, false),
                  pixels * 12 + blurred * (8 + composite) + taps * (16 + composite))
            << method;
        EXPECT_EQ(passes.passBytes(*gather, true), pixels * 8) << method;
        const MemoryReport m = replay(r, cachesOf(4096, 1u << 20));
        EXPECT_EQ(m.requested(MemoryClass::ImagePassReads), reads) << method;
        EXPECT_EQ(m.requested(MemoryClass::ImagePassWrites), writes) << method;
        const std::uint64_t imageAccesses = m.caches[std::size_t(CacheClient::Image)].accesses();
        EXPECT_GT(imageAccesses, 0u) << method;
        EXPECT_EQ(m.patches.back().lineAccesses[std::size_t(CacheClient::Image)], imageAccesses)
            << method;
        if (std::string(method) != "hybrid") continue;
        const auto reveal = std::find_if(passes.passes().begin(), passes.passes().end(),
                                         [](const ImagePass& p) { return p.name == "ray reveal"; });
        ASSERT_NE(reveal, passes.passes().end());
        EXPECT_GT(c.byName("HY/Masked pixels"), 0);
        EXPECT_EQ(reveal->elements.size(),
                  64u * 48 + 2 * std::uint64_t(c.byName("HY/Masked pixels")));
        RenderOptions untraced;
        untraced.method = &methodNamed(method);
        untraced.threads = 2;
        EXPECT_EQ(renderScene(scene, untraced).frame.color.rgb, r.frame.color.rgb);
    }
}

// Sample reprojection: two sharp frames, then its passes, each the reprojection's own work: a
// sample's part read per RP/Samples, an accumulation pixel updated per RP/Reprojections, every
// pixel's sum read and output written, a hole's two frame pixels read. Recording changes no pixel.
TEST(MemoryModel, SampleReprojectionChargesBothFramesAndItsPasses) {
    // scenes/hybrid.json at 1 spp: its cameras leave two holes.
    SceneDesc scene = readSceneFile(test::sourcePath("scenes/hybrid.json"));
    scene.film.samplesPerPixel = 1;
    const RenderResult r = renderTraced(scene, 2, "reprojection");
    const CounterValues c = CounterRegistry::instance().snapshot();
    ASSERT_TRUE(r.memoryTrace);
    ASSERT_EQ(r.memoryTrace->laterFrames().size(), 1u);
    EXPECT_GT(r.memoryTrace->laterFrames()[0].samplesWritten(), 0u);
    ASSERT_TRUE(r.memoryTrace->imagePasses());
    const ImagePassTrace& passes = *r.memoryTrace->imagePasses();
    EXPECT_EQ(passes.resolvedFrames(), 2);
    ASSERT_EQ(passes.passes().size(), 3u);
    const auto pixels = std::uint64_t(scene.film.width) * std::uint64_t(scene.film.height);
    const std::uint64_t samples = pixels;
    const ImagePass& parts = passes.passes()[0];
    EXPECT_EQ(parts.elements.size(), 2 * samples);
    EXPECT_EQ(passes.passBytes(parts, true), 2 * samples * kSamplePartBytes);
    // A sample's part read per RP/Samples, a 16-byte update per RP/Reprojections (an update that
    // repeats the one before it is kept as its bytes only: fewer accesses than landings).
    const ImagePass& reproject = passes.passes()[1];
    const auto updates = std::uint64_t(c.byName("RP/Reprojections"));
    const auto partReads =
        std::uint64_t(std::count_if(reproject.planes.begin(), reproject.planes.end(),
                                    [](std::uint16_t m) { return (m & kImageUpdate) == 0; }));
    EXPECT_EQ(partReads, std::uint64_t(c.byName("RP/Samples")));
    EXPECT_LT(reproject.elements.size() - partReads, updates);
    EXPECT_EQ(passes.passBytes(reproject, true), updates * kReprojectionSumBytes);
    EXPECT_EQ(passes.passBytes(reproject, false),
              updates * kReprojectionSumBytes + partReads * kSamplePartBytes);
    const ImagePass& resolve = passes.passes()[2];
    const auto holes = std::uint64_t(c.byName("RP/Holes"));
    EXPECT_GT(holes, 0u);
    EXPECT_EQ(resolve.elements.size(), 2 * pixels + holes);
    EXPECT_EQ(passes.passBytes(resolve, false), pixels * kReprojectionSumBytes + holes * 16);
    EXPECT_EQ(passes.passBytes(resolve, true), pixels * 8);
    const MemoryReport m = replay(r, cachesOf(4096, 1u << 20));
    EXPECT_GT(m.caches[std::size_t(CacheClient::Image)].writes, 0u);
    EXPECT_EQ(m.requested(MemoryClass::ResolveReads), 2 * samples * 32);  // both frames resolved
    // The same traffic on one thread.
    const MemoryReport one =
        replay(renderTraced(scene, 1, "reprojection"), cachesOf(4096, 1u << 20));
    EXPECT_EQ(one.requestedBytes, m.requestedBytes);
    EXPECT_EQ(one.dramReadBytes, m.dramReadBytes);
    EXPECT_EQ(one.dramWriteBytes, m.dramWriteBytes);
    RenderOptions untraced;
    untraced.method = &methodNamed("reprojection");
    untraced.threads = 2;
    EXPECT_EQ(renderScene(scene, untraced).frame.color.rgb, r.frame.color.rgb);
    // A transparent frame's layers, reprojected as parts of their samples, are not recorded: such
    // a frame records nothing, and says so.
    SceneDesc glass = readSceneFile(test::sourcePath("scenes/transparency.json"));
    glass.film.width = 32;
    glass.film.height = 24;
    glass.film.samplesPerPixel = 2;
    const RenderResult layered = renderTraced(glass, 1, "reprojection");
    EXPECT_FALSE(layered.memoryTrace);
    EXPECT_TRUE(layered.memoryTraceDropped);
    HardwareConfig hw = defaultHardwareConfig();
    hw.memory = cachesOf(4096, 16384);
    EXPECT_TRUE(timeFrame(layered, hw).memoryNotModelled);
}

// The accumulation buffer (interleaved) renders a frame per sample index onto 1-spp surfaces:
// every index z-tests and writes each pixel's one sample, the pass's resolve reads them and
// adds into the accumulation buffer (16 bytes a pixel: written every pass, read every pass but
// the first and once more for the image). Worked out for the full-screen quad: with an LLC that
// holds the frame, each pass's surfaces are cleared before they reach DRAM, and DRAM receives
// only the accumulation buffer and the image, written back at the end.
TEST(MemoryModel, AnAccumulationBufferWritesAFramePerSampleIndex) {
    const int w = 64, h = 48, spp = 4;
    const std::uint64_t samples = std::uint64_t(w) * h * spp, pixels = std::uint64_t(w) * h;
    const RenderResult r = renderTraced(fullScreenQuad(w, h, spp), 2, "interleaved");
    ASSERT_TRUE(r.memoryTrace);
    EXPECT_TRUE(r.memoryTrace->accumulation());
    EXPECT_EQ(r.memoryTrace->samplesWritten(), samples);
    const MemoryReport m = replay(r, cachesOf(4096, 4u << 20));
    EXPECT_EQ(m.requested(MemoryClass::DepthWrites), samples * 4);
    EXPECT_EQ(m.requested(MemoryClass::VisibilityWrites), samples * 28);
    EXPECT_EQ(m.requested(MemoryClass::ResolveReads), samples * 32);
    EXPECT_EQ(m.requested(MemoryClass::AccumulationWrites), samples * 16);
    EXPECT_EQ(m.requested(MemoryClass::AccumulationReads), samples * 16);
    EXPECT_EQ(m.requested(MemoryClass::ImageWrites), pixels * 8);
    EXPECT_EQ(m.dramReadBytes, 0u);
    EXPECT_EQ(m.dramWriteBytes, pixels * (16 + 8));
    // With small caches the 1-spp surfaces and the accumulation buffer stream through DRAM on
    // every pass: each pass writes its depth and records back and reads the buffer again.
    const MemoryReport small = replay(r, cachesOf(1024, 4096));
    EXPECT_GT(small.dramWriteBytes, std::uint64_t(spp) * pixels * 16);
    EXPECT_GT(small.dramReadBytes, std::uint64_t(spp - 1) * pixels * 16);
    // The same bytes on any thread count.
    const MemoryReport one =
        replay(renderTraced(fullScreenQuad(w, h, spp), 1, "interleaved"), cachesOf(1024, 4096));
    EXPECT_EQ(one.dramReadBytes, small.dramReadBytes);
    EXPECT_EQ(one.dramWriteBytes, small.dramWriteBytes);
    // A patch at a time replays the same passes of each index in another order.
    MemoryConfig patchOrder = cachesOf(1024, 4096);
    patchOrder.order = MemoryOrder::Patches;
    const MemoryReport byPatch = replay(r, patchOrder);
    EXPECT_EQ(byPatch.requestedBytes, small.requestedBytes);
    EXPECT_EQ(byPatch.caches[std::size_t(CacheClient::Depth)].accesses(),
              small.caches[std::size_t(CacheClient::Depth)].accesses());
}

// The bounding methods' traces are their sample tests and their nearer hits, band by band.
TEST(MemoryModel, TheBoundingMethodsTracesAreTheirTestsAndHits) {
    SceneDesc scene = defaultScene();
    scene.film.width = 64;
    scene.film.height = 48;
    scene.film.samplesPerPixel = 4;
    for (const auto& [name, bounding] : {std::pair{"triangle-bbox", Bounding::TriangleBBox},
                                         {"interval", Bounding::Interval},
                                         {"interleaved", Bounding::Interleaved}}) {
        const RenderResult one = renderTraced(scene, 1, name);
        const CounterValues counts = CounterRegistry::instance().snapshot();
        const BoundingCounters& c = boundingCounters(bounding);
        EXPECT_EQ(std::int64_t(one.memoryTrace->samplesRead()), counts[c.samplesTested]) << name;
        EXPECT_EQ(std::int64_t(one.memoryTrace->samplesWritten()), counts[c.visibilitySamples])
            << name;
        const RenderResult two = renderTraced(scene, 2, name);
        const MemoryConfig m = cachesOf(4096, 16384);
        const MemoryReport a = replay(one, m), b = replay(two, m);
        EXPECT_EQ(a.dramReadBytes, b.dramReadBytes) << name;
        EXPECT_EQ(a.dramWriteBytes, b.dramWriteBytes) << name;
        EXPECT_GT(a.requested(MemoryClass::DepthReads), 0u) << name;
    }
}

// A transparent full-screen quad: every sample gets one layer. Offers beyond one a sample are a
// ray through an edge two triangles share (merged: one surface). Each offer reads the sample's
// header and its layers so far and writes a layer, and the header when it adds one; the resolve
// reads each sample's header and its one layer. With an LLC that holds the frame, DRAM receives
// each sample's header, the line of its block that holds its layer, and the image.
TEST(MemoryModel, TransparentLayersAreChargedOfferByOffer) {
    const int w = 32, h = 24, spp = 4;
    const std::uint64_t samples = std::uint64_t(w) * h * spp, pixels = std::uint64_t(w) * h;
    for (const auto& [name, bounding] : {std::pair{"patch", Bounding::Interleaved},
                                         {"triangle-bbox", Bounding::TriangleBBox},
                                         {"interval", Bounding::Interval}}) {
        const RenderResult r = renderTraced(fullScreenQuad(w, h, spp, true, 0.5f), 1, name);
        const MemoryTrace& t = *r.memoryTrace;
        const CounterValues counts = CounterRegistry::instance().snapshot();
        const std::int64_t fragments =
            std::string(name) == "patch" ? counts[rasterCounters().transparentFragments]
                                         : counts[boundingCounters(bounding).transparentFragments];
        EXPECT_EQ(t.layerSlots(), 16) << name;
        EXPECT_EQ(std::int64_t(t.fragmentsOffered()), fragments) << name;
        EXPECT_EQ(t.layersAppended(), samples) << name;
        const std::uint64_t offers = t.fragmentsOffered();
        const MemoryReport m = replay(r, cachesOf(4096, 4u << 20));
        EXPECT_EQ(m.requested(MemoryClass::LayerWrites), offers * 32 + samples * 4) << name;
        EXPECT_EQ(m.requested(MemoryClass::LayerReads), offers * 4 + (offers - samples) * 32)
            << name;
        EXPECT_EQ(m.requested(MemoryClass::ResolveReads), samples * (32 + 4 + 32)) << name;
        EXPECT_EQ(m.requested(MemoryClass::DepthWrites), 0u) << name;
        EXPECT_EQ(m.dramReadBytes, 0u) << name;
        EXPECT_EQ(m.dramWriteBytes, samples * 64 + samples * 4 + pixels * 8) << name;
        EXPECT_GT(m.caches[std::size_t(CacheClient::Layers)].reads, 0u) << name;
    }
}

// The transparency scene with 1 layer a sample: offers overflow, yet a sample keeps as many
// layers as were added to it, which the resolve reads back; the same on any thread count.
TEST(MemoryModel, LayersThatOverflowAreReadBackAsKeptOnAnyThreadCount) {
    SceneDesc scene = readSceneFile(test::sourcePath("scenes/transparency.json"));
    scene.film.width = 64;
    scene.film.height = 48;
    const RenderResult one = renderTraced(scene, 1, "patch", 1);
    const CounterValues counts = CounterRegistry::instance().snapshot();
    EXPECT_GT(counts[rasterCounters().transparentOverflow], 0);
    const MemoryTrace& t = *one.memoryTrace;
    EXPECT_EQ(std::int64_t(t.fragmentsOffered()), counts[rasterCounters().transparentFragments]);
    const std::uint64_t samples = 64u * 48 * std::uint64_t(scene.film.samplesPerPixel);
    const MemoryConfig m = cachesOf(4096, 65536);
    const MemoryReport a = replay(one, m);
    EXPECT_EQ(a.requested(MemoryClass::ResolveReads), samples * (32 + 4) + t.layersAppended() * 32);
    const RenderResult two = renderTraced(scene, 2, "patch", 1);
    EXPECT_EQ(two.memoryTrace->layersAppended(), t.layersAppended());
    const MemoryReport b = replay(two, m);
    EXPECT_EQ(a.requestedBytes, b.requestedBytes);
    EXPECT_EQ(a.dramReadBytes, b.dramReadBytes);
    EXPECT_EQ(a.dramWriteBytes, b.dramWriteBytes);
    const CacheStats &la = a.caches[std::size_t(CacheClient::Layers)],
                     &lb = b.caches[std::size_t(CacheClient::Layers)];
    EXPECT_EQ(la.hits(), lb.hits());
    EXPECT_EQ(la.writebacks, lb.writebacks);
}

// The order is a design choice: a patch at a time replays the same passes, so every class asks
// for the same bytes and each cache sees as many line accesses; only hits and DRAM differ.
TEST(MemoryModel, APatchAtATimeReplaysTheSamePassesInAnotherOrder) {
    SceneDesc scene = defaultScene();
    scene.film.width = 96;
    scene.film.height = 64;
    for (const char* method : {"patch", "interval"}) {
        const RenderResult r = renderTraced(scene, 1, method);
        MemoryConfig m = cachesOf(4096, 16384);
        FrameMemoryInputs inputs{r.patchOps.size(), r.patchOps.size() - 1,
                                 hierarchySpills(r.patchOps, 1024)};
        inputs.fetch = &r.controlPointFetch;
        const MemoryReport regions = simulateMemory(*r.memoryTrace, m, inputs);
        m.order = MemoryOrder::Patches;
        const MemoryReport patches = simulateMemory(*r.memoryTrace, m, inputs);
        EXPECT_EQ(regions.requestedBytes, patches.requestedBytes) << method;
        for (int c = 0; c < kCacheClients - 1; ++c)
            EXPECT_EQ(regions.caches[std::size_t(c)].reads + regions.caches[std::size_t(c)].writes,
                      patches.caches[std::size_t(c)].reads + patches.caches[std::size_t(c)].writes)
                << method << " " << cacheClientName(CacheClient(c));
        EXPECT_NE(regions.dramBytes(), patches.dramBytes()) << method;
    }
}

// With depth compression the depth surface's lines move at their block's compressed size; the
// visibility surface and the image do not shrink.
TEST(MemoryModel, CompressedDepthMovesFewerBytesToDram) {
    const int w = 64, h = 48, spp = 4;
    const std::uint64_t samples = std::uint64_t(w) * h * spp, pixels = std::uint64_t(w) * h;
    RenderResult r = renderTraced(fullScreenQuad(w, h, spp));
    HardwareConfig hw = defaultHardwareConfig();
    hw.memory = cachesOf(4096, 4u << 20);
    hw.memory->depthCompression = DepthCompression::TimePlane;
    const FrameTiming t = timeFrame(r, hw);
    ASSERT_TRUE(t.memory && t.memory->depthCompression);
    const DepthCompressionReport& d = *t.memory->depthCompression;
    EXPECT_EQ(d.blockBits.size(), std::size_t(w / 8 * h / 8));
    EXPECT_LT(d.ratio(), 0.5);  // a flat quad facing the camera
    // Only the front end reads DRAM: the bilinear face's 4 indices and 4 positions, a line each.
    ASSERT_EQ(r.controlPointFetch.vertices.size(), 4u);
    EXPECT_EQ(t.memory->dramReadBytes, 2u * 64);
    EXPECT_LT(t.memory->dramWriteBytes, samples * 32 + pixels * 8);
    EXPECT_GE(t.memory->dramWriteBytes, samples * 28 + pixels * 8);
    // Each depth line at its block's size, rounded up to a byte.
    std::uint64_t depthBytes = 0;
    for (double scale : d.blockScales()) depthBytes += 16 * std::uint64_t(std::ceil(64 * scale));
    EXPECT_EQ(t.memory->dramWriteBytes, depthBytes + samples * 28 + pixels * 8);
}

TEST(MemoryModel, ASecondIdenticalFrameHitsOnEveryReadWhenTheCachesHoldTheFrame) {
    const RenderResult r = renderTraced(fullScreenQuad(32, 24, 4));
    const MemoryConfig big = cachesOf(1u << 20, 4u << 20);  // more than the 12 KiB of depth
    const MemoryReport one = replay(r, big, 1), two = replay(r, big, 2);
    const CacheStats& a = one.caches[std::size_t(CacheClient::Depth)];
    const CacheStats& b = two.caches[std::size_t(CacheClient::Depth)];
    const std::uint64_t secondReads = b.reads - a.reads, secondHits = b.readHits - a.readHits;
    EXPECT_GT(secondReads, 0u);
    EXPECT_EQ(secondHits, secondReads);
    EXPECT_EQ(b.writeHits - a.writeHits, b.writes - a.writes);
}

TEST(MemoryModel, AnEmptyFrameMovesNoSurfaceBytesOnlyTheImage) {
    const RenderResult r = renderTraced(fullScreenQuad(32, 24, 4, false));
    ASSERT_TRUE(r.memoryTrace);
    EXPECT_EQ(r.memoryTrace->samplesRead(), 0u);
    if (r.patchOps.empty()) GTEST_SKIP() << "no patch left to charge";
    const MemoryReport m = replay(r, cachesOf(4096, 16384));
    EXPECT_EQ(m.requested(MemoryClass::DepthWrites) + m.requested(MemoryClass::DepthReads), 0u);
    EXPECT_EQ(m.dramReadBytes, 0u);  // the resolve reads cleared lines: nothing to fetch
    EXPECT_EQ(m.dramWriteBytes, 32u * 24 * 8);
}

TEST(MemoryModel, TheTraceIsTheRaysTestsAndTheVisibilitySamplesOnAnyThreadCount) {
    SceneDesc scene = defaultScene();
    scene.film.width = 96;
    scene.film.height = 64;
    const RenderResult one = renderTraced(scene, 1);
    const CounterValues counts = CounterRegistry::instance().snapshot();
    const RasterCounters& c = rasterCounters();
    EXPECT_EQ(std::int64_t(one.memoryTrace->samplesRead()), counts[c.samplesTested]);
    EXPECT_EQ(std::int64_t(one.memoryTrace->samplesWritten()), counts[c.visibilitySamples]);
    const RenderResult two = renderTraced(scene, 2);
    const MemoryConfig m = cachesOf(16384, 65536);
    const MemoryReport a = replay(one, m), b = replay(two, m);
    EXPECT_EQ(a.dramReadBytes, b.dramReadBytes);
    EXPECT_EQ(a.dramWriteBytes, b.dramWriteBytes);
    for (int k = 0; k < kCacheClients; ++k) {
        EXPECT_EQ(a.caches[std::size_t(k)].hits(), b.caches[std::size_t(k)].hits());
        EXPECT_EQ(a.caches[std::size_t(k)].writebacks, b.caches[std::size_t(k)].writebacks);
    }
    for (std::size_t p = 0; p < a.patches.size(); ++p) {
        EXPECT_EQ(a.patches[p].dramBytes, b.patches[p].dramBytes) << "patch " << p;
        EXPECT_EQ(a.patches[p].lineAccesses, b.patches[p].lineAccesses) << "patch " << p;
    }
}

// A hierarchy larger than the scratch budget spills: its excess is written once and read by each
// tile pass of its patch, through the LLC; with an LLC too small to keep it, DRAM sees it.
TEST(MemoryModel, AHierarchyOverTheScratchBudgetSpillsAndIsCharged) {
    SceneDesc scene = defaultScene();
    scene.film.width = 96;
    scene.film.height = 64;
    const RenderResult r = renderTraced(scene);
    const MemoryConfig m = cachesOf(4096, 16384);
    const std::vector<std::uint64_t> none = hierarchySpills(r.patchOps, 1u << 30);
    EXPECT_EQ(std::count(none.begin(), none.end(), 0u), std::ptrdiff_t(none.size()));
    const std::vector<std::uint64_t> spills = hierarchySpills(r.patchOps, 256);
    std::uint64_t spilled = 0;
    for (std::size_t p = 0; p < spills.size(); ++p) {
        EXPECT_EQ(spills[p],
                  r.patchOps[p].hierarchyBytes > 256 ? r.patchOps[p].hierarchyBytes - 256 : 0);
        spilled += spills[p];
    }
    ASSERT_GT(spilled, 0u);
    // A tile test reads the spilled hierarchy whether or not it then tests a sample: every tile
    // in the group's bounds is a pass of the trace.
    const CounterValues counts = CounterRegistry::instance().snapshot();
    std::uint64_t passes = 0, spillReads = 0;
    for (std::size_t k = 0; k < r.memoryTrace->regionCount(); ++k)
        for (const TracedPass& pass : r.memoryTrace->region(k).passes) {
            ++passes;
            spillReads += spills[pass.patch];
        }
    EXPECT_EQ(std::int64_t(passes), counts[rasterCounters().tilesInBounds]);
    const std::size_t last = r.patchOps.size() - 1;
    const MemoryReport fits = simulateMemory(*r.memoryTrace, m, {r.patchOps.size(), last, none});
    const MemoryReport spills256 =
        simulateMemory(*r.memoryTrace, m, {r.patchOps.size(), last, spills});
    EXPECT_EQ(fits.requested(MemoryClass::SpillWrites), 0u);
    EXPECT_EQ(spills256.requested(MemoryClass::SpillWrites), spilled);
    EXPECT_EQ(spills256.requested(MemoryClass::SpillReads), spillReads);
    EXPECT_GT(spillReads, spilled);  // patches cover several tiles
    EXPECT_GT(spills256.dramBytes(), fits.dramBytes());
    for (int c = 0; c < 5; ++c)  // the surfaces' own traffic is unchanged
        EXPECT_EQ(spills256.requestedBytes[std::size_t(c)], fits.requestedBytes[std::size_t(c)]);
}

// The input assembler's fetch, worked by hand: two patches sharing two vertices, a 1 x 1 frame.
// Patch 0 reads its index line and vertex line 0 (vertices 0-3, bytes 0-47), both misses; patch 1
// reads the same index line and vertex line 0 again (hits) and line 1 for vertex 5's last bytes
// (bytes 60-71), a miss. Three misses fetch three lines from DRAM; nothing else is read there.
TEST(MemoryModel, TheInputAssemblerFetchesEachPatchsControlPointsThroughItsCache) {
    const MemoryTrace trace = MemoryTrace::tiles(1, 1, 1, 1);
    MemoryConfig m = cachesOf(4096, 16384);
    m.cache(CacheClient::VertexInput).geometry = {2048, 64, 4, Replacement::Lru};
    ControlPointFetch fetch;
    fetch.patchBegin = {0, 4, 8};
    fetch.vertices = {0, 1, 2, 3, 2, 3, 4, 5};
    fetch.vertexCount = 6;
    FrameMemoryInputs inputs{2, 1, {}};
    const MemoryReport without = simulateMemory(trace, m, inputs);
    inputs.fetch = &fetch;
    const MemoryReport with = simulateMemory(trace, m, inputs);
    EXPECT_EQ(with.requested(MemoryClass::IndexReads), 8u * kIndexBytes);
    EXPECT_EQ(with.requested(MemoryClass::ControlPointReads), 8u * kControlPointBytes);
    const CacheStats& input = with.caches[std::size_t(CacheClient::VertexInput)];
    EXPECT_EQ(input.reads, 5u);
    EXPECT_EQ(input.readHits, 2u);
    EXPECT_EQ(input.writes, 0u);
    EXPECT_EQ(without.dramReadBytes, 0u);
    EXPECT_EQ(with.dramReadBytes, 3u * 64);
    EXPECT_EQ(with.dramWriteBytes, without.dramWriteBytes);  // read-only buffers
    EXPECT_EQ(with.patches[0].lineAccesses[std::size_t(CacheClient::VertexInput)], 2u);
    EXPECT_EQ(with.patches[1].lineAccesses[std::size_t(CacheClient::VertexInput)], 3u);
    EXPECT_EQ(with.patches[0].dramBytes, 2u * 64);
}

// A rendered frame fetches, per patch, as many control points as the vertex stage counts.
TEST(MemoryModel, ARenderedFrameFetchesTheControlPointsTheVertexStageCounts) {
    SceneDesc scene = defaultScene();
    scene.film.width = 48;
    scene.film.height = 32;
    const RenderResult r = renderTraced(scene);
    const CounterValues counts = CounterRegistry::instance().snapshot();
    const ControlPointFetch& fetch = r.controlPointFetch;
    ASSERT_EQ(fetch.patches(), r.patchOps.size());
    EXPECT_EQ(std::int64_t(fetch.vertices.size()), counts[frontEndCounters().patchControlPoints]);
    for (const std::uint32_t v : fetch.vertices) ASSERT_LT(v, fetch.vertexCount);
    FrameMemoryInputs inputs{r.patchOps.size(), r.patchOps.size() - 1, {}};
    inputs.fetch = &fetch;
    const MemoryReport m = simulateMemory(*r.memoryTrace, cachesOf(16384, 65536), inputs);
    EXPECT_EQ(m.requested(MemoryClass::ControlPointReads),
              fetch.vertices.size() * kControlPointBytes);
    // Neighbouring patches share control points: most reads hit.
    EXPECT_GT(m.caches[std::size_t(CacheClient::VertexInput)].hitRate(), 0.5);
}

// The timing model with the memory system: a frame that streams through the caches is
// bandwidth-bound and runs at the configured DRAM bandwidth; halving it about doubles the
// frame; a compute-bound frame barely moves.
TEST(MemoryModel, ABandwidthBoundFrameRunsAtTheConfiguredBandwidth) {
    SceneDesc scene = defaultScene();
    scene.film.width = 96;
    scene.film.height = 64;
    const RenderResult r = renderTraced(scene);
    HardwareConfig hw = defaultHardwareConfig();
    hw.memory = cachesOf(1024, 4096);  // almost nothing stays on chip
    hw.memory->dramBytesPerClock = 0.25;
    const MemoryReport m = replay(r, *hw.memory);
    const TimingReport slow = simulateTiming(r.patchOps, hw, &m);
    ASSERT_TRUE(slow.memory);
    EXPECT_TRUE(slow.memoryBound);
    EXPECT_STREQ(slow.bottleneckName(), "DRAM");
    EXPECT_GE(slow.memory->dramBytesPerCycle, 0.95 * 0.25);
    hw.memory->dramBytesPerClock = 0.125;
    const TimingReport slower = simulateTiming(r.patchOps, hw, &m);
    EXPECT_NEAR(slower.totalCycles / slow.totalCycles, 2.0, 0.05);
    // The memory FIFO: a short one backs the stages up (OM stalls), a long one absorbs them.
    hw.memory->fifoDepth = 1;
    EXPECT_GT(simulateTiming(r.patchOps, hw, &m).stages[std::size_t(Stage::OM)].stalled, 0);
    hw.memory->fifoDepth = 100000;
    EXPECT_EQ(simulateTiming(r.patchOps, hw, &m).stages[std::size_t(Stage::OM)].stalled, 0);

    hw.memory->dramBytesPerClock = 4096;  // the rasterizer sets the pace
    const double fast = simulateTiming(r.patchOps, hw, &m).totalCycles;
    hw.memory->dramBytesPerClock = 2048;
    const TimingReport halved = simulateTiming(r.patchOps, hw, &m);
    EXPECT_FALSE(halved.memoryBound);
    EXPECT_LT(halved.totalCycles / fast, 1.01);
    // Without a memory section the model is the compute-only one.
    HardwareConfig computeOnly = defaultHardwareConfig();
    EXPECT_FALSE(simulateTiming(r.patchOps, computeOnly, &m).memory);
}

// DRAM with banks (dram_banks.h): with no activation cost the banks never outlast the bus, so
// the frame's cycles are the ideal bus's; the full-screen quad writes its surfaces in address
// order, so nearly every transfer is a row hit and a bandwidth-bound frame still runs near the
// configured bandwidth; one bank that is slow to open a row makes the frame DRAM-bound and
// longer, by the row misses the replay counted.
TEST(MemoryModel, DramBanksChargeTheRowsAFrameReopens) {
    const RenderResult r = renderTraced(fullScreenQuad(64, 48, 4));
    HardwareConfig hw = defaultHardwareConfig();
    hw.memory = cachesOf(1024, 4096);
    hw.memory->dramBytesPerClock = 0.25;
    const MemoryReport ideal = replay(r, *hw.memory);
    const double idealCycles = simulateTiming(r.patchOps, hw, &ideal).totalCycles;

    hw.memory->dramBanks = {.banks = 8, .rowBytes = 2048};
    const MemoryReport free = replay(r, *hw.memory);
    EXPECT_EQ(free.dramBanks.transfers * 64, free.dramBytes());
    EXPECT_NEAR(simulateTiming(r.patchOps, hw, &free).totalCycles, idealCycles, 1e-9 * idealCycles);

    hw.memory->dramBanks = {.channels = 4,
                            .banks = 8,
                            .rowBytes = 2048,
                            .activateCycles = 33,
                            .prechargeCycles = 35,
                            .activateToActivateCycles = 23};
    const MemoryReport banked = replay(r, *hw.memory);
    EXPECT_EQ(banked.dramBanks.transfers, free.dramBanks.transfers);
    EXPECT_GT(banked.dramBanks.rowHitRate(), 0.9);
    const TimingReport streamed = simulateTiming(r.patchOps, hw, &banked);
    EXPECT_TRUE(streamed.memoryBound);
    EXPECT_GE(streamed.memory->dramBytesPerCycle, 0.95 * 0.25);
    EXPECT_GE(streamed.totalCycles, idealCycles);  // channels and banks never beat the ideal bus

    hw.memory->dramBytesPerClock = 64;  // the bus is never what limits here
    hw.memory->dramBanks = {.banks = 1, .rowBytes = 64, .activateCycles = 1000};  // a row a line
    const MemoryReport slow = replay(r, *hw.memory);
    EXPECT_EQ(slow.dramBanks.rowHits, 0u);
    const TimingReport slowTiming = simulateTiming(r.patchOps, hw, &slow);
    EXPECT_TRUE(slowTiming.memoryBound);
    EXPECT_STREQ(slowTiming.bottleneckName(), "DRAM");
    // Every transfer an activation of the one bank: the DRAM part's busy time is 1000 cycles
    // plus a cycle a line for each.
    EXPECT_NEAR(slowTiming.memory->busy[kCacheClients],
                double(slow.dramBanks.transfers) * (1000.0 + 1.0),
                1e-6 * 1000.0 * double(slow.dramBanks.transfers));
}

// A limit on DRAM reads in flight (memory.dram.max_reads_in_flight): each line read holds one
// for DRAM's latency, so the frame reads at most limit x line / latency bytes a cycle (Little's
// law). With 4 reads in flight and 200 cycles the part's busy time is exactly 50 cycles a read,
// the frame is bound by it, and its reads run at no more than 4 x 64 / 200 = 1.28 bytes a cycle;
// with a limit no frame reaches, the cycles are those without one.
TEST(MemoryModel, ReadsInFlightBoundTheReadRateByLittlesLaw) {
    const RenderResult r = renderTraced(fullScreenQuad(64, 48, 4));
    HardwareConfig hw = defaultHardwareConfig();
    hw.memory = cachesOf(1024, 4096);
    hw.memory->dramBytesPerClock = 4096;  // the bus never limits
    hw.memory->dramLatency = 200;
    const MemoryReport m = replay(r, *hw.memory);
    ASSERT_GT(m.dramReads, 0u);
    std::uint64_t patchReads = 0;
    for (const PatchMemory& p : m.patches) patchReads += p.dramReads;
    EXPECT_EQ(patchReads, m.dramReads);
    EXPECT_EQ(m.dramReads * 64, m.dramReadBytes);  // uncompressed lines
    const double unlimited = simulateTiming(r.patchOps, hw, &m).totalCycles;

    hw.memory->dramReadsInFlight = 4;
    const TimingReport bound = simulateTiming(r.patchOps, hw, &m);
    EXPECT_DOUBLE_EQ(bound.memory->busy[kReadsInFlightPart], double(m.dramReads) * 50.0);
    EXPECT_TRUE(bound.memoryBound);
    EXPECT_STREQ(bound.bottleneckName(), "DRAM reads in flight");
    EXPECT_LE(double(m.dramReadBytes) / bound.totalCycles, 4.0 * 64.0 / 200.0);
    EXPECT_GT(bound.totalCycles, unlimited);

    hw.memory->dramReadsInFlight = 1000000;
    EXPECT_EQ(simulateTiming(r.patchOps, hw, &m).totalCycles, unlimited);
}

}  // namespace
}  // namespace patchsim
