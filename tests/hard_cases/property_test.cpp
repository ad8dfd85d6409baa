// Randomized property test: moving, defocused random patches from fixed seeds. Each case checks
// conservativeness and exactness against the reference, finiteness and determinism
// (tests/render_compare.h). PATCHSIM_PROPERTY_CASES sets the number of cases (default 200; the
// CTest label "slow" runs 20000).

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <random>

#include "tests/render_compare.h"
#include "tests/test_paths.h"

namespace patchsim {
namespace {

int caseCount() {
    const char* env = std::getenv("PATCHSIM_PROPERTY_CASES");
    return env ? std::max(1, std::atoi(env)) : 200;
}

// A 2 x 2 Catmull-Clark grid with random heights: four patches sharing edges.
std::string randomCage(std::mt19937& rng, const std::string& path) {
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::ofstream out(path);
    for (int j = 0; j <= 2; ++j)
        for (int i = 0; i <= 2; ++i)
            out << "v " << (float(i) - 1 + 0.3f * u(rng)) << " " << (float(j) - 1 + 0.3f * u(rng))
                << " " << 0.6f * u(rng) << "\n";
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i) {
            const int a = j * 3 + i + 1;
            out << "f " << a << " " << a + 1 << " " << a + 4 << " " << a + 3 << "\n";
        }
    return path;
}

TEST(PropertyTest, RandomMovingDefocusedPatchesAreConservativeAndExact) {
    std::mt19937 rng(20261122);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    const std::string cage = test::temporaryDirectory() + "/random_cage.obj";
    const Partitioning modes[] = {Partitioning::Integer, Partitioning::Pow2,
                                  Partitioning::FractionalOdd, Partitioning::FractionalEven};
    const int cases = caseCount();
    int casesWithHits = 0;
    for (int c = 0; c < cases; ++c) {
        SceneDesc scene;
        scene.path = "property case " + std::to_string(c);
        scene.film = {12, 10, 2, std::uint64_t(c),
                      c % 5 == 0 ? SamplePattern::Grid : SamplePattern::Stratified};
        scene.camera.open = {{0, 0, 4}, {0, 0, 0}, {0, 1, 0}};
        scene.camera.close =
            c % 7 == 0 ? CameraKey{{0.5f, 0, 4}, {0.5f, 0, 0}, {0, 1, 0}} : scene.camera.open;
        scene.lens = {c % 3 == 0 ? 0.0f : 0.4f * (u(rng) + 1.0f), 2.0f + 2.0f * (u(rng) + 1.0f)};
        scene.tessellation.partitioning = modes[c % 4];
        scene.tessellation.factor = 1.0f + 4.0f * (u(rng) + 1.0f);
        scene.rasterizer.tileSize = 2 << (c % 3);
        scene.rasterizer.leafSize = 1 + c % 4;
        scene.rasterizer.maxTrianglesPerGroup = 8 * scene.rasterizer.leafSize;
        scene.rasterizer.branchMethod = BranchMethod(c % 3);
        scene.rasterizer.boundsSpace = BoundsSpace(c / 3 % 3);
        scene.rasterizer.mergeTrianglesBelow = c % 4 == 1 ? 16 : 0;
        ObjectDesc o;
        o.cagePath = randomCage(rng, cage);
        o.open.translate = {u(rng), u(rng), u(rng)};
        o.open.rotateDegrees = 90.0f * Vec3(u(rng), u(rng), u(rng));
        o.close.translate = o.open.translate + 1.5f * Vec3(u(rng), u(rng), 1.5f * u(rng));
        o.close.rotateDegrees = o.open.rotateDegrees + 45.0f * Vec3(u(rng), u(rng), u(rng));
        if (c % 6 == 0) o.material.opacity = o.material.closeOpacity = 0.5f;
        scene.objects.push_back(o);
        casesWithHits += test::expectStableAndExact(scene, scene.path).hits > 0;
        if (HasFailure()) break;  // one failing case says enough
    }
    // A frame with no hit proves nothing about conservativeness: most cases must see the surface.
    EXPECT_GT(casesWithHits, cases * 3 / 4) << casesWithHits << " of " << cases << " cases hit";
}

}  // namespace
}  // namespace patchsim
