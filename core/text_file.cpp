#include "core/text_file.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.h"

namespace patchsim {

std::string readTextFile(const std::string& path, const std::string& referringFile,
                         const std::string& field) {
    if (path.starts_with(kBuiltinPrefix)) {
        if (auto asset = builtinAsset(std::string_view(path).substr(kBuiltinPrefix.size())))
            return std::string(*asset);
        throw InputError(referringFile.empty() ? path : referringFile, field,
                         "no built-in asset named '" + path + "'");
    }
    std::error_code ec;
    const std::string& blame = referringFile.empty() ? path : referringFile;
    if (std::filesystem::is_directory(path, ec))
        throw InputError(blame, field, "'" + path + "' is a directory, not a file");
    // Devices, pipes and sockets (e.g. /dev/zero) are not input files; nor is a missing one.
    if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec))
        throw InputError(blame, field, "'" + path + "' is not a regular file");
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        throw InputError(blame, field, "cannot open '" + path + "'");
    }
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

std::string parentDirectory(const std::string& path) {
    return std::filesystem::path(path).parent_path().string();
}

std::string joinPath(const std::string& dir, const std::string& relative) {
    if (relative.starts_with(kBuiltinPrefix)) return relative;
    if (dir.starts_with(kBuiltinPrefix)) return dir + relative;
    const std::filesystem::path rel(relative);
    if (rel.is_absolute() || dir.empty()) return rel.lexically_normal().string();
    return (std::filesystem::path(dir) / rel).lexically_normal().string();
}

}  // namespace patchsim
