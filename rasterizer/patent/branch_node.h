#pragma once
// The branch node (US 8,791,945, step 5): the node per-sample rays start from, below which every
// overlapping leaf lies. Starting lower saves ray-box tests; it must never be below a leaf that
// holds a hit.
//
// - root: the root, always safe, the most box tests.
// - first-split: the first node of the tile's walk whose two children both overlap (found during
//   the walk, `TileTraversal::firstSplitNode`).
// - bitmask: one bit per overlapping leaf, OR-reduced level by level (sibling pairs) until one bit
//   is left (x & (x-1) == 0); that bit's node is the lowest node above every overlapping leaf.

#include <cstdint>

#include "core/rasterizer_options.h"
#include "rasterizer/patent/tile_traversal.h"

namespace patchsim {

// The lowest node above every set leaf of `leafMask` in a complete tree of `depth` levels.
int bitmaskBranchNode(std::uint64_t leafMask, int depth);

// The node rays of an overlapping tile start from, by method.
int branchNode(BranchMethod method, const TileTraversal& traversal, int depth);

}  // namespace patchsim
