// docs/ARCHITECTURE.md against the code: the files it names exist, every source folder is in its
// table, every visibility method is named with its file, and no folder includes a header of a
// folder below it in the table's order (no arrow runs back up the house).

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>

#include "pipeline/methods/visibility_method.h"
#include "tests/test_paths.h"

namespace patchsim {
namespace {

namespace fs = std::filesystem;

std::string readText(const std::string& path) {
    std::ifstream in(path);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// The library folders, bottom floor first, as the table lists them.
const std::vector<std::string> kLayers = {"core",
                                          "tessellator",
                                          "rasterizer/common",
                                          "rasterizer/patent",
                                          "rasterizer/baselines",
                                          "rasterizer/verifier",
                                          "backend/images",
                                          "backend/shading",
                                          "backend/image_space",
                                          "backend/tfragment",
                                          "pipeline/timing",
                                          "pipeline/methods",
                                          "pipeline/driver",
                                          "pipeline/app"};

bool isSource(const fs::path& p) {
    return p.extension() == ".h" || p.extension() == ".cpp";
}

TEST(Architecture, EveryFileThePageNamesExists) {
    const std::string page = readText(test::sourcePath("docs/ARCHITECTURE.md"));
    ASSERT_FALSE(page.empty());
    // Paths such as rasterizer/patent/tile_rays or core/stage_ops.h, in the text or in code spans.
    const std::regex path(
        R"(\b((?:core|tessellator|rasterizer|backend|pipeline|tests|scripts)/[A-Za-z0-9_/.-]*[A-Za-z0-9_]))");
    int checked = 0;
    for (auto it = std::sregex_iterator(page.begin(), page.end(), path);
         it != std::sregex_iterator(); ++it) {
        const std::string name = (*it)[1];
        const std::string base = test::sourcePath(name);
        const bool exists = fs::exists(base) || fs::exists(base + ".h") ||
                            fs::exists(base + ".cpp") || fs::exists(base + ".py");
        EXPECT_TRUE(exists) << name << " is named in docs/ARCHITECTURE.md but does not exist";
        ++checked;
    }
    EXPECT_GT(checked, 60);
}

TEST(Architecture, EverySourceFolderIsInTheTable) {
    const std::string page = readText(test::sourcePath("docs/ARCHITECTURE.md"));
    for (const char* top : {"core", "tessellator", "rasterizer", "backend", "pipeline"}) {
        for (const auto& entry : fs::recursive_directory_iterator(test::sourcePath(top))) {
            if (!entry.is_directory()) continue;
            bool hasSource = false;
            for (const auto& f : fs::directory_iterator(entry.path()))
                hasSource = hasSource || isSource(f.path());
            if (!hasSource) continue;
            const std::string folder =
                fs::relative(entry.path(), test::sourcePath("")).generic_string();
            EXPECT_NE(page.find("| `" + folder + "` |"), std::string::npos)
                << folder << " holds sources but is not in docs/ARCHITECTURE.md's table";
            EXPECT_NE(std::find(kLayers.begin(), kLayers.end(), folder), kLayers.end())
                << folder << " is not in this test's layer order";
        }
    }
}

TEST(Architecture, EveryVisibilityMethodIsNamedWithItsFile) {
    const std::string page = readText(test::sourcePath("docs/ARCHITECTURE.md"));
    for (const VisibilityMethod* m : visibilityMethods()) {
        const std::regex row("\\| `" + std::string(m->name()) +
                             "` \\| `(pipeline/methods/[a-z_]+\\.cpp)` \\|");
        std::smatch match;
        ASSERT_TRUE(std::regex_search(page, match, row)) << m->name() << " has no row";
        const std::string file = readText(test::sourcePath(match[1]));
        EXPECT_NE(file.find(std::string("\"") + m->name() + "\""), std::string::npos)
            << m->name() << " is not made in " << match[1];
    }
}

// Every `#include "folder/..."` of a library folder names a folder at or above it.
TEST(Architecture, NoFolderIncludesOneBelowIt) {
    const std::regex include(R"re(#include "([a-z_]+/(?:[a-z_]+/)?)[a-z_0-9]+\.h")re");
    const auto layerOf = [](const std::string& header) {
        for (std::size_t i = kLayers.size(); i-- > 0;)
            if (header.rfind(kLayers[i] + "/", 0) == 0) return int(i);
        return -1;
    };
    int includes = 0;
    for (std::size_t layer = 0; layer < kLayers.size(); ++layer) {
        for (const auto& entry : fs::directory_iterator(test::sourcePath(kLayers[layer]))) {
            if (!isSource(entry.path())) continue;
            const std::string text = readText(entry.path().string());
            for (auto it = std::sregex_iterator(text.begin(), text.end(), include);
                 it != std::sregex_iterator(); ++it) {
                const std::string header = std::string((*it)[0]).substr(10);
                const int target = layerOf(header);
                if (target < 0) continue;  // tests/, generated files
                ++includes;
                EXPECT_LE(target, int(layer))
                    << entry.path().filename() << " (" << kLayers[layer] << ") includes " << header;
            }
        }
    }
    EXPECT_GT(includes, 300);
}

}  // namespace
}  // namespace patchsim
