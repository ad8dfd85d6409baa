#include "pipeline/driver/sweep.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/scene_reader.h"
#include "pipeline/driver/converged_image.h"
#include "tests/test_paths.h"

namespace patchsim {
namespace {

namespace fs = std::filesystem;

SceneDesc smallScene(const std::string& path, int w = 64, int h = 48) {
    SceneDesc scene = readSceneFile(test::sourcePath(path));
    scene.film.width = w;
    scene.film.height = h;
    return scene;
}

TEST(Sweep, ConvergedImageIsReusedOnlyWhenNothingChanged) {
    const std::string dir = test::temporaryDirectory() + "/converged-cache";
    fs::remove_all(dir);
    const std::string cage = test::temporaryDirectory() + "/cached_torus.obj";
    fs::copy_file(test::sourcePath("scenes/cages/catmark_torus.obj"), cage,
                  fs::copy_options::overwrite_existing);
    SceneDesc scene = smallScene("scenes/motion.json", 24, 16);
    scene.objects.resize(1);
    scene.objects[0].cagePath = cage;
    RenderOptions options;
    const ConvergedImage first = convergedImage(scene, 8, options, dir);
    EXPECT_FALSE(first.fromCache);
    const ConvergedImage second = convergedImage(scene, 8, options, dir);
    EXPECT_TRUE(second.fromCache);
    EXPECT_EQ(second.color.rgb, first.color.rgb);
    EXPECT_EQ(second.coverage, first.coverage);
    // Any change that can change the image is a new key: the cage's text, the seed, the count.
    std::ofstream(cage, std::ios::app) << "v 0 0 0\n";
    EXPECT_FALSE(convergedImage(scene, 8, options, dir).fromCache);
    scene.film.seed += 1;
    EXPECT_FALSE(convergedImage(scene, 8, options, dir).fromCache);
    EXPECT_FALSE(convergedImage(scene, 16, options, dir).fromCache);
    EXPECT_TRUE(convergedImage(scene, 16, options, dir).fromCache);
    // A key file that does not hold the key (a hash collision, a hand edit): not reused.
    const std::string key = convergedKey(scene, 16, options);
    char name[17];
    std::snprintf(name, sizeof name, "%016llx", static_cast<unsigned long long>(contentHash(key)));
    std::ofstream(dir + "/" + name + ".key") << "something else";
    EXPECT_FALSE(convergedImage(scene, 16, options, dir).fromCache);
}

TEST(Sweep, BlurScaleScalesMotionAndAperture) {
    const SceneDesc scene = smallScene("scenes/motion_defocus.json");
    const SceneDesc twice = scaleBlur(scene, 2.0f);
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
        const ObjectDesc& a = scene.objects[i];
        const ObjectDesc& b = twice.objects[i];
        EXPECT_LT(glm::length((b.close.translate - b.open.translate) -
                              2.0f * (a.close.translate - a.open.translate)),
                  1e-5f);
    }
    EXPECT_FLOAT_EQ(twice.lens.apertureRadius, 2.0f * scene.lens.apertureRadius);
}

// The exact methods give the same images, so the same errors; their RMSE falls at least as fast
// as 1/sqrt(spp) (log-log slope -0.5 or steeper) while the converged image is far enough ahead.
TEST(Sweep, ExactMethodsAgreeAndConvergeAtLeastAsFastAsOneOverRootSpp) {
    SweepOptions o;
    for (const char* name : {"patch", "triangle-bbox", "interval"})
        o.variants.push_back({&methodNamed(name), "", {}, {}});
    o.samplesPerPixel = {1, 4, 16, 64};
    o.repeats = 1;
    o.convergedSamplesPerPixel = 2048;
    o.hardware = defaultHardwareConfig();
    o.outputDir = test::temporaryDirectory() + "/sweep";
    o.progress = false;
    std::ostringstream log;
    const std::vector<SweepRow> rows =
        runSweep({{"motion_defocus", smallScene("scenes/motion_defocus.json")}}, o, log);
    ASSERT_EQ(rows.size(), 12u);
    for (int k = 0; k < 4; ++k) {
        EXPECT_EQ(rows[std::size_t(k)].rmse, rows[std::size_t(4 + k)].rmse);
        EXPECT_EQ(rows[std::size_t(k)].rmse, rows[std::size_t(8 + k)].rmse);
        EXPECT_EQ(rows[std::size_t(k)].ssim, rows[std::size_t(8 + k)].ssim);
    }
    // Least-squares slope of log RMSE against log spp.
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (int k = 0; k < 4; ++k) {
        const double x = std::log(double(rows[std::size_t(k)].spp)),
                     y = std::log(rows[std::size_t(k)].rmse);
        sx += x, sy += y, sxx += x * x, sxy += x * y;
    }
    const double slope = (4 * sxy - sx * sy) / (4 * sxx - sx * sx);
    EXPECT_LE(slope, -0.5) << log.str();
    EXPECT_GT(rows[3].psnr, rows[0].psnr + 10) << "64 spp is far closer than 1";
    // The patch method tests fewer samples than triangle-bbox for the same image (by how much
    // grows with the motion and the resolution: BoundingRasterizer.TighterBounds...).
    EXPECT_GT(rows[7].visibility.samplesTested, 2 * rows[3].visibility.samplesTested);
    EXPECT_TRUE(fs::exists(o.outputDir + "/results.csv"));
    EXPECT_TRUE(fs::exists(o.outputDir + "/images/motion_defocus-interval-16.png"));
}

}  // namespace
}  // namespace patchsim
