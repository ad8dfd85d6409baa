#pragma once
// Runs the patchsim binary for the command-line tests: its exit code and everything it printed.

#include <string>
#include <vector>

namespace patchsim::test {

struct CommandResult {
    int exitCode;        // -1 when the process did not exit normally (a signal)
    std::string output;  // stdout and stderr
};

// `patchsim ARGUMENTS`, in the current folder, or in `folder` when one is given.
CommandResult run(const std::string& arguments, const std::string& folder = {});

// Writes `text` to `name` in the process's temporary folder (test_paths.h); returns the path.
std::string writeFile(const std::string& name, const std::string& text);
std::string readFile(const std::string& path);

// Every entry under `folder`, relative to it, sorted.
std::vector<std::string> listTree(const std::string& folder);

}  // namespace patchsim::test
