#include "backend/sample_reprojection.h"

#include <gtest/gtest.h>

#include "pipeline/core/counters.h"
#include "pipeline/core/scene_reader.h"
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

std::vector<SweepRow> sweep(const SceneDesc& s, std::vector<VisibilityMethod> methods,
                            const RenderOptions& render = {}) {
    return test::quickSweep(s, std::move(methods), {4}, "reprojection", render);
}

// Taylor: for a small budget, reprojecting two frames' samples across the shutter gives a
// smoother camera-motion blur than as many distributed time samples; and more interpolated
// cameras give a smoother blur than fewer.
TEST(Reprojection, ACameraPanBlursSmootherThanDistributedSamplesOfTheSameCount) {
    const std::vector<SweepRow> rows =
        sweep(scene("scenes/camera_pan.json", 4),
              {VisibilityMethod::Patch, VisibilityMethod::Reprojection});
    ASSERT_EQ(rows.size(), 2u);
    EXPECT_GT(rows[1].psnr, rows[0].psnr + 3.0)
        << rows[0].psnr << " dB distributed, " << rows[1].psnr << " dB reprojected";
    RenderOptions few;
    few.reprojection.cameraSteps = 2;
    const std::vector<SweepRow> coarse =
        sweep(scene("scenes/camera_pan.json", 4), {VisibilityMethod::Reprojection}, few);
    EXPECT_GT(rows[1].psnr, coarse[0].psnr + 1.0) << coarse[0].psnr << " dB with 2 cameras";
}

// Where it fails: objects that move on their own are not interpolated between the two frames.
TEST(Reprojection, ObjectMotionIsNotBlurred) {
    const std::vector<SweepRow> rows =
        sweep(scene("scenes/hybrid.json", 4),
              {VisibilityMethod::Postprocess, VisibilityMethod::Reprojection});
    ASSERT_EQ(rows.size(), 2u);
    EXPECT_LT(rows[1].psnr, rows[0].psnr - 1.0)
        << rows[0].psnr << " dB post-process, " << rows[1].psnr << " dB reprojection";
}

TEST(Reprojection, EverySampleOfBothFramesGoesToEveryCamera) {
    CounterRegistry::instance().reset();
    RenderOptions o;
    o.method = VisibilityMethod::Reprojection;
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
