#include "tests/cli_runner.h"

#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "tests/test_paths.h"

namespace patchsim::test {

CommandResult run(const std::string& arguments, const std::string& folder) {
    std::string command = std::string(PATCHSIM_BINARY) + " " + arguments + " 2>&1";
    if (!folder.empty()) command = "cd '" + folder + "' && " + command;
    FILE* pipe = popen(command.c_str(), "r");
    CommandResult result{-1, {}};
    if (!pipe) return result;
    std::array<char, 4096> buffer;
    std::size_t n;
    while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0)
        result.output.append(buffer.data(), n);
    const int status = pclose(pipe);
    result.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return result;
}

std::string writeFile(const std::string& name, const std::string& text) {
    const std::string path = temporaryDirectory() + "/" + name;
    std::ofstream(path) << text;
    return path;
}

std::string readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

std::vector<std::string> listTree(const std::string& folder) {
    namespace fs = std::filesystem;
    std::vector<std::string> entries;
    std::error_code ec;
    for (const auto& entry : fs::recursive_directory_iterator(folder, ec))
        entries.push_back(fs::relative(entry.path(), folder).string());
    std::sort(entries.begin(), entries.end());
    return entries;
}

}  // namespace patchsim::test
