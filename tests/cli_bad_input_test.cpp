// Bad input on the command line, end to end: every refusal is one line naming the option, exit
// code 2, and nothing written anywhere (not in the folder the command ran in, not in /).

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "tests/cli_runner.h"
#include "tests/test_paths.h"

namespace {

namespace fs = std::filesystem;
using patchsim::test::CommandResult;
using patchsim::test::listTree;
using patchsim::test::readFile;
using patchsim::test::run;
using patchsim::test::sourcePath;
using patchsim::test::writeFile;

// A fresh, empty folder to run a command in.
std::string emptyFolder(const std::string& name) {
    const std::string dir = patchsim::test::temporaryDirectory() + "/" + name;
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

std::size_t lines(const std::string& text) {
    return std::size_t(std::count(text.begin(), text.end(), '\n'));
}

// Refused with exit 2 and one line holding `message`; the folder it ran in stays empty.
void expectRefused(const std::string& args, const std::string& message) {
    const std::string cwd = emptyFolder("cwd");
    const CommandResult r = run(args, cwd);
    EXPECT_EQ(r.exitCode, 2) << args << "\n" << r.output;
    EXPECT_NE(r.output.find(message), std::string::npos) << args << "\n" << r.output;
    EXPECT_EQ(lines(r.output), 1u) << args << "\n" << r.output;
    EXPECT_EQ(r.output.rfind("patchsim: error: ", 0), 0u) << r.output;
    EXPECT_TRUE(listTree(cwd).empty()) << args << " wrote into the folder it ran in";
}

// A render or sweep that could not write its pictures is refused before its work.
TEST(CliBadInput, AMissingImageModuleIsRefusedBeforeTheWork) {
    const std::string missing = patchsim::test::temporaryDirectory() + "/no-such-module.so";
    setenv("PATCHSIM_IMAGE_IO_MODULE", missing.c_str(), 1);
    const std::string refusal = missing + ": patchsim's image module (OpenImageIO) is missing";
    expectRefused("render --no-progress -q -o out", refusal);
    expectRefused("sweep --methods patch --spp 1 --no-progress -o out", refusal);
    unsetenv("PATCHSIM_IMAGE_IO_MODULE");
}

TEST(CliBadInput, EmptyPathsAreRefusedNotTakenForAFolder) {
    const std::string scene = sourcePath("scenes/static.json") + " --no-progress";
    const std::string grid = writeFile("grid.json", R"({"rasterizer": {"tile_size": [8]},
        "film": {"width": 8, "height": 8, "spp": 1}})");
    expectRefused("render " + scene + " -o ''", "command line: --output: empty folder name");
    expectRefused("render " + scene + " -o out --trace ''", "--trace: empty output file name");
    expectRefused("render " + scene + " -o out --hw ''", "--hw: empty file name");
    expectRefused("render '' -o out", "command line: scene: empty file name");
    expectRefused("sweep " + scene + " --methods patch --spp 1 -o ''",
                  "--output: empty folder name");
    const std::string cage = sourcePath("scenes/static.json");
    expectRefused("tessellate " + cage + " -o ''", "--output: empty output file name");
    expectRefused("tessellate " + cage + " -o x.obj --stats ''", "--stats: empty output file");
    expectRefused("explore " + scene + " --grid " + grid + " -o ''", "--output: empty output");
    expectRefused("explore " + scene + " --grid ''", "--grid: empty file name");
    expectRefused("explore " + scene + " --grid " + grid + " -o x.csv --plots ''",
                  "--plots: empty folder name");
    expectRefused("verify-tiles --replay ''", "--replay: empty value");
    expectRefused("verify-tiles --cases 10 --csv ''", "--csv: empty output file name");
    expectRefused("verify-tiles --cases 10 --summary ''", "--summary: empty output file name");
    expectRefused("verify-tiles --cases 10 --format fp8", "--format: 'fp8' is not a reduced");
    expectRefused("verify-tiles --cases 10 --format fp16,fixed1.4", "--format: 'fixed1.4' is not");
    expectRefused("verify-tiles --cases 10 --format fp32", "--format: 'fp32' is not a reduced");
    expectRefused("verify-tiles --cases 10 --format fp16,", "--format: '' is not a reduced");
    expectRefused("verify-tiles --cases 10 --family near", "--family: 'near' is not a case family");
    expectRefused("verify-tiles --family '' --replay lens:3", "--family: empty value");
    expectRefused("info ''", "scene: empty file name");
}

TEST(CliBadInput, NonFiniteNumbersAreRefused) {
    const std::string render = "render -q --no-progress -o out --method postprocess ";
    for (const char* value : {"nan", "-nan", "inf", "-inf"}) {
        expectRefused(render + "--soft-z-extent " + value,
                      std::string("--soft-z-extent: expected a finite number in [1e-06, 1000000], "
                                  "found '") +
                          value + "'");
        expectRefused(render + "--edge-threshold " + value, "--edge-threshold: expected a finite");
        expectRefused(std::string("tessellate -o x.obj --time ") + value,
                      "--time: expected a finite number in [0, 1]");
        expectRefused(std::string("sweep --spp 1 --blur 1,") + value, "--blur: expected a finite");
    }
}

TEST(CliBadInput, MalformedListsNameTheOption) {
    const std::string sweep = "sweep --no-progress -o out ";
    expectRefused(sweep + "--spp 1,,4", "--spp: empty item in the list '1,,4'");
    expectRefused(sweep + "--spp 1,4,", "--spp: empty item in the list '1,4,'");
    expectRefused(sweep + "--spp ''", "--spp: needs at least one value");
    expectRefused(sweep + "--spp 4,4", "--spp: the list '4,4' repeats an item");
    expectRefused(sweep + "--methods patch,,interval", "--methods: empty item");
    expectRefused(sweep + "--methods patch,patch", "--methods: the list 'patch,patch' repeats");
    expectRefused(sweep + "--blur 1,,2", "--blur: empty item");
    expectRefused(sweep + "--blur 2,2.0", "--blur: the list '2,2.0' repeats");
    const std::string scene = sourcePath("scenes/static.json");
    expectRefused(sweep + scene + " " + scene, "scenes: names '" + scene + "' twice");
    const std::string grid = writeFile("repeats.json", R"({"rasterizer": {"tile_size": [8, 8]},
        "film": {"width": 8, "height": 8, "spp": 1}})");
    expectRefused("explore --no-progress " + scene + " --grid " + grid + " -o x.csv",
                  "rasterizer.tile_size[1]: the value 8 repeats rasterizer.tile_size[0]");
    const std::string once = writeFile("once.json", R"({"rasterizer": {"tile_size": [8]},
        "film": {"width": 8, "height": 8, "spp": 1}})");
    expectRefused("explore --no-progress " + scene + " " + scene + " --grid " + once + " -o x.csv",
                  "command line: scenes: names '" + scene + "' twice");
}

// A cage at the coordinate cap scaled past the float range: refused by every command that
// builds the scene, naming the object, instead of writing NaN vertices or dropping the geometry.
TEST(CliBadInput, GeometryBeyondTheFloatRangeIsRefused) {
    writeFile("far_quad.obj", "v 1e30 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 4 3\n");
    const std::string scene =
        writeFile("far_quad.json",
                  R"({"objects": [{"cage": "far_quad.obj", "open": {"scale": [1e30, 1, 1]}}]})");
    const std::string message = scene + ": objects[0]: vertex 1 of";
    expectRefused("tessellate " + scene + " -o hu.obj", message);
    expectRefused("render " + scene + " -q --no-progress -o out", message);
}

// CLI11's own errors (an unknown option, a missing required one, an extra argument) are one
// line in the project's format too.
TEST(CliBadInput, ParserErrorsAreOneLine) {
    expectRefused("info --frobnicate", "--frobnicate");
    expectRefused("explore", "--grid");
    expectRefused("render a.json b.json", "b.json");
    expectRefused("render --method", "--method");
    expectRefused("render --pp-samples 4", "--pp-samples: 4 is even; it must be odd");
}

TEST(CliBadInput, SubcommandHelpHasItsOwnFooter) {
    CommandResult r = run("render --help");
    EXPECT_EQ(r.exitCode, 0);
    EXPECT_EQ(r.output.find("With no subcommand"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("--soft-z-extent"), std::string::npos) << r.output;
    r = run("--help");
    EXPECT_NE(r.output.find("With no subcommand"), std::string::npos) << r.output;
}

TEST(CliBadInput, HeatMapsNeedAMethodThatCountsPerPixel) {
    expectRefused("render -q --no-progress -o out --heatmaps --method reference",
                  "--heatmaps: the reference method does not count its work per pixel");
    expectRefused("render -q --no-progress -o out --heatmaps --method tfragment",
                  "--heatmaps: the tfragment method");
}

// Commands that do not split their work over ranks would each run it whole, racing on the same
// files: refused under mpirun, with one message.
TEST(CliBadInput, CommandsThatDoNotSplitAreRefusedUnderMpi) {
    if (std::system("command -v mpirun > /dev/null 2>&1") != 0) GTEST_SKIP() << "no mpirun";
    const std::string mpi =
        "ASAN_OPTIONS=detect_leaks=0 OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 "
        "timeout 120 mpirun -np 2 --oversubscribe -x ASAN_OPTIONS " +
        std::string(PATCHSIM_BINARY) + " ";
    const std::string cwd = emptyFolder("mpi-cwd");
    for (const std::string& args :
         {std::string("sweep --methods patch --spp 1 -o sweep"), std::string("tessellate -o t.obj"),
          std::string("verify-tiles --cases 10 --csv c.csv")}) {
        const std::string log = patchsim::test::temporaryDirectory() + "/mpi.log";
        const int status =
            std::system(("cd " + cwd + " && " + mpi + args + " > " + log + " 2>&1").c_str());
        ASSERT_TRUE(WIFEXITED(status));
        EXPECT_EQ(WEXITSTATUS(status), 2) << args << "\n" << readFile(log);
        const std::string out = readFile(log);
        EXPECT_NE(out.find("does not run under mpirun (2 ranks)"), std::string::npos) << out;
        EXPECT_EQ(out.find("does not run"), out.rfind("does not run")) << "said twice:\n" << out;
        EXPECT_TRUE(listTree(cwd).empty()) << args;
    }
}

TEST(CliBadInput, RenderTakesFilmOverrides) {
    const std::string dir = patchsim::test::temporaryDirectory() + "/film-overrides";
    const CommandResult r = run("render -q --no-progress --spp 2 --width 40 --height 30 -o " + dir);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const std::string stats = readFile(dir + "/stats.json");
    EXPECT_NE(stats.find("\"width\": \"40\""), std::string::npos) << stats;
    EXPECT_NE(stats.find("\"height\": \"30\""), std::string::npos) << stats;
    EXPECT_NE(stats.find("\"spp\": \"2\""), std::string::npos) << stats;
    // Every option of the job and of the rasterizer, from the tables.
    EXPECT_NE(stats.find("\"soft_z_extent\": \"0.05\""), std::string::npos) << stats;
    EXPECT_NE(stats.find("\"rasterizer.interior_time_refinement\": \"true\""), std::string::npos);
    EXPECT_NE(stats.find("\"rasterizer.max_triangles_per_group\": \"0\""), std::string::npos);
    expectRefused("render -q --no-progress -o out --spp 4096 --width 16384 --height 16384",
                  "command line: --spp: film of 16384x16384 at 4096 spp needs");
}

// "--trace=" would have CLI11 take the next argument as the file; an empty argument where none
// belongs is named as such; a name of blanks is no name.
TEST(CliBadInput, EmptyAssignmentsAndArgumentsAreRefused) {
    const std::string scene = sourcePath("scenes/static.json");
    expectRefused("render " + scene + " --trace= -q -o out", "command line: --trace: empty value");
    expectRefused("tessellate " + scene + " --stats= -q", "command line: --stats: empty value");
    expectRefused("''", "command line: an argument nothing takes: ''");
    expectRefused("render " + scene + " -o ' '", "--output: empty folder name");
    expectRefused("tessellate " + scene + " -o '  '", "--output: empty output file name");
}

// One output must not overwrite another, nor a file the command reads.
TEST(CliBadInput, NoOutputOverwritesAnInputOrAnotherOutput) {
    const std::string cwd = emptyFolder("overwrite");
    const std::string scene = cwd + "/scene.json", grid = cwd + "/grid.json";
    std::ofstream(scene) << R"({"film": {"width": 16, "height": 12, "spp": 1},
        "objects": [{"cage": ")"
                         << sourcePath("scenes/cages/catmark_torus.obj") << R"("}]})";
    std::ofstream(grid) << R"({"rasterizer": {"tile_size": [8]}})";
    const auto refused = [&](const std::string& args, const std::string& message) {
        const CommandResult r = run(args, cwd);
        EXPECT_EQ(r.exitCode, 2) << args << "\n" << r.output;
        EXPECT_NE(r.output.find(message), std::string::npos) << args << "\n" << r.output;
        EXPECT_EQ(listTree(cwd), (std::vector<std::string>{"grid.json", "scene.json"})) << args;
    };
    refused("tessellate scene.json -o same.obj --stats same.obj",
            "same.obj: --stats: is written as -o too");
    refused("render scene.json -q --no-progress -o out --trace out/stats.json",
            "out/stats.json: --trace: is written as -o too");
    refused("render scene.json -q --no-progress -o out --trace ./scene.json",
            "./scene.json: --trace: is the file scene names, which is read");
    refused("tessellate scene.json -o scene.json", "scene.json: -o: is the file scene names");
    refused("explore scene.json --grid grid.json -o grid.json --no-progress",
            "grid.json: -o: is the file --grid names, which is read");
    refused("verify-tiles --cases 10 --csv a.csv --summary a.csv",
            "a.csv: --csv: is written as --summary too");
}

// Under mpirun every rank reads the same command line and inputs: an error in them is said once.
TEST(CliBadInput, AnErrorUnderMpiIsSaidOnce) {
    if (std::system("command -v mpirun > /dev/null 2>&1") != 0) GTEST_SKIP() << "no mpirun";
    const std::string cwd = emptyFolder("mpi-once");
    const std::string mpi =
        "ASAN_OPTIONS=detect_leaks=0 OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 "
        "timeout 120 mpirun -np 2 --oversubscribe -x ASAN_OPTIONS " +
        std::string(PATCHSIM_BINARY) + " ";
    for (const std::string& args :
         {std::string("render --spp nan -o out"), std::string("render /nonexistent.json -o out"),
          std::string("explore --grid /nonexistent.json -o x.csv")}) {
        const std::string log = patchsim::test::temporaryDirectory() + "/mpi-once.log";
        const int status =
            std::system(("cd " + cwd + " && " + mpi + args + " > " + log + " 2>&1").c_str());
        ASSERT_TRUE(WIFEXITED(status));
        EXPECT_EQ(WEXITSTATUS(status), 2) << args;
        const std::string out = readFile(log);
        const std::size_t first = out.find("patchsim: error: ");
        EXPECT_NE(first, std::string::npos) << args << "\n" << out;
        EXPECT_EQ(out.find("patchsim: error: ", first + 1), std::string::npos)
            << "said twice: " << args << "\n"
            << out;
        EXPECT_TRUE(listTree(cwd).empty()) << args;
    }
}

}  // namespace
