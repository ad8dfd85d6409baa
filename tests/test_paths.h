#pragma once
// Where tests find the project's scenes and OpenSubdiv's regression cages (tests/data/opensubdiv).

#include <string>
#include <vector>

namespace patchsim::test {

std::string sourcePath(const std::string& relative);  // under the project root
std::string regressionCagesDir();                     // tests/data/opensubdiv
// Every .obj in regressionCagesDir(), sorted. Throws (failing the test, never skipping it) when
// the folder is missing or holds fewer cages than the repository ships.
std::vector<std::string> regressionCageFiles();
std::vector<std::string> sceneFiles();  // every scenes/*.json, sorted
std::string temporaryDirectory();       // fresh, per process

}  // namespace patchsim::test
