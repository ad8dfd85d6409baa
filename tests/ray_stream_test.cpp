#include "rasterizer/ray_stream.h"

#include <gtest/gtest.h>
#include <hwy/targets.h>

#include "pipeline/core/counters.h"
#include "pipeline/core/scene_reader.h"
#include "pipeline/driver/render.h"
#include "tests/render_compare.h"
#include "tests/test_paths.h"

namespace patchsim {
namespace {

// The kernels run on whichever SIMD target the host has; each must give the same samples and the
// same counts (no fused multiply-adds, per-lane results equal to the scalar tests).
TEST(RayStream, EverySimdTargetGivesTheSameSamplesAndCounts) {
    const std::vector<std::int64_t> targets = hwy::SupportedAndGeneratedTargets();
    ASSERT_FALSE(targets.empty());
    for (const char* path : {"scenes/motion_defocus.json", "scenes/transparency.json"}) {
        SceneDesc scene = readSceneFile(test::sourcePath(path));
        scene.film.width = 48;
        scene.film.height = 36;
        scene.film.samplesPerPixel = 4;
        RenderOptions options;
        options.threads = 1;
        std::unique_ptr<RenderResult> first;
        CounterValues firstCounts;
        for (std::int64_t target : targets) {
            hwy::SetSupportedTargetsForTest(target);
            EXPECT_STREQ(rayStreamTarget(), hwy::TargetName(target));
            CounterRegistry::instance().reset();
            auto result = std::make_unique<RenderResult>(renderScene(scene, options));
            const CounterValues counts = CounterRegistry::instance().snapshot();
            if (!first) {
                first = std::move(result);
                firstCounts = counts;
                continue;
            }
            EXPECT_EQ(test::compare(*first, *result).mismatches, 0u)
                << path << " on " << hwy::TargetName(target);
            EXPECT_EQ(first->frame.color.rgb, result->frame.color.rgb) << path;
            EXPECT_EQ(firstCounts.raw(), counts.raw())
                << path << ": counts on " << hwy::TargetName(target);
        }
        hwy::SetSupportedTargetsForTest(0);
    }
    std::printf("SIMD targets compared: %zu\n", targets.size());
}

}  // namespace
}  // namespace patchsim
