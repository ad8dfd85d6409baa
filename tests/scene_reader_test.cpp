#include "core/scene_reader.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "core/error.h"
#include "tests/test_paths.h"

namespace patchsim {
namespace {

std::string errorOf(const std::string& json, const SceneLimits& limits = {}) {
    try {
        parseScene(json, "scene.json", "");
    } catch (const InputError& e) {
        EXPECT_EQ(e.file(), "scene.json");
        return e.what();
    }
    (void)limits;
    ADD_FAILURE() << "no error for " << json;
    return {};
}

const char* kMinimal = R"({"objects": [{"cage": "a.obj"}]})";

TEST(SceneReader, ReadsEveryShippedScene) {
    const auto scenes = test::sceneFiles();
    ASSERT_GE(scenes.size(), 5u);
    for (const std::string& path : scenes) {
        const SceneDesc scene = readSceneFile(path);
        EXPECT_FALSE(scene.objects.empty()) << path;
    }
}

TEST(SceneReader, DefaultSceneIsBuiltIn) {
    const SceneDesc scene = defaultScene();
    EXPECT_EQ(scene.objects.size(), 3u);
    EXPECT_GT(scene.lens.apertureRadius, 0.0f);
    EXPECT_TRUE(scene.objects[0].cagePath.starts_with("builtin:"));
}

bool sameVec(const Vec3& a, const Vec3& b) {
    return a.x == b.x && a.y == b.y && a.z == b.z;
}

bool sameTransform(const TransformDesc& a, const TransformDesc& b) {
    return sameVec(a.translate, b.translate) && sameVec(a.rotateDegrees, b.rotateDegrees) &&
           sameVec(a.scale, b.scale);
}

// docs/performance/factor32/ holds the Embree benchmark's `factor32` frames as scene files, for
// `patchsim explore` (docs/PERFORMANCE.md, "Fewer, larger units on the micropolygon scene"): each
// must be the built-in scene at a fixed factor of 32, still or with the scene's own motion (the
// benchmark's large blur), with or without its lens, as bench/embree_compare_bench.cpp makes them.
TEST(SceneReader, TheFactor32SceneFilesAreTheBenchmarksFrames) {
    const SceneDesc builtIn = defaultScene();
    struct Frame {
        const char* file;
        bool moves, lens;
    };
    for (const Frame& frame :
         {Frame{"none_pinhole", false, false}, Frame{"none_lens", false, true},
          Frame{"large_pinhole", true, false}, Frame{"large_lens", true, true}}) {
        const std::string path =
            test::sourcePath("docs/performance/factor32/" + std::string(frame.file) + ".json");
        const SceneDesc s = readSceneFile(path);
        EXPECT_EQ(s.tessellation.partitioning, builtIn.tessellation.partitioning) << path;
        EXPECT_EQ(s.tessellation.targetEdgePixels, 0.0f) << path;
        EXPECT_EQ(s.tessellation.factor, 32.0f) << path;
        EXPECT_EQ(s.film.width, builtIn.film.width) << path;
        EXPECT_EQ(s.film.height, builtIn.film.height) << path;
        EXPECT_EQ(s.film.samplesPerPixel, builtIn.film.samplesPerPixel) << path;
        EXPECT_EQ(s.film.seed, builtIn.film.seed) << path;
        EXPECT_TRUE(sameVec(s.camera.open.position, builtIn.camera.open.position)) << path;
        EXPECT_TRUE(sameVec(s.camera.open.lookAt, builtIn.camera.open.lookAt)) << path;
        EXPECT_EQ(s.camera.fovYDegrees, builtIn.camera.fovYDegrees) << path;
        EXPECT_EQ(s.lens.apertureRadius, frame.lens ? builtIn.lens.apertureRadius : 0.0f) << path;
        EXPECT_EQ(s.lens.focusDistance, builtIn.lens.focusDistance) << path;
        ASSERT_EQ(s.objects.size(), builtIn.objects.size()) << path;
        for (std::size_t i = 0; i < s.objects.size(); ++i) {
            const ObjectDesc &o = s.objects[i], &b = builtIn.objects[i];
            EXPECT_EQ(std::filesystem::path(o.cagePath).filename(),
                      std::filesystem::path(b.cagePath).filename())
                << path;
            EXPECT_TRUE(std::filesystem::exists(o.cagePath)) << o.cagePath;
            EXPECT_TRUE(sameTransform(o.open, b.open)) << path << " " << o.name;
            EXPECT_TRUE(sameTransform(o.close, frame.moves ? b.close : b.open))
                << path << " " << o.name;
            EXPECT_TRUE(sameVec(o.material.color, b.material.color)) << path << " " << o.name;
        }
    }
}

TEST(SceneReader, DefaultsAndResolution) {
    const SceneDesc scene = parseScene(kMinimal, "dir/scene.json", "dir");
    ASSERT_EQ(scene.objects.size(), 1u);
    EXPECT_EQ(scene.objects[0].cagePath, "dir/a.obj");
    EXPECT_EQ(scene.objects[0].scheme, SubdivisionScheme::Catmark);
    EXPECT_EQ(scene.lens.apertureRadius, 0.0f);
    EXPECT_EQ(scene.shutter.open, 0.0f);
    EXPECT_EQ(scene.shutter.close, 1.0f);
    const SceneDesc loop = parseScene(R"({"objects": [{"cage": "m/loop_x.obj"}]})", "s", "");
    EXPECT_EQ(loop.objects[0].scheme, SubdivisionScheme::Loop);
}

TEST(SceneReader, ReadsEveryField) {
    const SceneDesc s = parseScene(R"({
      "camera": {"position": [1, 2, 3], "look_at": [0, 0, 0], "up": [0, 0, 1], "fov_y_degrees": 30,
                 "near": 0.1, "far": 50, "close": {"position": [2, 2, 3]}},
      "lens": {"aperture_radius": 0.5, "focus_distance": 4},
      "shutter": {"open": 0.25, "close": 0.75},
      "film": {"width": 64, "height": 32, "spp": 8, "seed": 9},
      "tessellation": {"partitioning": "fractional_even", "target_edge_pixels": 3, "max_factor": 20,
                       "inside_reduction": "max", "factor": 2},
      "objects": [{"name": "x", "cage": "a.obj", "cage_close": "b.obj", "scheme": "bilinear",
                   "open": {"translate": [1, 0, 0], "rotate_degrees": [0, 90, 0], "scale": [2, 2, 2]},
                   "close": {"translate": [2, 0, 0]},
                   "material": {"color": [1, 0, 0], "opacity": 0.25}}]})",
                                   "s.json", "");
    EXPECT_EQ(s.camera.close.position, Vec3(2, 2, 3));
    EXPECT_EQ(s.camera.close.lookAt, Vec3(0, 0, 0));
    EXPECT_EQ(s.camera.fovYDegrees, 30.0f);
    EXPECT_EQ(s.lens.focusDistance, 4.0f);
    EXPECT_EQ(s.shutter.open, 0.25f);
    EXPECT_EQ(s.film.samplesPerPixel, 8);
    EXPECT_EQ(s.film.seed, 9u);
    EXPECT_EQ(s.tessellation.partitioning, Partitioning::FractionalEven);
    EXPECT_EQ(s.tessellation.insideReduction, InsideReduction::Max);
    EXPECT_EQ(s.objects[0].scheme, SubdivisionScheme::Bilinear);
    EXPECT_EQ(s.objects[0].cageClosePath, "b.obj");
    EXPECT_EQ(s.objects[0].close.translate, Vec3(2, 0, 0));
    EXPECT_EQ(s.objects[0].close.scale, Vec3(2, 2, 2));  // unspecified close values follow open
    EXPECT_EQ(s.objects[0].material.opacity, 0.25f);
}

TEST(SceneReader, SyntaxErrorsGiveLineAndColumn) {
    const std::string e = errorOf("{\n  \"objects\": [\n    {\"cage\": \"a.obj\",}\n  ]\n}");
    EXPECT_NE(e.find("scene.json: line 3, column 22: JSON syntax error"), std::string::npos) << e;
}

// A number beyond double range is refused by nlohmann without a position: it is found in the
// text (the first such number outside a string) and named by line and column, like a syntax error.
TEST(SceneReader, NumberOverflowGivesLineAndColumn) {
    const std::string e = errorOf(
        "{\"objects\": [{\"cage\": \"1e999.obj\", \"name\": \"a \\\" -1e999\", \"open\":\n"
        "  {\"scale\": [1e300, 2, -1E+999]}}]}");
    EXPECT_NE(e.find("scene.json: line 2, column 24: JSON number overflow parsing '-1E+999'"),
              std::string::npos)
        << e;
    EXPECT_NE(errorOf("{\"film\": {\"seed\": 1" + std::string(400, '0') + "}}")
                  .find("scene.json: line 1, column 19: JSON number overflow"),
              std::string::npos);
}

TEST(SceneReader, FieldErrorsNameTheField) {
    EXPECT_NE(errorOf(R"({"objects": [{"cage": "a.obj", "colour": 1}]})")
                  .find("objects[0].colour: unknown key"),
              std::string::npos);
    EXPECT_NE(
        errorOf(R"({"camara": {}, "objects": [{"cage": "a.obj"}]})").find("camara: unknown key"),
        std::string::npos);
    EXPECT_NE(errorOf(R"({"film": {"width": "wide"}, "objects": [{"cage": "a.obj"}]})")
                  .find("film.width: expected an integer, found string"),
              std::string::npos);
    EXPECT_NE(errorOf(R"({"film": {"width": 0}, "objects": [{"cage": "a.obj"}]})")
                  .find("film.width: value 0 is outside"),
              std::string::npos);
    EXPECT_NE(errorOf(R"({"lens": {"aperture_radius": -1}, "objects": [{"cage": "a.obj"}]})")
                  .find("lens.aperture_radius"),
              std::string::npos);
    EXPECT_NE(errorOf(R"({"lens": {"focus_distance": 1e999}, "objects": [{"cage": "a.obj"}]})")
                  .find("scene.json: line 1, column 29: JSON number overflow parsing '1e999'"),
              std::string::npos);
    EXPECT_NE(errorOf(R"({"camera": {"position": [0, 0]}, "objects": [{"cage": "a.obj"}]})")
                  .find("camera.position: expected an array of 3 numbers"),
              std::string::npos);
    EXPECT_NE(
        errorOf(
            R"({"camera": {"position": [0, 0, 0], "look_at": [0, 0, 0]}, "objects": [{"cage": "a.obj"}]})")
            .find("camera.look_at"),
        std::string::npos);
    EXPECT_NE(errorOf(R"({"objects": [{"cage": "a.obj", "material": {"opacity": 2}}]})")
                  .find("objects[0].material.opacity"),
              std::string::npos);
    EXPECT_NE(errorOf(R"({"objects": [{"cage": "a.obj", "scheme": "doo-sabin"}]})")
                  .find("objects[0].scheme"),
              std::string::npos);
    EXPECT_NE(
        errorOf(R"({"tessellation": {"partitioning": "odd"}, "objects": [{"cage": "a.obj"}]})")
            .find("tessellation.partitioning: unknown partitioning 'odd'"),
        std::string::npos);
    EXPECT_NE(
        errorOf(R"({"objects": [{"name": "x"}]})").find("objects[0].cage: missing required string"),
        std::string::npos);
    EXPECT_NE(errorOf(R"({"objects": []})").find("objects: the scene has no objects"),
              std::string::npos);
    EXPECT_NE(errorOf(R"({})").find("objects: missing"), std::string::npos);
    EXPECT_NE(errorOf(R"([1, 2])").find("expected an object"), std::string::npos);
    EXPECT_NE(errorOf(R"({"shutter": {"open": 0.8, "close": 0.2}, "objects": [{"cage": "a.obj"}]})")
                  .find("shutter.close"),
              std::string::npos);
}

TEST(SceneReader, FilmOverTheMemoryBudgetIsRefusedBeforeAllocating) {
    SceneLimits limits;
    limits.memoryBudgetBytes = 1 << 20;
    try {
        parseScene(
            R"({"film": {"width": 1024, "height": 1024, "spp": 64}, "objects": [{"cage": "a.obj"}]})",
            "scene.json", "", limits);
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(
            std::string(e.what()).find("film.spp: film of 1024x1024 at 64 spp needs 2048 MiB"),
            std::string::npos)
            << e.what();
    }
}

TEST(SceneReader, MissingSceneFileIsAnInputError) {
    EXPECT_THROW(readSceneFile("/nonexistent/scene.json"), InputError);
}

}  // namespace
}  // namespace patchsim
