#include "tessellator/front_end.h"

#include <algorithm>
#include <cmath>
#include <exception>

#include "core/error.h"
#include "core/parallel.h"
#include "tessellator/patch_boundary.h"

namespace patchsim {

namespace {

bool integerLike(Partitioning p) {
    return p == Partitioning::Integer || p == Partitioning::Pow2;
}

Vec3 safeNormal(const Vec3& du, const Vec3& dv) {
    const Vec3 n = glm::cross(du, dv);
    const float len = glm::length(n);
    return len > 0 && std::isfinite(len) ? n / len : Vec3(0);
}

}  // namespace

namespace {

// Every control point of object i, placed by its transforms at both shutter ends, must be a
// float: the cage's and the scene's numbers are each capped at 1e30, but a product of two
// (a coordinate times a scale) can overflow, and an infinite control point makes every limit
// point it touches NaN, which the rasterizers would then silently drop.
void checkFinite(const ControlPoints& points, const SceneDesc& scene, std::size_t i) {
    static constexpr const char* kEnd[2] = {"open", "close"};
    for (int end = 0; end < 2; ++end) {
        const std::vector<Vec3>& at = points.at[end];
        for (std::size_t v = 0; v < at.size(); ++v) {
            if (std::isfinite(at[v].x) && std::isfinite(at[v].y) && std::isfinite(at[v].z))
                continue;
            throw InputError(scene.path, "objects[" + std::to_string(i) + "]",
                             "vertex " + std::to_string(v + 1) + " of '" +
                                 scene.objects[i].cagePath + "' is not finite at shutter " +
                                 kEnd[end] +
                                 " once placed by the object's transforms (beyond the float "
                                 "range: reduce the cage's coordinates or the object's scale)");
        }
    }
}

// Object i of the scene without its limit surface: its cage (and shutter-close cage) and vertex
// stage.
SceneObject readObject(const SceneDesc& scene, std::size_t i) {
    const ObjectDesc& desc = scene.objects[i];
    const std::string field = "objects[" + std::to_string(i) + "]";
    SceneObject object;
    object.desc = desc;
    object.cage = readObjCage(desc.cagePath, scene.path, field + ".cage");
    std::unique_ptr<Cage> closeCage;
    if (!desc.cageClosePath.empty()) {
        closeCage = std::make_unique<Cage>(
            readObjCage(desc.cageClosePath, scene.path, field + ".cage_close"));
        if (closeCage->faceSizes != object.cage.faceSizes ||
            closeCage->faceVertices != object.cage.faceVertices)
            throw InputError(scene.path, field + ".cage_close",
                             "'" + desc.cageClosePath + "' does not have the topology of '" +
                                 desc.cagePath + "'");
    }
    object.points = runVertexStage(desc, object.cage, closeCage.get(), scene.shutter);
    checkFinite(object.points, scene, i);
    return object;
}

}  // namespace

FrontEnd::FrontEnd(const SceneDesc& scene, int threads)
    : scene_(scene), camera_(scene.camera, scene.shutter, scene.film.width, scene.film.height) {
    hull_.partitioning = scene.tessellation.partitioning;
    hull_.insideReduction = scene.tessellation.insideReduction;
    // The objects' cages are read and their vertex stages run on `threads`, each into its slot.
    // Their meshes are then built one object after another, each object's Bfr surfaces on
    // `threads` (subdivision_mesh.cpp): a scene's surfaces are mostly one object's (the creased
    // cube of the default scene; a cage rendered on its own). The first object in scene order
    // that fails is the one reported, as one thread would.
    const std::size_t count = scene.objects.size();
    objects_.resize(count);
    std::vector<std::exception_ptr> failures(count);
    parallelFor(count, threads, [&](int, std::size_t i) {
        try {
            objects_[i] = readObject(scene, i);
        } catch (...) {
            failures[i] = std::current_exception();
        }
    });
    for (std::size_t i = 0; i < count; ++i) {
        if (failures[i]) std::rethrow_exception(failures[i]);
        SceneObject& object = objects_[i];
        object.mesh =
            std::make_unique<SubdivisionMesh>(object.cage, object.desc.scheme, object.desc.cagePath,
                                              SubdivisionMesh::FarFaces::OnlyUnsafeForBfr, threads);
    }
    patchOffsets_.push_back(0);
    for (const SceneObject& object : objects_)
        patchOffsets_.push_back(patchOffsets_.back() + object.mesh->patches().size());
}

bool FrontEnd::geometryMoves() const {
    return std::any_of(objects_.begin(), objects_.end(),
                       [](const SceneObject& o) { return o.points.moves(); });
}

float FrontEnd::adaptiveFactor(const Vec3 a[2], const Vec3 b[2]) const {
    const TessellationDesc& t = scene_.tessellation;
    float longest = 0;
    for (int end = 0; end < 2; ++end) {
        Vec2 ra, rb;
        const bool visibleA = camera_.cameraToRaster(camera_.toCamera(a[end], ShutterEnd(end)), ra);
        const bool visibleB = camera_.cameraToRaster(camera_.toCamera(b[end], ShutterEnd(end)), rb);
        // An edge reaching behind the near plane has no finite screen length: tessellate fully.
        if (!visibleA || !visibleB) return t.maxFactor;
        longest = std::max(longest, glm::length(ra - rb));
    }
    const float f = longest / t.targetEdgePixels;
    return std::isfinite(f) ? std::clamp(f, 1.0f, t.maxFactor) : t.maxFactor;
}

float FrontEnd::rawEdgeFactor(const SceneObject& object, const EdgeFactorSource& source) const {
    const TessellationDesc& t = scene_.tessellation;
    const bool adaptive = t.targetEdgePixels > 0;
    const SubdivisionMesh& mesh = *object.mesh;
    const auto& pts = object.points.at;
    auto cageEdgeFactor = [&](int farEdge) {
        const int edge = mesh.sharedEdge(farEdge);  // the same factor on every copy of the edge
        float f = t.factor;
        if (adaptive) {
            const int v0 = mesh.cageEdgeVertex(edge, 0), v1 = mesh.cageEdgeVertex(edge, 1);
            const Vec3 a[2] = {pts[0][std::size_t(v0)], pts[1][std::size_t(v0)]};
            const Vec3 b[2] = {pts[0][std::size_t(v1)], pts[1][std::size_t(v1)]};
            f = adaptiveFactor(a, b);
        }
        // Next to an N-gon the edge is split in two halves of half the factor; an even whole
        // factor (at most 64) puts the halves' points on the whole edge's points.
        if (mesh.cageEdgeNextToSubpatches(edge) && integerLike(t.partitioning))
            f = 2.0f * std::ceil(std::min(f, 64.0f) / 2.0f);
        return f;
    };
    switch (source.kind) {
        case EdgeFactorSource::WholeCageEdge:
            return cageEdgeFactor(source.cageEdge);
        case EdgeFactorSource::HalfCageEdge:
            return cageEdgeFactor(source.cageEdge) / 2.0f;
        case EdgeFactorSource::Interior: {
            if (!adaptive) return t.factor / 2.0f;
            const std::vector<int>& fv = mesh.faceVertices(source.face);
            const int v0 = mesh.cageEdgeVertex(source.cageEdge, 0);
            const int v1 = mesh.cageEdgeVertex(source.cageEdge, 1);
            Vec3 mid[2], centre[2];
            for (int end = 0; end < 2; ++end) {
                mid[end] = 0.5f * (pts[end][std::size_t(v0)] + pts[end][std::size_t(v1)]);
                centre[end] = Vec3(0);
                for (int v : fv) centre[end] += pts[end][std::size_t(v)];
                centre[end] /= float(fv.size());
            }
            return adaptiveFactor(mid, centre);
        }
    }
    return t.factor;
}

void FrontEnd::runHullShader(const SceneObject& object, const PatchInfo& patch,
                             TessellatedPatch& out) const {
    float patchEdges[4];
    for (int e = 0; e < patch.cornerCount(); ++e)
        patchEdges[e] = rawEdgeFactor(object, patch.edgeSources[e]);
    if (patch.domain == PatchDomain::Quad) {
        // D3D11 order u=0, v=0, u=1, v=1 is patch edges 3, 0, 1, 2.
        const float d3d[4] = {patchEdges[3], patchEdges[0], patchEdges[1], patchEdges[2]};
        const QuadTessFactors f = processQuadFactors(d3d, hull_);
        std::copy(f.edge, f.edge + 4, out.edgeFactors);
        std::copy(f.inside, f.inside + 2, out.insideFactors);
    } else {
        // D3D11 order u=0, v=0, w=0 is patch edges 2, 0, 1.
        const float d3d[3] = {patchEdges[2], patchEdges[0], patchEdges[1]};
        const TriTessFactors f = processTriFactors(d3d, hull_);
        std::copy(f.edge, f.edge + 3, out.edgeFactors);
        out.edgeFactors[3] = 0;
        out.insideFactors[0] = f.inside;
        out.insideFactors[1] = 0;
    }
}

void FrontEnd::runTessellator(std::size_t index, TessellatedPatch& out,
                              FrontEndWorkspace& ws) const {
    const auto it = std::upper_bound(patchOffsets_.begin(), patchOffsets_.end(), index);
    const std::size_t objectIndex = std::size_t(it - patchOffsets_.begin()) - 1;
    const SceneObject& object = objects_[objectIndex];
    const int patchIndex = int(index - patchOffsets_[objectIndex]);
    const PatchInfo& patch = object.mesh->patches()[std::size_t(patchIndex)];
    out.object = int(objectIndex);
    out.patch = patchIndex;
    out.domain = patch.domain;
    out.controlPoints = object.mesh->controlPointCount(patch.face);
    runHullShader(object, patch, out);
    if (patch.domain == PatchDomain::Quad) {
        QuadTessFactors f;
        std::copy(out.edgeFactors, out.edgeFactors + 4, f.edge);
        std::copy(out.insideFactors, out.insideFactors + 2, f.inside);
        ws.tessellator.tessellateQuad(f, out.tessellation);
    } else {
        TriTessFactors f;
        std::copy(out.edgeFactors, out.edgeFactors + 3, f.edge);
        f.inside = out.insideFactors[0];
        ws.tessellator.tessellateTri(f, out.tessellation);
    }
}

void FrontEnd::stitchSharedEdges(TessellatedPatch& out, FrontEndWorkspace& ws) const {
    const SubdivisionMesh& mesh = *objects_[std::size_t(out.object)].mesh;
    const std::size_t objectBase = patchOffsets_[std::size_t(out.object)];
    const PatchInfo& patch = mesh.patches()[std::size_t(out.patch)];
    std::vector<std::uint32_t>& wanted = ws.stitchPoints;
    for (int e = 0; e < patch.cornerCount(); ++e) {
        SubdivisionMesh::CageEdgeSpan mine;
        if (!mesh.cageEdgeSpan(out.patch, e, mine)) continue;
        wanted.clear();
        for (const SubdivisionMesh::CageEdgeSpan& other :
             mesh.spansOnCageEdge(patch.edgeSources[e].cageEdge)) {
            // A patch may have a cage edge twice (a face that repeats a vertex): its other copy
            // is a neighbour like any other.
            if ((other.patch == out.patch && other.edge == e) ||
                other.start >= mine.start + mine.length || other.start + other.length <= mine.start)
                continue;
            runTessellator(objectBase + std::size_t(other.patch), ws.neighbour, ws);
            ++out.work.neighbourTessellations;
            if (ws.neighbour.culled()) continue;
            for (const std::uint32_t s :
                 pointsOnEdge(ws.neighbour.tessellation, ws.neighbour.domain, other.edge)) {
                const std::uint32_t w = SubdivisionMesh::toCageEdge(other, s);
                if (w > mine.start && w < mine.start + mine.length)
                    wanted.push_back(SubdivisionMesh::fromCageEdge(mine, w));
            }
        }
        std::sort(wanted.begin(), wanted.end());
        wanted.erase(std::unique(wanted.begin(), wanted.end()), wanted.end());
        out.work.stitchPoints += insertEdgePoints(out.tessellation, out.domain, e, wanted);
    }
}

void FrontEnd::tessellate(std::size_t index, TessellatedPatch& out, FrontEndWorkspace& ws,
                          bool evaluate) const {
    out.work = {};
    runTessellator(index, out, ws);
    FrontEndWork& work = out.work;
    work.patches = 1;
    work.patchControlPoints = out.controlPoints;
    work.hullPatches = 1;
    work.edgeFactors = out.domain == PatchDomain::Quad ? 4 : 3;
    work.culledPatches = out.culled() ? 1 : 0;
    // Integer partitioning makes the two sides agree by construction (hull shader); fractional
    // patterns of whole and half edges differ, so each side takes the other's points.
    if (!out.culled() && !integerLike(hull_.partitioning)) stitchSharedEdges(out, ws);
    work.domainPoints = std::int64_t(out.tessellation.points.size());
    work.triangles = std::int64_t(out.triangleCount());
    for (int end = 0; end < 2; ++end) {
        out.position[end].clear();
        out.normal[end].clear();
    }
    out.surfaceUV.clear();
    if (evaluate && !out.culled())
        runDomainShader(objects_[std::size_t(out.object)], out.patch, out, ws);
    work.flush();
}

void FrontEnd::runDomainShader(const SceneObject& object, int patchIndex, TessellatedPatch& out,
                               FrontEndWorkspace& ws) const {
    const SubdivisionMesh& mesh = *object.mesh;
    const PatchInfo& self = mesh.patches()[std::size_t(patchIndex)];
    const std::size_t n = out.tessellation.points.size();
    for (int end = 0; end < 2; ++end) {
        out.position[end].resize(n);
        out.normal[end].resize(n);
    }
    out.surfaceUV.resize(n);
    std::int64_t ownerEvaluations = 0;
    // Segments per patch edge under integer partitioning (patch edge e is D3D11 edge
    // kQuadD3DEdge[e] or kTriD3DEdge[e]); 0 for fractional partitioning.
    int segments[4] = {0, 0, 0, 0};
    if (integerLike(scene_.tessellation.partitioning)) {
        static constexpr int kQuadD3DEdge[4] = {1, 2, 3, 0};
        static constexpr int kTriD3DEdge[3] = {1, 2, 0};
        for (int e = 0; e < self.cornerCount(); ++e) {
            const float f = out.edgeFactors[self.domain == PatchDomain::Quad ? kQuadD3DEdge[e]
                                                                             : kTriD3DEdge[e]];
            segments[e] = int(std::ceil(std::clamp(f, 1.0f, 64.0f)));
        }
    }
    for (std::size_t k = 0; k < n; ++k) {
        const DomainPoint dp = out.tessellation.points[k];
        float faceUV[2];
        mesh.faceCoord(self, dp.u, dp.v, faceUV);
        out.surfaceUV[k] = {faceUV[0], faceUV[1]};
        // Points on a shared edge or corner are evaluated on the owning patch (watertightness).
        int owner = patchIndex;
        float ownerUV[2] = {dp.u, dp.v};
        const BoundaryPlace place = locateOnBoundary(self.domain, dp.u, dp.v);
        if (place.corner >= 0)
            mesh.ownerOfCorner(patchIndex, place.corner, segments, owner, ownerUV);
        else if (place.edge >= 0)
            mesh.ownerOfEdgePoint(patchIndex, place.edge, place.s, segments, owner, ownerUV);
        const PatchInfo& ownerPatch = mesh.patches()[std::size_t(owner)];
        float evalUV[2];
        mesh.faceCoord(ownerPatch, ownerUV[0], ownerUV[1], evalUV);
        if (owner != patchIndex) ++ownerEvaluations;
        mesh.evaluateStencil(ownerPatch.face, evalUV, ws.stencil);
        for (int end = 0; end < 2; ++end) {
            const std::vector<Vec3>& cps = object.points.at[end];
            const SubdivisionMesh::Stencil& st = ws.stencil;
            out.position[end][k] = mesh.applyStencil(ownerPatch.face, st, st.position, cps);
            const Vec3 du = mesh.applyStencil(ownerPatch.face, st, st.du, cps);
            const Vec3 dv = mesh.applyStencil(ownerPatch.face, st, st.dv, cps);
            out.normal[end][k] = safeNormal(du, dv);
        }
    }
    out.work.evaluations = std::int64_t(n);
    out.work.ownerEvaluations = ownerEvaluations;
    out.work.stencilApplications = std::int64_t(n) * 6;
}

}  // namespace patchsim
