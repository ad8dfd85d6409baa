// End-to-end tests of the patchsim command: exit codes, messages, and no partial output.

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "tests/cli_runner.h"
#include "tests/test_paths.h"

namespace {

namespace fs = std::filesystem;
using patchsim::test::sourcePath;

using patchsim::test::CommandResult;
using patchsim::test::run;
using patchsim::test::writeFile;

std::string readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// The Pythons patchsim tries for its plots (pipeline/driver/plots.cpp), the first with matplotlib;
// empty when none has it.
std::string pythonWithMatplotlib() {
    for (const char* python : {"/usr/bin/python3", "python3"})
        if (std::system((std::string(python) + " -c 'import matplotlib, numpy' > /dev/null 2>&1")
                            .c_str()) == 0)
            return python;
    return {};
}

TEST(Cli, InfoOnEveryShippedSceneAndTheDefault) {
    for (const std::string& scene : patchsim::test::sceneFiles()) {
        const CommandResult r = run("info " + scene);
        EXPECT_EQ(r.exitCode, 0) << scene << "\n" << r.output;
        EXPECT_NE(r.output.find("mode:"), std::string::npos);
    }
    const CommandResult r = run("info");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("motion:        yes"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("defocus:       yes"), std::string::npos) << r.output;
}

TEST(Cli, InfoReportsStaticModeAndOverrides) {
    CommandResult r = run("info " + sourcePath("scenes/static.json"));
    EXPECT_NE(r.output.find("motion:        no"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("mode:          static"), std::string::npos) << r.output;
    r = run("info --no-motion " + sourcePath("scenes/motion.json"));
    EXPECT_NE(r.output.find("motion:        yes (switched off)"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("mode:          static"), std::string::npos) << r.output;
}

TEST(Cli, TessellateWritesAnObjAndStats) {
    const std::string dir = patchsim::test::temporaryDirectory();
    const std::string obj = dir + "/ngons.obj", stats = dir + "/stats.json";
    const CommandResult r = run("tessellate " + sourcePath("scenes/ngons_loop.json") + " -o " +
                                obj + " --time 0.5 --stats " + stats + " --threads 2");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_TRUE(fs::exists(obj));
    EXPECT_TRUE(fs::exists(stats));
    std::ifstream in(stats);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_NE(text.find("\"schema\": \"patchsim-stats\""), std::string::npos);
    EXPECT_NE(text.find("\"TS/Triangles\""), std::string::npos);
}

TEST(Cli, TessellationIsIdenticalOnOneAndTwoThreads) {
    const std::string dir = patchsim::test::temporaryDirectory();
    ASSERT_EQ(
        run("tessellate -q --threads 1 -o " + dir + "/a.obj --stats " + dir + "/a.json").exitCode,
        0);
    ASSERT_EQ(
        run("tessellate -q --threads 2 -o " + dir + "/b.obj --stats " + dir + "/b.json").exitCode,
        0);
    auto read = [](const std::string& p) {
        std::ifstream in(p);
        return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    };
    EXPECT_EQ(read(dir + "/a.obj"), read(dir + "/b.obj"));
    EXPECT_EQ(read(dir + "/a.json"), read(dir + "/b.json"));
}

void expectCleanFailure(const std::string& scene, const std::string& message) {
    const std::string out = patchsim::test::temporaryDirectory() + "/should-not-exist.obj";
    fs::remove(out);
    const CommandResult r = run("tessellate " + scene + " -o " + out);
    EXPECT_NE(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find(message), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("internal error"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out)) << "partial output left behind";
    for (const auto& entry : fs::directory_iterator(fs::path(out).parent_path()))
        EXPECT_EQ(entry.path().string().find(".tmp-patchsim"), std::string::npos);
}

TEST(Cli, BadInputFailsCleanly) {
    expectCleanFailure("/nonexistent.json", "/nonexistent.json: scene: cannot open");
    const std::string bad = writeFile("syntax.json", "{\n  \"objects\": [,]\n}\n");
    expectCleanFailure(bad, "syntax.json: line 2, column 15: JSON syntax error");
    const std::string unknown =
        writeFile("unknown.json", R"({"objects": [{"cage": "x.obj", "speed": 1}]})");
    expectCleanFailure(unknown, "unknown.json: objects[0].speed: unknown key");
    const std::string missing =
        writeFile("missing.json", R"({"objects": [{"cage": "no-such-cage.obj"}]})");
    expectCleanFailure(missing, "missing.json: objects[0].cage: cannot open");
    const std::string badObj = writeFile("bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
    const std::string usesBad = writeFile("uses-bad.json", R"({"objects": [{"cage": "bad.obj"}]})");
    expectCleanFailure(usesBad, "bad.obj: line 4, column 7: vertex index 9 out of range");
    const std::string wrongType =
        writeFile("type.json", R"({"film": {"spp": 2.5}, "objects": [{"cage": "x.obj"}]})");
    expectCleanFailure(wrongType, "type.json: film.spp: expected an integer");
    const std::string huge = writeFile(
        "huge.json",
        R"({"film": {"width": 16384, "height": 16384, "spp": 4096}, "objects": [{"cage": "x.obj"}]})");
    // Refused by the command that would render the film (tessellate renders none).
    const std::string out = patchsim::test::temporaryDirectory() + "/huge-render";
    const CommandResult r = run("render -q --no-progress " + huge + " -o " + out);
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("huge.json: film.spp: film of 16384x16384 at 4096 spp needs"),
              std::string::npos)
        << r.output;
    EXPECT_FALSE(fs::exists(out));
}

TEST(Cli, NonRegularFilesAndDuplicateKeysAreRefused) {
    expectCleanFailure("/dev/zero", "'/dev/zero' is not a regular file");
    const std::string zeroCage =
        writeFile("zero-cage.json", R"({"objects": [{"cage": "/dev/zero"}]})");
    expectCleanFailure(zeroCage,
                       "zero-cage.json: objects[0].cage: '/dev/zero' is not a regular file");
    const std::string twice = writeFile(
        "twice.json", R"({"film": {"spp": 4, "spp": 8}, "objects": [{"cage": "x.obj"}]})");
    expectCleanFailure(twice, "twice.json: film.spp: key given twice");
}

// Every output problem is bad input (exit 2, the path named) found before the work, and a
// failure leaves no file behind, not even a temporary.
TEST(Cli, OutputPathErrorsExitTwoAndLeaveNothing) {
    const std::string tmp = patchsim::test::temporaryDirectory() + "/outputs";
    fs::remove_all(tmp);
    fs::create_directories(tmp);
    const std::string file = writeFile("outputs/plain-file", "x");
    const std::string small = sourcePath("scenes/static.json") + " -q --no-progress";
    auto expectRefused = [&](const std::string& args, const std::string& message) {
        const CommandResult r = run(args);
        EXPECT_EQ(r.exitCode, 2) << args << "\n" << r.output;
        EXPECT_NE(r.output.find(message), std::string::npos) << args << "\n" << r.output;
        EXPECT_EQ(r.output.find("internal error"), std::string::npos) << r.output;
    };
    expectRefused("render " + small + " -o " + file + "/below", file + "/below: -o: cannot make");
    expectRefused("render " + small + " -o " + file, file + ": -o: is a file");
    expectRefused("render " + small + " -o /proc/patchsim-out", "/proc/patchsim-out: -o");
    expectRefused("render " + small + " -o " + tmp + "/r1 --trace " + tmp,
                  tmp + ": --trace: is a folder");
    EXPECT_FALSE(fs::exists(tmp + "/r1")) << "the output folder made for a failed render";
    fs::create_directories(tmp + "/r2/image.exr");
    expectRefused("render " + small + " -o " + tmp + "/r2", tmp + "/r2/image.exr: -o: is a folder");
    expectRefused("tessellate -q " + sourcePath("scenes/static.json") + " -o " + tmp,
                  tmp + ": -o: is a folder");
    const std::string grid = writeFile("outputs/grid.json", R"({"rasterizer": {"tile_size": [8]},
        "film": {"width": 8, "height": 8, "spp": 1}})");
    expectRefused("explore " + sourcePath("scenes/static.json") + " --grid " + grid + " -o " + tmp,
                  tmp + ": -o: is a folder");
    expectRefused("explore " + sourcePath("scenes/static.json") + " --grid " + grid + " -o " + tmp +
                      "/points.csv --plots " + file,
                  file + ": --plots: is a file");
    // The plots' folder and the script's copy are made before the CSV is refused, and removed.
    expectRefused("explore " + sourcePath("scenes/static.json") + " --grid " + grid + " -o " + tmp +
                      " --plots " + tmp + "/plots",
                  tmp + ": -o: is a folder");
    fs::create_directories(tmp + "/p2/plot_results.py");
    expectRefused("explore " + sourcePath("scenes/static.json") + " --grid " + grid + " -o " + tmp +
                      "/points.csv --plots " + tmp + "/p2",
                  tmp + "/p2/plot_results.py: --plots: is a folder");
    fs::remove_all(tmp + "/p2");
    // What is left: the plain file, the grid, the folder named image.exr. Nothing else.
    std::vector<std::string> left;
    for (const auto& entry : fs::recursive_directory_iterator(tmp))
        left.push_back(fs::relative(entry.path(), tmp).string());
    std::sort(left.begin(), left.end());
    EXPECT_EQ(left, (std::vector<std::string>{"grid.json", "plain-file", "r2", "r2/image.exr"}));
}

TEST(Cli, CommandLineNumbersAreCheckedWithClearMessages) {
    CommandResult r = run("info --threads -1");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("command line: --threads: -1 is outside [0, 4096]"), std::string::npos)
        << r.output;
    EXPECT_LT(r.output.size(), 400u) << r.output;
    r = run("explore --grid x.json --threads -3");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("--threads: -3 is outside [0, 4096]"), std::string::npos) << r.output;
    const std::string out = patchsim::test::temporaryDirectory() + "/budget";
    r = run("render -q --no-progress -o " + out + " --memory-budget-mib 17592186044416");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("--memory-budget-mib"), std::string::npos) << r.output;
    // The budget holds for the built-in scene too (it asks for 320x240 at 16 spp, 37 MiB).
    r = run("render -q --no-progress -o " + out + " --memory-budget-mib 1");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("builtin:default.json: film.spp: film of 320x240 at 16 spp needs 37 "
                            "MiB, over the memory budget of 1 MiB"),
              std::string::npos)
        << r.output;
    EXPECT_FALSE(fs::exists(out));
    // A scene's own film does not stop the commands that render none, nor a smaller --spp.
    r = run("info --memory-budget-mib 1");
    EXPECT_EQ(r.exitCode, 2) << "info renders no film: no budget option\n" << r.output;
    r = run("info");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    r = run("render -q --no-progress -o " + out + " --memory-budget-mib 3 --spp 1");
    EXPECT_EQ(r.exitCode, 0) << "the film rendered is 320x240 at 1 spp\n" << r.output;
    r = run("--help");
    EXPECT_NE(r.output.find("out/"), std::string::npos) << "a bare patchsim writes out/";
}

TEST(Cli, InfoAndTessellateEveryRegressionCage) {
    auto cages = patchsim::test::regressionCageFiles();
    for (const auto& entry : fs::directory_iterator(sourcePath("scenes/cages")))
        if (entry.path().extension() == ".obj") cages.push_back(entry.path().string());
    const std::string out = patchsim::test::temporaryDirectory() + "/cage.obj";
    for (const std::string& cage : cages) {
        CommandResult r = run("info " + cage);
        EXPECT_EQ(r.exitCode, 0) << cage << "\n" << r.output;
        EXPECT_NE(r.output.find("triangles:"), std::string::npos) << cage;
        r = run("tessellate -q " + cage + " -o " + out);
        EXPECT_EQ(r.exitCode, 0) << cage << "\n" << r.output;
        EXPECT_TRUE(fs::exists(out)) << cage;
        fs::remove(out);
    }
}

// OpenSubdiv 3.5.0's Bfr reads uninitialised memory on this cage and may crash; patchsim evaluates
// the affected faces on Far's patch table and says so.
TEST(Cli, RendersTheCageThatCrashesBfr350) {
    const std::string dir = patchsim::test::temporaryDirectory() + "/val2";
    const std::string cage = sourcePath("scenes/cages/catmark_val2_interior.obj");
    CommandResult r = run("info " + cage);
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("8 faces evaluated on Far's patch table"), std::string::npos)
        << r.output;
    r = run("render -q --no-progress " + cage + " -o " + dir);
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_TRUE(fs::exists(dir + "/image.exr"));
}

TEST(Cli, RenderWritesImagesAndStats) {
    const std::string dir = patchsim::test::temporaryDirectory() + "/render";
    const CommandResult r = run("render -q " + sourcePath("scenes/motion.json") + " -o " + dir +
                                " --tile-size 16 --branch-method first-split");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    for (const char* file : {"image.exr", "image.png", "stats.json"})
        EXPECT_TRUE(fs::exists(dir + "/" + file)) << file;
    std::ifstream in(dir + "/stats.json");
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_NE(text.find("\"RS/Rays cast\""), std::string::npos);
    EXPECT_NE(text.find("\"sample test efficiency\""), std::string::npos);
    EXPECT_NE(text.find("\"branch method\": \"first-split\""), std::string::npos);
}

TEST(Cli, RenderRejectsBadRasterizerOptions) {
    const std::string dir = patchsim::test::temporaryDirectory() + "/bad-render";
    CommandResult r = run("render -q -o " + dir + " --tile-size 0");
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(r.output.find("command line: --tile-size: value 0 is outside [1, 256]"),
              std::string::npos)
        << r.output;
    r = run("render -q -o " + dir + " --tile-size 8.5");
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(r.output.find("--tile-size: expected an integer"), std::string::npos) << r.output;
    r = run("render -q -o " + dir + " --branch-method sideways");
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.output.find("--branch-method"), std::string::npos) << r.output;
    const std::string scene = writeFile(
        "raster.json",
        R"({"rasterizer": {"leaf_size": 4, "max_triangles_per_group": 1000}, "objects": [{"cage": "x.obj"}]})");
    r = run("render -q " + scene + " -o " + dir);
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.output.find("raster.json: rasterizer.max_triangles_per_group"), std::string::npos)
        << r.output;
    EXPECT_FALSE(fs::exists(dir + "/image.png"));
    // A tile holding more samples than a worker keeps: one error, no output.
    const std::string bigTiles =
        writeFile("big_tiles.json", R"({"film": {"width": 64, "height": 48, "spp": 64},
        "rasterizer": {"tile_size": 256},
        "objects": [{"cage": ")" + sourcePath("scenes/cages/catmark_torus.obj") +
                                        R"("}]})");
    r = run("render -q " + bigTiles + " -o " + dir);
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(r.output.find("big_tiles.json: rasterizer.tile_size: a tile of 256x256 pixels at 64 "
                            "spp holds 4194304 samples"),
              std::string::npos)
        << r.output;
    EXPECT_FALSE(fs::exists(dir + "/image.png"));
    // Legal tiles whose ray scratch, one per rasterizer worker, with the film exceeds the memory
    // budget: 2 tiles of 256x256 at 16 spp, so 2 workers even when 16 threads are asked for.
    r = run("render -q -o " + dir + " --tile-size 256 --threads 16 --memory-budget-mib 1024");
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(r.output.find("builtin:default.json: rasterizer.tile_size: tiles of 256x256 pixels "
                            "at 16 spp need"),
              std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find("in each of 2 rasterizer workers"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("over the memory budget of 1024 MiB"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir + "/image.png"));
    // One worker's scratch fits the same budget.
    r = run("render -q -o " + dir + " --tile-size 256 --threads 1 --memory-budget-mib 1024");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_TRUE(fs::exists(dir + "/image.png"));
}

TEST(Cli, VerifyTilesReportsEveryVariantWithoutFalseRejects) {
    const std::string dir = patchsim::test::temporaryDirectory() + "/verify";
    fs::create_directories(dir);
    const CommandResult r = run("verify-tiles --cases 300 --csv " + dir + "/cases.csv --summary " +
                                dir + "/summary.csv");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    for (const char* variant :
         {"patent-3d (pinhole):", "patent-3d-time (lens):", "patent-2dh-time (lens):",
          "patent-2d-time (pinhole):", "triangle-bbox (lens):", "interval-4 (pinhole):",
          "dual-space (lens):", "traversal-2d (hierarchy):", "branch-bitmask (hierarchy):",
          "bounds-level-0 (hierarchy):"})
        EXPECT_NE(
            r.output.find(std::string(variant) + " cases 300, false rejects 0, false accepts"),
            std::string::npos)
            << variant << "\n"
            << r.output;
    EXPECT_NE(r.output.find(" outside the exact truth"), std::string::npos) << r.output;
    std::ifstream summary(dir + "/summary.csv"), cases(dir + "/cases.csv");
    std::string header, line;
    std::getline(summary, header);
    EXPECT_EQ(header.rfind("variant,model,cases,", 0), 0u) << header;
    int rows = 0;
    while (std::getline(summary, line)) ++rows;
    EXPECT_GE(rows, 30);
    std::getline(cases, header);
    EXPECT_EQ(header.rfind("model,case,kind,variant,truth_hit", 0), 0u) << header;
    std::getline(cases, line);
    EXPECT_EQ(line.rfind("pinhole,0,", 0), 0u) << line;
}

TEST(Cli, VerifyTilesReplaysACaseAndRefusesABadName) {
    CommandResult r = run("verify-tiles --seed 3 --replay pinhole:12");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("case pinhole:12 (seed 3)"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("patent-2d-time:"), std::string::npos) << r.output;
    r = run("verify-tiles --replay lens:twelve");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("--replay"), std::string::npos) << r.output;
    r = run("verify-tiles --cases 0");
    EXPECT_EQ(r.exitCode, 2) << r.output;
}

TEST(Cli, RenderWritesHeatMapsAndUsesTheBackEndOptions) {
    const std::string dir = patchsim::test::temporaryDirectory() + "/heat";
    const CommandResult r =
        run("render -q " + sourcePath("scenes/transparency.json") + " -o " + dir +
            " --heatmaps --filter gaussian --shading-rate per-pixel-primitive --max-layers 4");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("and 13 heat maps"), std::string::npos) << r.output;
    for (const char* file :
         {"heat_rays_cast_pixel.png", "heat_ste_tile.png", "heat_tile_tests_tile.png"})
        EXPECT_TRUE(fs::exists(dir + "/" + file)) << file;
    std::ifstream in(dir + "/stats.json");
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_NE(text.find("\"filter\": \"gaussian\""), std::string::npos);
    EXPECT_NE(text.find("\"max layers\": \"4\""), std::string::npos);
    EXPECT_NE(text.find("\"OM/Transparent fragments\""), std::string::npos);
}

// Heat maps of an earlier render in the folder would describe another frame.
TEST(Cli, RenderRemovesHeatMapsOfAnEarlierRender) {
    const std::string dir = patchsim::test::temporaryDirectory() + "/heat-stale";
    const std::string args = "render -q --no-progress --width 32 --height 24 --spp 1 -o " + dir;
    ASSERT_EQ(run(args + " --heatmaps").exitCode, 0);
    ASSERT_TRUE(fs::exists(dir + "/heat_rays_cast_pixel.png"));
    std::ofstream(dir + "/heat_mine.png") << "the user's own";
    ASSERT_EQ(run(args + " --method interval").exitCode, 0);
    std::vector<std::string> left;
    for (const auto& entry : fs::directory_iterator(dir))
        left.push_back(entry.path().filename().string());
    std::sort(left.begin(), left.end());
    EXPECT_EQ(left,
              (std::vector<std::string>{"heat_mine.png", "image.exr", "image.png", "stats.json"}));
}

TEST(Cli, ProgressBarOnlyOnATerminal) {
    const std::string dir = patchsim::test::temporaryDirectory() + "/progress";
    // Not a terminal (a pipe): no progress bar.
    CommandResult r = run("render -q -o " + dir);
    EXPECT_EQ(r.output.find("patches  "), std::string::npos) << r.output;
    // On a pseudo-terminal (util-linux script): patches done and time left.
    if (std::system("command -v script > /dev/null 2>&1") != 0) GTEST_SKIP() << "no script(1)";
    const std::string command = "script -q -e -c '" + std::string(PATCHSIM_BINARY) +
                                " render -q -o " + dir + "' /dev/null 2>&1";
    FILE* pipe = popen(command.c_str(), "r");
    ASSERT_NE(pipe, nullptr);
    std::string output;
    char buffer[4096];
    std::size_t n;
    while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) output.append(buffer, n);
    pclose(pipe);
    EXPECT_NE(output.find("58/58 patches"), std::string::npos) << output;
    EXPECT_NE(output.find("shading    [##############################] 100%  240/240 rows"),
              std::string::npos)
        << "the bar must follow the render to its end\n"
        << output;
    EXPECT_NE(output.find("took"), std::string::npos) << output;
}

TEST(Cli, RenderIsBitIdenticalAcrossRunsAndThreadCounts) {
    const std::string dir = patchsim::test::temporaryDirectory();
    auto read = [](const std::string& p) {
        std::ifstream in(p, std::ios::binary);
        return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    };
    const std::string scene = sourcePath("scenes/motion_defocus.json");
    std::vector<std::string> runs;
    for (const char* threads : {"1", "2", "2"}) {
        const std::string out = dir + "/determinism-" + std::to_string(runs.size());
        ASSERT_EQ(run("render -q --no-progress --heatmaps " + scene + " -o " + out + " --threads " +
                      threads)
                      .exitCode,
                  0);
        runs.push_back(out);
    }
    for (const char* file : {"image.exr", "image.png", "stats.json", "heat_rays_cast_pixel.png"}) {
        const std::string first = read(runs[0] + "/" + file);
        EXPECT_FALSE(first.empty()) << file;
        for (std::size_t i = 1; i < runs.size(); ++i)
            EXPECT_TRUE(first == read(runs[i] + "/" + file)) << file << " differs in run " << i;
    }
}

TEST(Cli, ExploreWritesCsvAndMpiGivesTheSameFile) {
    const std::string dir = patchsim::test::temporaryDirectory() + "/explore";
    fs::create_directories(dir);
    const std::string grid =
        writeFile("grid.json", R"({"rasterizer": {"tile_size": [4, 16], "leaf_size": [2, 4]},
        "hardware": {"RS.throughput.ray_box_tests": [8, 16]}, "film": {"width": 32, "height": 24, "spp": 2}})");
    const std::string scenes =
        sourcePath("scenes/motion.json") + " " + sourcePath("scenes/static.json");
    CommandResult r = run("explore " + scenes + " --grid " + grid + " -o " + dir + "/local.csv");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const std::string local = readFile(dir + "/local.csv");
    EXPECT_EQ(std::count(local.begin(), local.end(), '\n'), 1 + 2 * 2 * 2 * 2);  // header + points
    if (std::system("command -v mpirun > /dev/null 2>&1") != 0) GTEST_SKIP() << "no mpirun";
    // OpenMPI's own start-up allocations are never freed; under LeakSanitizer they would be
    // reported as leaks of this run, so leak detection is off for the MPI run alone (the same
    // explore code ran above without MPI, with it on).
    const std::string mpiEnv =
        "ASAN_OPTIONS=detect_leaks=0 OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 ";
    const std::string mpi = mpiEnv + "mpirun -np 2 --oversubscribe -x ASAN_OPTIONS ";
    const std::string command = mpi + PATCHSIM_BINARY + " explore " + scenes + " --grid " + grid +
                                " -o " + dir + "/mpi.csv --threads 1 2>&1";
    ASSERT_EQ(std::system(command.c_str()), 0);
    std::ifstream mpiIn(dir + "/mpi.csv");
    const std::string distributed((std::istreambuf_iterator<char>(mpiIn)),
                                  std::istreambuf_iterator<char>());
    EXPECT_TRUE(local == distributed) << "mpirun -np 2 wrote a different file";
    // A bad value in the job rank 1 would run: every rank refuses the grid before any job, so
    // no rank waits for another; all exit 2.
    const std::string bad = writeFile("bad-grid.json", R"({"rasterizer": {"tile_size": [8, 0]}})");
    const std::string badRun = mpiEnv +
                               "timeout 120 mpirun -np 2 --oversubscribe -x ASAN_OPTIONS " +
                               PATCHSIM_BINARY + " explore " + scenes + " --grid " + bad + " -o " +
                               dir + "/bad.csv > " + dir + "/bad.log 2>&1";
    const int status = std::system(badRun.c_str());
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 2) << "124 means a rank hung";
    EXPECT_FALSE(fs::exists(dir + "/bad.csv"));
}

// explore --plots: the built-in script, copied beside the plots, draws cycles against each
// parameter and the heat map of the pair, PNG and SVG; the CSV names each point's bottleneck.
TEST(Cli, ExplorePlotsCyclesAndAHeatMapAndTheCsvNamesTheBottleneck) {
    const std::string dir = patchsim::test::temporaryDirectory() + "/explore-plots";
    fs::remove_all(dir);
    const std::string grid =
        writeFile("plots-grid.json",
                  R"({"rasterizer": {"tile_size": [4, 16], "leaf_size": [2, 4]},
        "film": {"width": 32, "height": 24, "spp": 2}})");
    // The plots' folder may hold the CSV too; the command makes it.
    const std::string args = "explore " + sourcePath("scenes/motion.json") + " --grid " + grid +
                             " -o " + dir + "/plots/points.csv --plots " + dir + "/plots";
    CommandResult r = run(args);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    std::istringstream csv(readFile(dir + "/plots/points.csv"));
    std::string header;
    std::getline(csv, header);
    EXPECT_EQ(header.rfind("scene,tile_size,leaf_size,total_cycles,microseconds,bottleneck,"
                           "bottleneck_utilisation,",
                           0),
              0u)
        << header;
    int points = 0;
    for (std::string line; std::getline(csv, line); ++points)
        EXPECT_NE(line.find(",RS,"), std::string::npos) << "the rasterizer limits: " << line;
    EXPECT_EQ(points, 4);
    EXPECT_EQ(readFile(dir + "/plots/plot_results.py"),
              readFile(sourcePath("scripts/plot_results.py")))
        << "the copy beside the plots is the script built into the binary";
    // Without matplotlib: the results, the script and a hint how to draw the plots later.
    const std::string withoutPython = dir + "/without-python.log";
    std::system(("PATCHSIM_PYTHON=/nonexistent " + std::string(PATCHSIM_BINARY) + " " + args +
                 " > " + withoutPython + " 2>&1")
                    .c_str());
    EXPECT_NE(readFile(withoutPython).find("plots skipped: no Python with matplotlib"),
              std::string::npos)
        << readFile(withoutPython);
    EXPECT_NE(readFile(withoutPython).find("plot_results.py' explore '"), std::string::npos);

    if (pythonWithMatplotlib().empty())
        GTEST_SKIP() << "no python3 with matplotlib and numpy (Debian: python3-matplotlib, "
                        "scripts/install-deps.sh): the plots were not drawn";
    EXPECT_NE(r.output.find("wrote the plots in " + dir + "/plots"), std::string::npos) << r.output;
    for (const char* name : {"cycles_vs_tile_size", "cycles_vs_leaf_size",
                             "heatmap_tile_size_x_leaf_size", "energy_vs_cycles"}) {
        const std::string png = readFile(dir + "/plots/" + name + ".png");
        EXPECT_EQ(png.substr(0, 4), "\x89PNG") << name << "\n"
                                               << readFile(dir + "/plots/plots.log");
        EXPECT_NE(readFile(dir + "/plots/" + name + ".svg").find("<svg"), std::string::npos)
            << name;
    }
    // SVG text stays text: the axis titles with their units, the cells' bottleneck stage.
    const std::string heatMap = readFile(dir + "/plots/heatmap_tile_size_x_leaf_size.svg");
    for (const char* text :
         {"tile_size (pixels)", "leaf_size (triangles)", "modelled cycles per frame", ">RS 9"})
        EXPECT_NE(heatMap.find(text), std::string::npos) << text;
}

// The plotting script itself, on a hand-written explore CSV: engineering numbers (695k, 1.23M),
// binary sizes, units on both axes, and each cell's bottleneck and utilisation.
TEST(Cli, PlotScriptDrawsExploreFiguresFromAHandWrittenCsv) {
    const std::string python = pythonWithMatplotlib();
    if (python.empty())
        GTEST_SKIP() << "no python3 with matplotlib and numpy (Debian: python3-matplotlib)";
    const std::string dir = patchsim::test::temporaryDirectory() + "/plot-script";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string csv = writeFile(
        "plot-script/hand.csv",
        "scene,tile_size,scratch_budget_bytes,total_cycles,microseconds,bottleneck,"
        "bottleneck_utilisation,sample_test_efficiency,patches_over_scratch_budget,RS/Rays cast\n"
        "hand.json,4,16384,695355,463.57,RS,0.99,0.1,0,100\n"
        "hand.json,4,65536,521516,347.6773333,RS,0.98,0.1,0,100\n"
        "hand.json,8,16384,1234567,823.0446667,PS,0.87,0.1,0,100\n"
        "hand.json,8,65536,999999,666.666,PS,0.9,0.1,0,100\n");
    const std::string command = python + " " + sourcePath("scripts/plot_results.py") + " explore " +
                                csv + " " + dir + "/out > " + dir + "/log 2>&1";
    ASSERT_EQ(std::system(command.c_str()), 0) << readFile(dir + "/log");
    const std::string heatMap = readFile(dir + "/out/heatmap_tile_size_x_scratch_budget_bytes.svg");
    for (const char* text :
         {">695k<", ">522k<", ">1.23M<", ">1M<", ">RS 99%<", ">PS 87%<", ">16 KiB<", ">64 KiB<",
          "tile_size (pixels)", "scratch_budget_bytes (bytes)", "modelled cycles per frame"})
        EXPECT_NE(heatMap.find(text), std::string::npos) << text;
    const std::string against = readFile(dir + "/out/cycles_vs_scratch_budget_bytes.svg");
    for (const char* text : {"modelled cycles per frame", "microseconds at 1.5 GHz",
                             "bottleneck PS", "bottleneck RS", "tile_size 8", ">1.2M<"})
        EXPECT_NE(against.find(text), std::string::npos) << text;
    EXPECT_TRUE(fs::exists(dir + "/out/cycles_vs_tile_size.png"));
    // A bad call says how to call it.
    EXPECT_NE(std::system((python + " " + sourcePath("scripts/plot_results.py") + " plot " + csv +
                           " > /dev/null 2>&1")
                              .c_str()),
              0);
}

// DESIGN.md section 13: one frame split across ranks by screen tiles, one output, equal to a local
// render byte for byte (images, heat maps, stats); for both visibility methods and with
// transparency.
TEST(Cli, MpiRenderSplitsAFrameAndEqualsTheLocalRender) {
    if (std::system("command -v mpirun > /dev/null 2>&1") != 0) GTEST_SKIP() << "no mpirun";
    const std::string dir = patchsim::test::temporaryDirectory() + "/mpi-render";
    fs::remove_all(dir);
    const std::string scene =
        writeFile("mpi-scene.json", R"({"film": {"width": 40, "height": 30, "spp": 4},
        "lens": {"aperture_radius": 0.1, "focus_distance": 6},
        "objects": [{"cage": ")" + sourcePath("scenes/cages/catmark_torus.obj") +
                                        R"(",
                     "close": {"translate": [0.5, 0, 0]}, "material": {"opacity": 0.6}},
                    {"cage": ")" + sourcePath("scenes/cages/loop_icosahedron.obj") +
                                        R"(",
                     "open": {"translate": [0, 0, -1]}}]})");
    const std::string mpi =
        "ASAN_OPTIONS=detect_leaks=0 OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 "
        "timeout 300 mpirun -np 2 --oversubscribe -x ASAN_OPTIONS ";
    for (const char* method : {"patch", "reference"}) {
        const std::string local = dir + "/local-" + method, split = dir + "/split-" + method;
        // Heat maps come from the methods that count per pixel (the patch rasterizer's).
        const bool heatMaps = std::string(method) == "patch";
        const std::string args =
            " render " + scene + " -q --method " + method + (heatMaps ? " --heatmaps" : "");
        ASSERT_EQ(run(args.substr(1) + " -o " + local).exitCode, 0);
        const std::string command = mpi + PATCHSIM_BINARY + args + " -o " + split + " > " + dir +
                                    "/" + method + ".log 2>&1";
        ASSERT_EQ(std::system(command.c_str()), 0) << method;
        std::size_t files = 0;
        for (const auto& entry : fs::directory_iterator(local)) {
            const std::string name = entry.path().filename().string();
            std::ifstream a(entry.path(), std::ios::binary),
                b(split + "/" + name, std::ios::binary);
            const std::string bytesA((std::istreambuf_iterator<char>(a)), {});
            const std::string bytesB((std::istreambuf_iterator<char>(b)), {});
            EXPECT_TRUE(!bytesA.empty() && bytesA == bytesB) << method << " " << name << " differs";
            ++files;
        }
        EXPECT_EQ(files, heatMaps ? 16u : 3u) << "image.exr, image.png, stats.json (and 13 "
                                                 "heat maps)";
    }
    // An output refused by rank 0 ends every rank, exit 2, no hang.
    const std::string file = writeFile("mpi-render/not-a-folder", "x");
    const int status = std::system(
        (mpi + PATCHSIM_BINARY + " render -q -o " + file + " > /dev/null 2>&1").c_str());
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 2) << "124 means a rank hung";
}

TEST(Cli, SweepWritesResultsImagesPlotsAndReusesTheConvergedImage) {
    const std::string dir = patchsim::test::temporaryDirectory() + "/sweep";
    fs::remove_all(dir);
    const std::string scene = writeFile("sweep-scene.json", R"({"film": {"width": 48, "height": 32},
        "lens": {"aperture_radius": 0.1, "focus_distance": 5},
        "objects": [{"cage": ")" + sourcePath("scenes/cages/catmark_torus.obj") +
                                                                R"(",
                     "open": {"rotate_degrees": [60, 0, 0]}, "close": {"translate": [0.8, 0, 0]}}]})");
    const std::string args = "sweep " + scene +
                             " --methods patch,interval,interleaved --spp 1,4 --repeats 1 "
                             "--blur 1,3 --no-progress -o " +
                             dir;
    CommandResult r = run(args);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("sweep-scene: converged image (64 spp, patch method) rendered"),
              std::string::npos)
        << r.output;
    std::ifstream in(dir + "/results.csv");
    std::string header;
    std::getline(in, header);
    EXPECT_EQ(header.rfind("scene,method,setting,spp,wall_seconds,modelled_cycles,", 0), 0u)
        << header;
    int rows = 0;
    for (std::string line; std::getline(in, line);) ++rows;
    EXPECT_EQ(rows, 2 * 3 * 2);  // blur levels x methods x spp
    EXPECT_TRUE(fs::exists(dir + "/images/sweep-scene-blur3-interleaved-4.png"));
    EXPECT_TRUE(fs::exists(dir + "/images/sweep-scene-converged.png"));
    EXPECT_TRUE(fs::exists(dir + "/plots/plot_results.py"));
    if (!pythonWithMatplotlib().empty()) {
        for (const char* plot : {"sweep-scene.png", "sweep-scene.svg", "sweep-scene-blur3.png",
                                 "sweep-scene-crops.png"})
            EXPECT_TRUE(fs::exists(dir + "/plots/" + plot)) << plot << "\n" << r.output;
    }
    // Again, without a plotting library: the converged images are reused, the CSV still written.
    fs::remove(dir + "/results.csv");
    r = CommandResult{std::system(("PATCHSIM_PYTHON=/nonexistent " + std::string(PATCHSIM_BINARY) +
                                   " " + args + " > " + dir + "/second.log 2>&1")
                                      .c_str()),
                      ""};
    std::ifstream log(dir + "/second.log");
    const std::string second((std::istreambuf_iterator<char>(log)), {});
    EXPECT_NE(second.find("converged image (64 spp, patch method) reused"), std::string::npos)
        << second;
    EXPECT_NE(second.find("plots skipped: no Python with matplotlib"), std::string::npos) << second;
    EXPECT_TRUE(fs::exists(dir + "/results.csv"));
    r = run("sweep " + scene + " --methods patch,rasterize-harder -o " + dir);
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(r.output.find("--methods: 'rasterize-harder' is not one of patch, reference"),
              std::string::npos)
        << r.output;
}

// --vary runs a method at every combination of its own parameters' values; the exact methods'
// settings give the same error, so each method's Pareto-best setting is its cheapest in modelled
// cycles, marked in results.csv and listed in best.csv.
TEST(Cli, SweepVariesEachMethodsOwnParametersAndMarksItsParetoBest) {
    const std::string dir = patchsim::test::temporaryDirectory() + "/sweep-vary";
    fs::remove_all(dir);
    const std::string args = "sweep " + sourcePath("scenes/motion.json") +
                             " --methods patch,interval,triangle-bbox --spp 4 --repeats 1 "
                             "--converged-spp 16 --no-progress --vary time-strata=0,1 "
                             "--vary bbox-bound=hull,oriented,box --vary leaf-size=2,4 -o " +
                             dir;
    const CommandResult r = run(args);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    std::ifstream in(dir + "/results.csv");
    std::string line;
    std::getline(in, line);
    std::map<std::string, std::vector<std::string>> bySetting;  // "method setting" -> fields
    while (std::getline(in, line)) {
        std::vector<std::string> fields;
        std::stringstream row(line);
        for (std::string f; std::getline(row, f, ',');) fields.push_back(f);
        bySetting[fields[1] + " " + fields[2]] = fields;
    }
    ASSERT_EQ(bySetting.size(), 7u) << "2 + 2 + 3 settings";
    const auto cycles = [&](const std::string& run) { return std::stod(bySetting[run][5]); };
    const auto front = [&](const std::string& run) { return bySetting[run][15] == "1"; };
    const auto rmse = [&](const std::string& run) { return bySetting[run][11]; };
    // Exact methods: one image, so one error; the cheaper setting is the front.
    EXPECT_EQ(rmse("interval time-strata=0"), rmse("interval time-strata=1"));
    EXPECT_EQ(rmse("triangle-bbox bbox-bound=hull"), rmse("triangle-bbox bbox-bound=box"));
    EXPECT_LT(cycles("interval time-strata=0"), cycles("interval time-strata=1"));
    EXPECT_TRUE(front("interval time-strata=0"));
    EXPECT_FALSE(front("interval time-strata=1"));
    EXPECT_LT(cycles("triangle-bbox bbox-bound=hull"), cycles("triangle-bbox bbox-bound=oriented"));
    EXPECT_LT(cycles("triangle-bbox bbox-bound=oriented"), cycles("triangle-bbox bbox-bound=box"));
    EXPECT_TRUE(front("triangle-bbox bbox-bound=hull"));
    EXPECT_FALSE(front("triangle-bbox bbox-bound=box"));
    EXPECT_NE(front("patch leaf-size=2"), front("patch leaf-size=4"));
    int best = 0;
    std::ifstream bestCsv(dir + "/best.csv");
    for (std::getline(bestCsv, line); std::getline(bestCsv, line);) ++best;
    EXPECT_EQ(best, 3) << "one cheapest setting per method";
    EXPECT_TRUE(fs::exists(dir + "/images/motion-interval-time-strata_1-4.png"));
    EXPECT_TRUE(fs::exists(dir + "/images/motion-patch-leaf-size_2-4.png"));
    // A parameter of a method the sweep does not run, or of none, is refused before any run.
    const std::string refused = dir + "-refused";
    for (const auto& [option, message] :
         {std::pair{"--methods patch --vary time-strata=4",
                    "--vary: time-strata is a parameter of interval, which --methods does not run"},
          {"--vary warp-factor=9", "--vary: 'warp-factor' is not a method parameter"},
          {"--vary bbox-bound=hull,round", "--vary: bbox-bound: 'round' is not one of"},
          {"--vary time-strata=4 --vary time-strata=8", "--vary: varies 'time-strata' twice"},
          {"--vary edge-threshold=0.9,inf", "--vary: edge-threshold: expected a finite number"},
          {"--vary leaf-size", "--vary: expected NAME=V1,V2,..., found 'leaf-size'"},
          {"--vary time-strata=4,04", "--vary: time-strata: the list '4,04' repeats an item"},
          {"--vary edge-threshold=0.9,0.90", "--vary: edge-threshold: the list"},
          {"--vary 'leaf-size= 4,2'", "--vary: leaf-size: ' 4' has blanks"},
          {"--methods patch --vary pp-tile-size=10,20",
           "--vary: pp-tile-size is a parameter of postprocess and hybrid, none of which "
           "--methods runs"}}) {
        const CommandResult e =
            run(std::string("sweep --no-progress -o ") + refused + " " + option);
        EXPECT_EQ(e.exitCode, 2) << option << "\n" << e.output;
        EXPECT_NE(e.output.find(message), std::string::npos) << option << "\n" << e.output;
        EXPECT_FALSE(fs::exists(refused)) << option;
    }
}

TEST(Cli, RenderWithHardwareConfigAndTrace) {
    const std::string dir = patchsim::test::temporaryDirectory() + "/hw";
    const std::string hw = writeFile("slow_rs.json", R"({"clock_ghz": 1, "stages": {
        "IA": {"throughput": {"patches": 1}}, "VS": {"throughput": {"control_points": 1}},
        "HS": {"throughput": {"edge_factors": 1}}, "TS": {"throughput": {"domain_points": 1, "triangles": 1}},
        "DS": {"throughput": {"evaluations": 1, "stencil_applications": 1}},
        "RS": {"throughput": {"nodes_built": 1, "plane_tests": 1, "time_intervals": 1, "samples_tested": 1,
                              "ray_box_tests": 0.01, "ray_triangle_tests": 1, "triangle_setups": 1,
                              "edge_tests": 1, "edge_setups": 1, "lens_edge_tests": 1, "lens_edge_setups": 1}},
        "PS": {"throughput": {"invocations": 1, "post_samples": 1}}, "OM": {"throughput": {"depth_tests": 1, "transparent_fragments": 1}}}})");
    const CommandResult r =
        run("render -q -o " + dir + " --hw " + hw + " --trace " + dir + "/trace.json");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("bottleneck RS"), std::string::npos) << r.output;
    std::ifstream stats(dir + "/stats.json");
    const std::string text((std::istreambuf_iterator<char>(stats)),
                           std::istreambuf_iterator<char>());
    EXPECT_NE(text.find("\"timing\""), std::string::npos);
    EXPECT_NE(text.find("\"bottleneck\": \"RS\""), std::string::npos);
    EXPECT_TRUE(fs::exists(dir + "/trace.json"));
    const std::string bad = writeFile("bad_hw.json", R"({"stages": {}})");
    const CommandResult e = run("render -q -o " + dir + "/bad --hw " + bad);
    EXPECT_NE(e.exitCode, 0);
    EXPECT_NE(e.output.find("bad_hw.json: stages.IA: missing stage"), std::string::npos)
        << e.output;
    EXPECT_FALSE(fs::exists(dir + "/bad/image.png"));
}

// The memory system modelled (pipeline/hw/memory.json): the report and stats.json carry the
// caches and DRAM, the trace a memory track and DRAM bandwidth; a method that records no traffic
// says so; sweep refuses to charge some of its methods only.
TEST(Cli, RenderWithTheMemorySystemModelled) {
    const std::string dir = patchsim::test::temporaryDirectory() + "/memory";
    const std::string hw = sourcePath("pipeline/hw/memory.json");
    const CommandResult r = run("render -q --no-progress " + sourcePath("scenes/static.json") +
                                " -o " + dir + " --hw " + hw + " --trace " + dir + "/trace.json");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    for (const char* line :
         {"  MEM ", "    DRAM ", "memory: requested bytes by class", "  depth cache ", "  DRAM: "})
        EXPECT_NE(r.output.find(line), std::string::npos) << line << "\n" << r.output;
    const auto stats = nlohmann::json::parse(std::ifstream(dir + "/stats.json"));
    ASSERT_TRUE(stats.contains("memory")) << stats.dump(1);
    EXPECT_GT(stats["memory"]["dram_write_bytes"].get<double>(), 0);
    EXPECT_GT(stats["memory"]["requested_bytes"]["depth_writes"].get<double>(), 0);
    EXPECT_TRUE(stats["timing"].contains("memory"));
    // Energy: the stages' arithmetic and the memory system's accesses, which add up.
    const auto& energy = stats["energy"];
    EXPECT_TRUE(energy["memory_modelled"].get<bool>()) << energy.dump(1);
    EXPECT_GT(energy["memory_parts_nj"]["DRAM"].get<double>(), 0);
    EXPECT_GT(energy["stages_nj"]["RS"].get<double>(), 0);
    EXPECT_NEAR(energy["total_nj"].get<double>(),
                energy["compute_nj"].get<double>() + energy["memory_nj"].get<double>(),
                1e-9 * energy["total_nj"].get<double>());
    EXPECT_NE(r.output.find("energy: "), std::string::npos) << r.output;
    std::ifstream traceFile(dir + "/trace.json");
    const std::string trace((std::istreambuf_iterator<char>(traceFile)),
                            std::istreambuf_iterator<char>());
    EXPECT_NE(trace.find("\"DRAM bandwidth\""), std::string::npos);
    EXPECT_NE(trace.find("\"name\":\"memory\""), std::string::npos);

    const CommandResult tfragment =
        run("render -q --no-progress --method tfragment --width 96 --height 64 " +
            sourcePath("scenes/static.json") + " -o " + dir + "/tfragment --hw " + hw);
    ASSERT_EQ(tfragment.exitCode, 0) << tfragment.output;
    EXPECT_NE(tfragment.output.find("memory: not modelled for the tfragment method"),
              std::string::npos)
        << tfragment.output;

    const CommandResult sweep = run("sweep --methods patch,tfragment --spp 1 --no-progress -o " +
                                    dir + "/sweep --hw " + hw);
    EXPECT_EQ(sweep.exitCode, 2) << sweep.output;
    EXPECT_NE(sweep.output.find("memory.json: memory: sweep compares its methods on modelled "
                                "cycles, and tfragment records no memory traffic yet"),
              std::string::npos)
        << sweep.output;
    // The accumulation buffer records its traffic, but not on a transparent frame: a render says
    // so, and a sweep over a transparent scene refuses it.
    const std::string transparent = sourcePath("scenes/transparency.json");
    const CommandResult layers =
        run("render -q --no-progress --method interleaved --width 32 --height 24 --spp 2 " +
            transparent + " -o " + dir + "/layers --hw " + hw);
    ASSERT_EQ(layers.exitCode, 0) << layers.output;
    EXPECT_NE(layers.output.find("memory: not modelled for the interleaved method yet (it records "
                                 "no surface traffic on transparent frames)"),
              std::string::npos)
        << layers.output;
    const CommandResult transparentSweep =
        run("sweep " + transparent + " --methods patch,interleaved --spp 1 --no-progress -o " +
            dir + "/sweep-transparent --hw " + hw);
    EXPECT_EQ(transparentSweep.exitCode, 2) << transparentSweep.output;
    EXPECT_NE(transparentSweep.output.find(
                  "and interleaved records no memory traffic on transparent frames yet"),
              std::string::npos)
        << transparentSweep.output;
    EXPECT_FALSE(fs::exists(dir + "/sweep-transparent"));
    EXPECT_FALSE(fs::exists(dir + "/sweep"));
}

TEST(Cli, UnknownOptionIsAUsageError) {
    CommandResult r = run("info --frobnicate");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("--frobnicate"), std::string::npos) << r.output;
    r = run("--help");
    EXPECT_EQ(r.exitCode, 0) << r.output;
}

}  // namespace
