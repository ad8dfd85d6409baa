#pragma once
// Where tests find the project's scenes and the shared OpenSubdiv cages.

#include <string>
#include <vector>

namespace patchsim::test {

std::string sourcePath(const std::string& relative);  // under the project root
std::string sharedModelsDir();                        // ../shared/models/opensubdiv
std::vector<std::string> sharedModelFiles();          // every .obj there, sorted
std::vector<std::string> sceneFiles();                // every scenes/*.json, sorted
std::string temporaryDirectory();                     // fresh, per process

}  // namespace patchsim::test
