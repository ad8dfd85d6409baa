#pragma once
// The visibility methods patchsim compares (DESIGN.md section 5): their names, whether they are
// exact (the same visibility as the brute-force reference for the same samples) or approximate, and
// the work they come from. One table; the command line, the sweep and the docs read it.

#include <cstdint>
#include <string>
#include <vector>

namespace patchsim {

enum class VisibilityMethod : std::uint8_t {
    Patch,
    Reference,
    TriangleBBox,
    Interval,
    Interleaved,
    Postprocess,
    Hybrid,
    Reprojection,
    TFragment
};

struct VisibilityMethodInfo {
    VisibilityMethod method;
    const char* name;   // as on the command line: "triangle-bbox"
    bool exact;         // same samples, same nearest hits as the reference
    const char* after;  // where it comes from
};

const std::vector<VisibilityMethodInfo>& visibilityMethods();
const VisibilityMethodInfo& methodInfo(VisibilityMethod m);
const char* visibilityMethodName(VisibilityMethod m);
bool parseVisibilityMethod(const std::string& name, VisibilityMethod& out);
std::string visibilityMethodNames();  // "patch, reference, ..." for messages

}  // namespace patchsim
