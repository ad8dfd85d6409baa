#include "pipeline/core/rasterizer_options.h"

#include "pipeline/core/error.h"

namespace patchsim {

const char* branchMethodName(BranchMethod m) {
    switch (m) {
        case BranchMethod::Root:
            return "root";
        case BranchMethod::FirstSplit:
            return "first-split";
        case BranchMethod::Bitmask:
            return "bitmask";
    }
    return "?";
}

bool parseBranchMethod(const std::string& name, BranchMethod& out) {
    for (BranchMethod m : {BranchMethod::Root, BranchMethod::FirstSplit, BranchMethod::Bitmask}) {
        if (name == branchMethodName(m)) {
            out = m;
            return true;
        }
    }
    return false;
}

void RasterizerOptions::validate(const std::string& source) const {
    auto check = [&](bool ok, const char* field, const char* message) {
        if (!ok) throw InputError(source, std::string("rasterizer.") + field, message);
    };
    check(tileSize >= 1 && tileSize <= 256, "tile_size", "must be in [1, 256]");
    check(leafSize >= 1 && leafSize <= 64, "leaf_size", "must be in [1, 64]");
    check(boundsLevel >= 0 && boundsLevel <= 6, "bounds_level", "must be in [0, 6]");
    check(maxTrianglesPerGroup >= 1 && maxTrianglesPerGroup <= leafSize * 64,
          "max_triangles_per_group", "must be in [1, 64 * leaf_size]");
}

}  // namespace patchsim
