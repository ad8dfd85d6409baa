#include "rasterizer/patent/branch_node.h"

#include <bit>

#include "rasterizer/patent/patch_hierarchy.h"

namespace patchsim {

int bitmaskBranchNode(std::uint64_t mask, int depth) {
    if (mask == 0) return 0;
    for (int level = depth; level >= 0; --level) {
        if ((mask & (mask - 1)) == 0)
            return PatchHierarchy::firstLeaf(level) + std::countr_zero(mask);
        std::uint64_t up = 0;
        for (int j = 0; j < (1 << level); j += 2)
            if (mask & (std::uint64_t(3) << j)) up |= std::uint64_t(1) << (j / 2);
        mask = up;
    }
    return 0;
}

int branchNode(BranchMethod method, const TileTraversal& traversal, int depth) {
    switch (method) {
        case BranchMethod::Root:
            return 0;
        case BranchMethod::FirstSplit:
            return traversal.firstSplitNode;
        case BranchMethod::Bitmask:
            return bitmaskBranchNode(traversal.leafMask, depth);
    }
    return 0;
}

}  // namespace patchsim
