#pragma once
// Small neighbouring patches merged into one hierarchy (US 8,791,945: "subsets of a patch, or
// several patches"). A patch tessellated to a handful of triangles fills a handful of leaves; its
// own hierarchy costs a screen-bounds setup and a tile walk per tile for little culling. Merged
// with its neighbours, one hierarchy serves them all, and its upper levels separate the patches.
//
// Representation
// --------------
// A rasterization unit is either one patch's mesh as it is, or a merged mesh: the vertices and
// triangles of a run of patches that are consecutive in the scene's order (a cage's faces, so
// mostly neighbours on the surface), of one object and one opacity, each with at most
// `mergeBelow` triangles, together at most a group's worth. In a merged mesh a triangle's domain
// position is its patch's camera-space centre plus its own (u, v) scaled far down, so the
// hierarchy's upper splits fall between patches by where they are; every triangle keeps its own
// patch and its index there, which its hits carry, so the visibility samples are those of the
// unmerged patches.

#include <cstddef>
#include <vector>

#include "rasterizer/common/moving_mesh.h"

namespace patchsim {

struct RasterUnits {
    std::vector<MovingMesh> merged;         // the merged meshes
    std::vector<const MovingMesh*> meshes;  // per unit: a patch's own mesh or a merged one
    std::vector<std::size_t> firstPatch;    // per unit: its first patch (its work goes there)
    std::vector<std::size_t> patchCount;    // per unit: how many patches it holds
    std::vector<std::size_t> unitOf;        // per patch: its unit
};

// `mergeBelow` 0: one unit per patch.
RasterUnits makeRasterUnits(const std::vector<MovingMesh>& patches, int mergeBelow,
                            int trianglesPerGroup);

}  // namespace patchsim
