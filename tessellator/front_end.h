#pragma once
// The front end of the pipeline: IA, VS, HS, TS and DS for a whole scene, one patch at a time.
//
// Representation
// --------------
// Construction runs the input assembler and vertex stage for every object (cages read, OpenSubdiv
// topology and surfaces built, control points placed at shutter open and close); that is the
// scene's only persistent geometry. `tessellate(i)` then runs HS, TS and DS for global patch i
// into a caller-owned TessellatedPatch, so patches stream through with bounded memory and any
// number of threads can tessellate different patches at once (each with its own workspace).
//
// A TessellatedPatch holds the D3D11 domain points and triangles, and per domain point the limit
// position and normal at both shutter ends plus the face-level surface (u,v).

#include <cstddef>
#include <memory>
#include <vector>

#include "core/camera.h"
#include "core/scene.h"
#include "tessellator/d3d11_tessellator.h"
#include "tessellator/front_end_work.h"
#include "tessellator/hull_shader.h"
#include "tessellator/subdivision_mesh.h"
#include "tessellator/vertex_stage.h"

namespace patchsim {

struct SceneObject {
    ObjectDesc desc;
    Cage cage;
    std::unique_ptr<SubdivisionMesh> mesh;
    ControlPoints points;
};

struct TessellatedPatch {
    int object = -1;
    int patch = -1;  // index into the object's mesh patches
    PatchDomain domain = PatchDomain::Quad;
    float edgeFactors[4] = {};  // after HS processing, D3D11 edge order
    float insideFactors[2] = {};
    int controlPoints = 0;  // control points of the patch's limit surface
    Tessellation tessellation;
    std::vector<Vec3> position[2];  // limit position at shutter open / close, world space
    std::vector<Vec3> normal[2];
    std::vector<Vec2> surfaceUV;  // face-level Bfr (u,v)
    FrontEndWork work;            // what the front end did for this patch (already counted)

    bool culled() const { return tessellation.culled; }
    std::size_t triangleCount() const { return tessellation.triangleCount(); }
};

struct FrontEndWorkspace {
    explicit FrontEndWorkspace(Partitioning p) : tessellator(p) {}
    D3D11Tessellator tessellator;
    SubdivisionMesh::Stencil stencil;
    TessellatedPatch neighbour;  // a neighbour's TS output, for stitching shared edges
    std::vector<std::uint32_t> stitchPoints;
};

class FrontEnd {
  public:
    // Reads every cage (the objects on `threads` workers); throws InputError naming the scene
    // file and field on bad input.
    explicit FrontEnd(const SceneDesc& scene, int threads = 1);

    const SceneDesc& scene() const { return scene_; }
    const Camera& camera() const { return camera_; }
    const std::vector<SceneObject>& objects() const { return objects_; }
    std::size_t patchCount() const { return patchOffsets_.back(); }
    bool geometryMoves() const;

    FrontEndWorkspace makeWorkspace() const { return FrontEndWorkspace(hull_.partitioning); }

    // HS and TS for global patch `index`; DS as well when `evaluate` (otherwise only the domain
    // points and triangles are filled, e.g. to count them).
    void tessellate(std::size_t index, TessellatedPatch& out, FrontEndWorkspace& ws,
                    bool evaluate = true) const;

    // Raw factor of a patch edge before HS processing (public for tests of crack-freeness).
    float rawEdgeFactor(const SceneObject& object, const EdgeFactorSource& source) const;

  private:
    void runHullShader(const SceneObject& object, const PatchInfo& patch,
                       TessellatedPatch& out) const;
    // HS and TS only.
    void runTessellator(std::size_t index, TessellatedPatch& out, FrontEndWorkspace& ws) const;
    // Adds the points neighbouring patches have on shared cage edges (patch_boundary.h).
    void stitchSharedEdges(TessellatedPatch& out, FrontEndWorkspace& ws) const;
    void runDomainShader(const SceneObject& object, int patchIndex, TessellatedPatch& out,
                         FrontEndWorkspace& ws) const;
    float adaptiveFactor(const Vec3 a[2], const Vec3 b[2]) const;

    SceneDesc scene_;
    Camera camera_;
    HullShaderConfig hull_;
    std::vector<SceneObject> objects_;
    std::vector<std::size_t> patchOffsets_;  // prefix sums of patches per object
};

}  // namespace patchsim
