#include "backend/image_space/sample_reprojection.h"

#include <gtest/gtest.h>

#include "backend/images/image_metrics.h"
#include "core/counters.h"
#include "core/scene_reader.h"
#include "pipeline/driver/render.h"
#include "pipeline/driver/sweep.h"
#include "tests/quick_sweep.h"
#include "tests/test_paths.h"

namespace patchsim {
namespace {

SceneDesc scene(const char* path, int spp) {
    SceneDesc s = readSceneFile(test::sourcePath(path));
    s.film.width = 160;
    s.film.height = 120;
    s.film.samplesPerPixel = spp;
    return s;
}

std::vector<SweepRow> sweep(const SceneDesc& s, std::vector<const VisibilityMethod*> methods,
                            const RenderOptions& render = {}) {
    return test::quickSweep(s, std::move(methods), {4}, "reprojection", render);
}

// Taylor: for a small budget, reprojecting two frames' samples across the shutter gives a
// smoother camera-motion blur than as many distributed time samples; and more interpolated
// cameras give a smoother blur than fewer.
TEST(Reprojection, ACameraPanBlursSmootherThanDistributedSamplesOfTheSameCount) {
    const std::vector<SweepRow> rows = sweep(scene("scenes/camera_pan.json", 4),
                                             {&methodNamed("patch"), &methodNamed("reprojection")});
    ASSERT_EQ(rows.size(), 2u);
    EXPECT_GT(rows[1].psnr, rows[0].psnr + 3.0)
        << rows[0].psnr << " dB distributed, " << rows[1].psnr << " dB reprojected";
    RenderOptions few;
    few.reprojection.cameraSteps = 2;
    const std::vector<SweepRow> coarse =
        sweep(scene("scenes/camera_pan.json", 4), {&methodNamed("reprojection")}, few);
    EXPECT_GT(rows[1].psnr, coarse[0].psnr + 1.0) << coarse[0].psnr << " dB with 2 cameras";
}

// Where it fails: objects that move on their own are not interpolated between the two frames.
TEST(Reprojection, ObjectMotionIsNotBlurred) {
    const std::vector<SweepRow> rows =
        sweep(scene("scenes/hybrid.json", 4),
              {&methodNamed("postprocess"), &methodNamed("reprojection")});
    ASSERT_EQ(rows.size(), 2u);
    EXPECT_LT(rows[1].psnr, rows[0].psnr - 1.0)
        << rows[0].psnr << " dB post-process, " << rows[1].psnr << " dB reprojection";
}

// Transparent surfaces take part: both sharp frames carry their transparent layers, and each
// layer is reprojected from its own position with its share of the sample's blend. The camera
// of transparency.json stands still, so the result is the mean of the two sharp frames, each
// blended, which the exact method renders with the glass cube held at its open and close place.
// (The shutter-open copy was missing: plain background there.)
TEST(Reprojection, BothFramesCarryTheirTransparentLayers) {
    const SceneDesc moving = scene("scenes/transparency.json", 4);
    RenderOptions o;
    o.threads = 2;
    RenderResult held[2];
    for (int close = 0; close < 2; ++close) {
        SceneDesc still = moving;
        ObjectDesc& cube = still.objects[1];
        cube.open = cube.close = close ? cube.close : cube.open;
        held[close] = renderScene(still, o);
    }
    o.method = &methodNamed("reprojection");
    const RenderResult r = renderScene(moving, o);
    Image expected(160, 120);
    double openError = 0, openContrast = 0;
    int openPixels = 0;
    for (int y = 0; y < 120; ++y) {
        for (int x = 0; x < 160; ++x) {
            const Vec3 mean =
                0.5f * (held[0].frame.color.get(x, y) + held[1].frame.color.get(x, y));
            expected.set(x, y, mean);
            bool glassAtOpen = true;  // every sample of the pixel sees the cube at shutter open
            for (int s = 0; s < 4; ++s)
                glassAtOpen = glassAtOpen &&
                              held[0].transparent->count(held[0].visibility->index(x, y, s)) > 0;
            if (!glassAtOpen) continue;
            ++openPixels;
            const Vec3 got = r.frame.color.get(x, y);
            openError += double(glm::length(got - mean));
            openContrast += double(glm::length(got - held[1].frame.color.get(x, y)));
        }
    }
    ASSERT_GT(openPixels, 300);
    EXPECT_LT(openError / openPixels, 0.01) << "mean colour error where the cube is at open";
    EXPECT_GT(openContrast / openPixels, 0.05) << "the cube at open is the frame without it";
    EXPECT_GT(psnr(r.frame.color, expected), 40.0);
}

TEST(Reprojection, EverySampleOfBothFramesGoesToEveryCamera) {
    CounterRegistry::instance().reset();
    RenderOptions o;
    o.method = &methodNamed("reprojection");
    o.threads = 1;
    o.reprojection.cameraSteps = 8;
    const RenderResult r = renderScene(scene("scenes/camera_pan.json", 2), o);
    const CounterValues c = CounterRegistry::instance().snapshot();
    EXPECT_EQ(c.byName("RP/Samples"), 2 * 160 * 120 * 2);
    EXPECT_EQ(c.byName("RP/Reprojections") + c.byName("RP/Off-screen reprojections"),
              8 * c.byName("RP/Samples"));
    EXPECT_GE(c.byName("RP/Holes"), 0);
    // Both sharp frames were rasterized: twice the visibility samples of one.
    EXPECT_GT(c.byName("RS/Visibility samples"), 160 * 120 * 2);
    EXPECT_TRUE(r.effects.motion);
}

}  // namespace
}  // namespace patchsim
