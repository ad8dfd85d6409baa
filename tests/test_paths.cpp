#include "tests/test_paths.h"

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <stdexcept>

namespace patchsim::test {

namespace fs = std::filesystem;

std::string sourcePath(const std::string& relative) {
    return (fs::path(PATCHSIM_SOURCE_DIR) / relative).string();
}

std::string regressionCagesDir() {
    return sourcePath("tests/data/opensubdiv");
}

static std::vector<std::string> filesWithExtension(const std::string& dir, const std::string& ext) {
    std::vector<std::string> files;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(dir, ec))
        if (entry.path().extension() == ext) files.push_back(entry.path().string());
    std::sort(files.begin(), files.end());
    return files;
}

std::vector<std::string> regressionCageFiles() {
    // The 41 shapes copied into the repository (tests/data/opensubdiv/README.md).
    constexpr std::size_t kShipped = 41;
    std::vector<std::string> files = filesWithExtension(regressionCagesDir(), ".obj");
    if (files.size() < kShipped)
        throw std::runtime_error("the regression cages are missing: " + regressionCagesDir() +
                                 " holds " + std::to_string(files.size()) + " .obj files, not " +
                                 std::to_string(kShipped));
    return files;
}
std::vector<std::string> sceneFiles() {
    return filesWithExtension(sourcePath("scenes"), ".json");
}

std::string temporaryDirectory() {
    const fs::path dir =
        fs::temp_directory_path() / ("patchsim-test-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    return dir.string();
}

}  // namespace patchsim::test
