// docs/ARCHITECTURE.md against the code: the files it names exist, every source folder is in its
// table, every visibility method is named with its file, and no folder includes a header of a
// folder below it in the table's order (no arrow runs back up the house).

#include <gtest/gtest.h>

#include <cctype>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <vector>

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

// std::regex is avoided: GCC 12 warns inside its own <regex> under the sanitizer build.
bool isPathChar(char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '/' || c == '.' ||
           c == '-';
}

// Paths such as rasterizer/patent/tile_rays or core/stage_ops.h, in the text or in code spans.
std::vector<std::string> sourcePathsNamedIn(const std::string& page) {
    std::vector<std::string> paths;
    for (const char* top :
         {"core/", "tessellator/", "rasterizer/", "backend/", "pipeline/", "tests/", "scripts/"}) {
        for (std::size_t at = page.find(top); at != std::string::npos;
             at = page.find(top, at + 1)) {
            if (at > 0 && isPathChar(page[at - 1])) continue;  // inside a longer word or path
            std::size_t end = at;
            while (end < page.size() && isPathChar(page[end])) ++end;
            while (end > at && !std::isalnum(static_cast<unsigned char>(page[end - 1])) &&
                   page[end - 1] != '_')
                --end;
            if (end > at + std::strlen(top)) paths.push_back(page.substr(at, end - at));
        }
    }
    return paths;
}

// The text after PREFIX up to the next CLOSE, or "" when PREFIX is absent.
std::string textAfter(const std::string& text, const std::string& prefix, char close,
                      std::size_t from = 0) {
    const std::size_t at = text.find(prefix, from);
    if (at == std::string::npos) return {};
    const std::size_t begin = at + prefix.size(), end = text.find(close, begin);
    return end == std::string::npos ? std::string() : text.substr(begin, end - begin);
}

// The headers named by the file's `#include "..."` lines.
std::vector<std::string> quotedIncludes(const std::string& text) {
    std::vector<std::string> headers;
    const std::string directive = "#include \"";
    for (std::size_t at = text.find(directive); at != std::string::npos;
         at = text.find(directive, at + 1))
        if (at == 0 || text[at - 1] == '\n') headers.push_back(textAfter(text, directive, '"', at));
    return headers;
}

bool isSource(const fs::path& p) {
    return p.extension() == ".h" || p.extension() == ".cpp";
}

TEST(Architecture, EveryFileThePageNamesExists) {
    const std::string page = readText(test::sourcePath("docs/ARCHITECTURE.md"));
    ASSERT_FALSE(page.empty());
    int checked = 0;
    for (const std::string& name : sourcePathsNamedIn(page)) {
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
        const std::string fileName = textAfter(page, "| `" + std::string(m->name()) + "` | `", '`');
        ASSERT_EQ(fileName.rfind("pipeline/methods/", 0), 0u) << m->name() << " has no row";
        const std::string file = readText(test::sourcePath(fileName));
        EXPECT_NE(file.find(std::string("\"") + m->name() + "\""), std::string::npos)
            << m->name() << " is not made in " << fileName;
    }
}

// Every `#include "folder/..."` of a library folder names a folder at or above it.
TEST(Architecture, NoFolderIncludesOneBelowIt) {
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
            for (const std::string& header : quotedIncludes(text)) {
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
