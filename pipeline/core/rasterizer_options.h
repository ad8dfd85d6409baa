#pragma once
// Options of the patch rasterizer (SPEC section 4), settable from a scene's "rasterizer" object
// and from the command line. Documented in docs/SCENES.md.

#include <cstdint>
#include <string>

namespace patchsim {

enum class BranchMethod : std::uint8_t { Root, FirstSplit, Bitmask };
const char* branchMethodName(BranchMethod m);
bool parseBranchMethod(const std::string& name, BranchMethod& out);

struct RasterizerOptions {
    int tileSize = 8;     // pixels per tile side
    int leafSize = 4;     // triangles per leaf
    int boundsLevel = 0;  // tree level whose boxes give the screen bounds
    BranchMethod branchMethod = BranchMethod::Bitmask;
    bool timeRefinement = true;                    // narrow [tmin, tmax] at the leaves
    bool zCulling = true;                          // tile far plane and ray tmax from the z-buffer
    int maxTrianglesPerGroup = 256;                // at most 64 leaves per hierarchy
    std::uint64_t scratchBudgetBytes = 16 * 1024;  // on-chip memory for one hierarchy

    // Throws InputError(source, "rasterizer.FIELD") when a value is out of range.
    void validate(const std::string& source) const;
};

}  // namespace patchsim
