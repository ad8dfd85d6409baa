#pragma once
// The camera-space moving triangles of one tessellated patch, the rasterizer's input.
//
// Representation
// --------------
// Per vertex: camera-space positions at t=0 and t=1 (each shutter end uses its own view
// transform), and the domain (u,v) the tessellator gave it; triangles as index triples. A vertex
// at time t is lerp(p0, p1, t) computed in float exactly as LBBox::at blends box corners.

#include <cstdint>
#include <vector>

#include "core/camera.h"
#include "core/lbbox.h"
#include "core/number_format.h"
#include "tessellator/front_end.h"

namespace patchsim {

struct MovingMesh {
    std::vector<Vec3> position0, position1;
    std::vector<Vec2> domain;
    std::vector<std::uint32_t> indices;
    // Global patch index: hits at equal depth resolve to the lower patch, then triangle.
    int patchId = -1;
    int objectId = -1;
    bool opaque = true;  // false: every hit goes to the transparent layers
    // Set when neighbouring patches were merged into this mesh (patch_merge.h): each triangle's
    // own patch and its index there, which its hits carry.
    std::vector<int> trianglePatch;
    std::vector<std::uint32_t> triangleInPatch;

    std::size_t triangleCount() const { return indices.size() / 3; }
    Vec3 vertexAt(std::uint32_t v, float t) const { return lerp(position0[v], position1[v], t); }
    LBBox triangleBounds(std::size_t triangle) const {
        LBBox b;
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t v = indices[3 * triangle + std::size_t(k)];
            b.extend(position0[v], position1[v]);
        }
        return b;
    }
    void clear() {
        position0.clear();
        position1.clear();
        domain.clear();
        indices.clear();
        trianglePatch.clear();
        triangleInPatch.clear();
    }
    // The patch and triangle a hit on `triangle` reports.
    int patchOf(std::uint32_t triangle) const {
        return trianglePatch.empty() ? patchId : trianglePatch[triangle];
    }
    std::uint32_t triangleInPatchOf(std::uint32_t triangle) const {
        return triangleInPatch.empty() ? triangle : triangleInPatch[triangle];
    }
};

// Camera-space mesh of a tessellated patch. Without motion (`motion` false) the t=1 positions are
// the t=0 ones, so every box is static.
void toMovingMesh(const TessellatedPatch& patch, const Camera& camera, bool motion, int patchId,
                  bool opaque, MovingMesh& out);

// Every position as the rasterizer receives it in `format` (rasterizer.vertex_format, issue 35):
// each coordinate rounded to the nearest value, one beyond the format's range to its end.
// Lossy by design (a vertex has no outward side), but a vertex shared by triangles is rounded
// once, so shared edges stay shared and the mesh stays watertight. fp32 leaves the mesh as it is.
void storePositionsIn(MovingMesh& mesh, const NumberFormat& format);

}  // namespace patchsim
