// `patchsim sweep` end to end, for what a user meets beyond the happy path: runs that would share
// a name, images of an earlier sweep, a damaged converged-image cache, a memory budget exceeded by
// a late run, and an interrupt.

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <thread>

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

// A small moving torus: a sweep of it takes a fraction of a second.
std::string smallScene(const std::string& name, int width = 40) {
    return writeFile(name, R"({"film": {"width": )" + std::to_string(width) + R"(, "height": 24},
        "objects": [{"cage": ")" +
                               sourcePath("scenes/cages/catmark_torus.obj") +
                               R"(", "open": {"rotate_degrees": [60, 0, 0]},
                     "close": {"translate": [0.6, 0, 0]}}]})");
}

std::string freshFolder(const std::string& name) {
    const std::string dir = patchsim::test::temporaryDirectory() + "/" + name;
    fs::remove_all(dir);
    return dir;
}

std::vector<std::string> csvColumn(const std::string& csv, int column) {
    std::vector<std::string> values;
    std::istringstream in(csv);
    std::string line;
    std::getline(in, line);
    while (std::getline(in, line)) {
        std::istringstream fields(line);
        std::string field;
        for (int i = 0; i <= column; ++i) std::getline(fields, field, ',');
        values.push_back(field);
    }
    return values;
}

// With the memory system modelled, every row is charged its own traffic: the CSV's last column,
// DRAM bytes, is filled for each method.
// With DRAM banks (memory_gddr3.json) each row also has its row-hit rate; without them the
// column is empty.
TEST(CliSweep, WithMemoryModelledEveryRowHasItsDramBytes) {
    for (const bool banks : {false, true}) {
        const std::string dir = freshFolder(banks ? "memory-banks" : "memory");
        const CommandResult r =
            run("sweep " + smallScene("memory.json") +
                " --methods patch,triangle-bbox,interval --spp 1 --repeats 1 --no-progress --hw " +
                sourcePath(banks ? "pipeline/hw/memory_gddr3.json" : "pipeline/hw/memory.json") +
                " -o " + dir);
        ASSERT_EQ(r.exitCode, 0) << r.output;
        const std::string csv = readFile(dir + "/results.csv");
        EXPECT_NE(csv.find(",front,dram_bytes,dram_row_hit_rate,energy_nj\n"), std::string::npos)
            << csv;
        EXPECT_EQ(csvColumn(csv, 1),
                  (std::vector<std::string>{"patch", "triangle-bbox", "interval"}));
        for (const std::string& bytes : csvColumn(csv, 16)) EXPECT_GT(std::stod(bytes), 0) << csv;
        for (const std::string& rate : csvColumn(csv, 17)) {
            if (!banks) {
                EXPECT_EQ(rate, "") << csv;
                continue;
            }
            EXPECT_GT(std::stod(rate), 0) << csv;
            EXPECT_LE(std::stod(rate), 1) << csv;
        }
        // Each method's energy, its DRAM bytes priced among the rest, over 8 bytes at 1.95 nJ.
        const std::vector<std::string> bytes = csvColumn(csv, 16), energy = csvColumn(csv, 18);
        ASSERT_EQ(energy.size(), bytes.size());
        for (std::size_t k = 0; k < energy.size(); ++k)
            EXPECT_GT(std::stod(energy[k]), std::stod(bytes[k]) / 8 * 1.95) << csv;
    }
}

TEST(CliSweep, ScenesOfTheSameNameGetTheirOwnRuns) {
    const std::string tmp = patchsim::test::temporaryDirectory();
    fs::create_directories(tmp + "/a");
    fs::create_directories(tmp + "/b");
    const std::string a = smallScene("a/scene.json"), b = smallScene("b/scene.json", 48);
    const std::string dir = freshFolder("same-name");
    const CommandResult r = run("sweep " + a + " " + b +
                                " --methods patch --spp 1 --repeats 1 --no-progress -o " + dir);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(csvColumn(readFile(dir + "/results.csv"), 0),
              (std::vector<std::string>{"a-scene", "b-scene"}));
    for (const char* image : {"a-scene-patch-1.png", "b-scene-patch-1.png", "a-scene-converged.png",
                              "b-scene-converged.png"})
        EXPECT_TRUE(fs::exists(dir + "/images/" + image)) << image;
}

TEST(CliSweep, ImagesOfAnEarlierSweepAreRemoved) {
    const std::string scene = smallScene("stale.json");
    const std::string dir = freshFolder("stale");
    const std::string args = "sweep " + scene +
                             " --methods patch,interval --repeats 1 "
                             "--no-progress --converged-spp 16 -o " +
                             dir;
    ASSERT_EQ(run(args + " --spp 1,2").exitCode, 0);
    EXPECT_EQ(listTree(dir + "/images").size(), 5u);
    std::ofstream(dir + "/images/notes.txt") << "the user's own file";
    const CommandResult r = run(args + " --spp 1");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("removed 2 images of an earlier sweep"), std::string::npos) << r.output;
    EXPECT_EQ(listTree(dir + "/images"),
              (std::vector<std::string>{"notes.txt", "stale-converged.png", "stale-interval-1.png",
                                        "stale-patch-1.png"}));
}

// A damaged cache entry is rendered again, and the runs' errors are those against a whole image.
TEST(CliSweep, DamagedConvergedImagesAreRenderedAgain) {
    const std::string scene = smallScene("cache.json");
    const std::string dir = freshFolder("cache");
    const std::string args = "sweep " + scene +
                             " --methods interval --spp 1 --repeats 1 "
                             "--no-progress --converged-spp 16 -o " +
                             dir;
    ASSERT_EQ(run(args).exitCode, 0);
    const std::string rmse = csvColumn(readFile(dir + "/results.csv"), 10).at(0);
    std::string exr;
    for (const auto& entry : fs::directory_iterator(dir + "/converged"))
        if (entry.path().extension() == ".exr") exr = entry.path().string();
    ASSERT_FALSE(exr.empty());
    CommandResult r = run(args);
    EXPECT_NE(r.output.find("reused from"), std::string::npos) << r.output;
    fs::resize_file(exr, fs::file_size(exr) / 2);
    r = run(args);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("rendered into"), std::string::npos) << r.output;
    // OpenImageIO reads some truncated files without an error (the missing pixels zero): the
    // recorded hash of the pixels finds those.
    EXPECT_TRUE(r.output.find("the cached image did not read back") != std::string::npos ||
                r.output.find("pixels do not match their recorded hash") != std::string::npos)
        << r.output;
    EXPECT_EQ(csvColumn(readFile(dir + "/results.csv"), 10).at(0), rmse);
    // An image of another size where this one should be.
    const std::string other = freshFolder("cache-other");
    ASSERT_EQ(
        run("sweep " + smallScene("cache.json", 32) +
            " --methods interval --spp 1 --repeats 1 --no-progress --converged-spp 16 -o " + other)
            .exitCode,
        0);
    smallScene("cache.json");  // back to 40 pixels wide
    for (const auto& entry : fs::directory_iterator(other + "/converged"))
        if (entry.path().extension() == ".exr")
            fs::copy_file(entry.path(), exr, fs::copy_options::overwrite_existing);
    r = run(args);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("the cached image is 32x24, not 40x24"), std::string::npos) << r.output;
    // Pixels edited in place, the file still whole.
    r = run(args);
    EXPECT_NE(r.output.find("reused from"), std::string::npos) << r.output;
    std::fstream edit(exr, std::ios::in | std::ios::out | std::ios::binary);
    edit.seekp(std::streamoff(fs::file_size(exr) - 64));
    edit.write("\x7f\x7f\x7f\x7f", 4);
    edit.close();
    r = run(args);
    EXPECT_NE(r.output.find("rendered into"), std::string::npos) << r.output;
    EXPECT_EQ(csvColumn(readFile(dir + "/results.csv"), 10).at(0), rmse);
}

// Labels name files and CSV fields: never two runs with one name, never a comma in a field.
TEST(CliSweep, RunLabelsNeverCollide) {
    const std::string tmp = patchsim::test::temporaryDirectory();
    fs::create_directories(tmp + "/labels");
    const std::string a = smallScene("labels/motion.json"),
                      b = smallScene("labels/motion-blur2.json"), c = smallScene("labels/x,y.json");
    fs::copy_file(sourcePath("scenes/cages/catmark_torus.obj"), tmp + "/labels/motion.obj",
                  fs::copy_options::overwrite_existing);
    const std::string dir = freshFolder("labels-out");
    const CommandResult r = run("sweep " + a + " " + b + " " + c + " " + tmp +
                                "/labels/motion.obj --methods patch --spp 1 --blur 1,2 "
                                "--repeats 1 --no-progress --converged-spp 2 -o " +
                                dir);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const std::vector<std::string> labels = csvColumn(readFile(dir + "/results.csv"), 0);
    EXPECT_EQ(labels, (std::vector<std::string>{"motion", "motion-blur2", "motion-blur2-2",
                                                "motion-blur2-blur2", "x_y", "x_y-blur2",
                                                "motion-2", "motion-blur2-3"}));
    EXPECT_EQ(listTree(dir + "/images").size(), 2 * labels.size());
}

// `patchsim ARGUMENTS`, killed after two minutes (exit code 124) so a hang fails the test.
CommandResult runWithin(const std::string& arguments) {
    CommandResult result{-1, {}};
    FILE* pipe = popen(
        ("timeout 120 " + std::string(PATCHSIM_BINARY) + " " + arguments + " 2>&1").c_str(), "r");
    if (!pipe) return result;
    char buffer[4096];
    for (std::size_t n; (n = fread(buffer, 1, sizeof buffer, pipe)) > 0;)
        result.output.append(buffer, n);
    const int status = pclose(pipe);
    result.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return result;
}

// A cache entry that is not a regular file (a FIFO, a link to /dev/zero) is never read: reading
// it would wait or run forever. It is rendered again, and the cache's errors name the sweep's
// -o.
TEST(CliSweep, ConvergedCacheEntriesThatAreNotFilesAreRenderedAgain) {
    const std::string scene = smallScene("special.json");
    const std::string dir = freshFolder("special");
    const std::string args = "sweep " + scene +
                             " --methods interval --spp 1 --repeats 1 "
                             "--no-progress --converged-spp 16 -o " +
                             dir;
    ASSERT_EQ(run(args).exitCode, 0);
    const std::string rmse = csvColumn(readFile(dir + "/results.csv"), 10).at(0);
    std::string base;
    for (const auto& entry : fs::directory_iterator(dir + "/converged"))
        if (entry.path().extension() == ".exr")
            base = fs::path(entry.path()).replace_extension().string();
    ASSERT_FALSE(base.empty());
    const auto fifo = [](const std::string& path) {
        fs::remove(path);
        ASSERT_EQ(mkfifo(path.c_str(), 0600), 0) << path;
    };
    const auto toZero = [](const std::string& path) {
        fs::remove(path);
        fs::create_symlink("/dev/zero", path);
    };
    for (const auto& [make, extension] :
         std::vector<std::pair<std::function<void(const std::string&)>, std::string>>{
             {fifo, ".exr"}, {toZero, ".exr"}, {fifo, ".key"}, {toZero, ".key"}}) {
        make(base + extension);
        const CommandResult r = runWithin(args);
        ASSERT_EQ(r.exitCode, 0) << extension << "\n" << r.output;
        EXPECT_NE(r.output.find("rendered into"), std::string::npos) << r.output;
        EXPECT_NE(r.output.find("the cached '" + base + extension + "' is not a regular file"),
                  std::string::npos)
            << r.output;
        EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(base + extension))) << extension;
        EXPECT_EQ(csvColumn(readFile(dir + "/results.csv"), 10).at(0), rmse);
    }
    // The cache folder is made in -o: a file in its place is refused under that option.
    const std::string blocked = freshFolder("special-blocked");
    fs::create_directories(blocked);
    std::ofstream(blocked + "/converged") << "not a folder";
    const CommandResult r = run("sweep " + scene +
                                " --methods interval --spp 1 --repeats 1 --no-progress "
                                "--converged-spp 16 -o " +
                                blocked);
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find(blocked + "/converged: -o: is a file, not a folder for the outputs"),
              std::string::npos)
        << r.output;
}

// The scene's own film.spp is not what a sweep renders; every --spp is checked before any run.
TEST(CliSweep, EveryRunIsCheckedAgainstTheMemoryBudgetFirst) {
    const std::string scene = writeFile("budget.json", R"({"film": {"width": 256, "height": 256,
        "spp": 4096}, "objects": [{"cage": ")" + sourcePath("scenes/cages/catmark_torus.obj") +
                                                           R"("}]})");
    const std::string dir = freshFolder("budget");
    CommandResult r = run("sweep " + scene +
                          " --methods patch --spp 1 --repeats 1 --no-progress "
                          "--converged-spp 4 --memory-budget-mib 64 -o " +
                          dir);
    EXPECT_EQ(r.exitCode, 0) << "film.spp 4096 is not swept\n" << r.output;
    const std::string late = freshFolder("budget-late");
    r = run("sweep " + scene +
            " --methods patch --spp 1,256 --repeats 1 --no-progress "
            "--memory-budget-mib 64 -o " +
            late);
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("budget: --spp: film of 256x256 at 256 spp needs 512 MiB"),
              std::string::npos)
        << r.output;
    EXPECT_FALSE(fs::exists(late)) << "work began before the over-budget run was found";
}

TEST(CliSweep, ConvergedSamplesBelowTheRunsAreWarnedOf) {
    const std::string dir = freshFolder("low-converged");
    const CommandResult r = run("sweep " + smallScene("low.json") +
                                " --methods patch --spp 1,8 --repeats 1 --no-progress "
                                "--converged-spp 4 -o " +
                                dir);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("warning: --converged-spp 4 is below the largest --spp 8"),
              std::string::npos)
        << r.output;
}

// Plots of scenes an earlier sweep had are removed with the earlier images; other files stay.
TEST(CliSweep, PlotsOfAnEarlierSweepAreRemoved) {
    if (std::system("/usr/bin/python3 -c 'import matplotlib' > /dev/null 2>&1") != 0)
        GTEST_SKIP() << "no matplotlib";
    const std::string dir = freshFolder("stale-plots");
    const std::string args =
        " --methods patch --spp 1 --repeats 1 --no-progress --converged-spp 2 -o " + dir;
    ASSERT_EQ(run("sweep " + smallScene("first.json") + args).exitCode, 0);
    ASSERT_TRUE(fs::exists(dir + "/plots/first.png"));
    std::ofstream(dir + "/plots/mine.png") << "the user's own";
    const CommandResult r = run("sweep " + smallScene("second.json") + args);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_FALSE(fs::exists(dir + "/plots/first.png"));
    EXPECT_FALSE(fs::exists(dir + "/plots/first.svg"));
    EXPECT_TRUE(fs::exists(dir + "/plots/second.png"));
    EXPECT_TRUE(fs::exists(dir + "/plots/mine.png"));
}

// Ctrl-C in the middle of a sweep: no hidden temporaries, no empty folders.
TEST(CliSweep, AnInterruptLeavesNoTemporaries) {
    const std::string dir = freshFolder("interrupted");
    const std::string command = "exec " + std::string(PATCHSIM_BINARY) + " sweep " +
                                sourcePath("scenes/motion.json") +
                                " --methods patch,interval,triangle-bbox --spp 1,2,4,8 "
                                "--repeats 3 --no-progress --converged-spp 8 -o " +
                                dir + " > /dev/null 2>&1";
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char*>(nullptr));
        _exit(127);
    }
    // Wait for the first run's image: the temporaries of the sweep exist from then on.
    bool midway = false;
    for (int i = 0; i < 600 && !midway; ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
        for (const std::string& entry : listTree(dir))
            midway = midway || entry.find(".tmp-patchsim") != std::string::npos;
    }
    ASSERT_TRUE(midway) << "the sweep never wrote a temporary";
    kill(child, SIGINT);
    int status = 0;
    waitpid(child, &status, 0);
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGINT) << "status " << status;
    for (const std::string& entry : listTree(dir)) {
        EXPECT_EQ(entry.find(".tmp-patchsim"), std::string::npos) << entry;
        if (fs::is_directory(dir + "/" + entry)) {
            EXPECT_FALSE(fs::is_empty(dir + "/" + entry)) << "empty folder " << entry;
        }
    }
}

}  // namespace
