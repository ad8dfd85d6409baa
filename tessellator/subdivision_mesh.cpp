#include "tessellator/subdivision_mesh.h"

#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/bfr/surfaceFactoryCache.h>
#include <opensubdiv/far/error.h>
#include <opensubdiv/far/topologyDescriptor.h>

#include <algorithm>
#include <cstdio>
#include <mutex>
#include <shared_mutex>
#include <stdexcept>
#include <unordered_map>

#include "core/counters.h"
#include "core/error.h"
#include "core/parallel.h"
#include "tessellator/far_limit_evaluator.h"

namespace patchsim {

namespace osd = OpenSubdiv::OPENSUBDIV_VERSION;

const Counter iaCageFaces{"IA/Cage faces", "faces", "Faces of the control cages read"};
const Counter iaHoleFaces{"IA/Hole faces", "faces", "Cage faces tagged as holes (no patch)"};
const Counter iaFarFaces{
    "IA/Far-evaluated faces", "faces",
    "Cage faces evaluated on Far's patch table instead of Bfr (OpenSubdiv 3.5.0 bug)"};

namespace {

constexpr std::uint32_t kCageEdgeOne = 1u << 17;

// Far reports topology errors through a process-wide callback; collect the first one per thread.
// A character array, not a std::string: a thread_local with a destructor registers with the C
// runtime on first use, which waits for any dlopen under way (backend/images/image_io_module.h).
thread_local char farError[512] = "";
void onFarError(osd::Far::ErrorType, const char* message) {
    if (farError[0] == '\0') std::snprintf(farError, sizeof farError, "%s", message);
}

osd::Sdc::SchemeType toOsd(SubdivisionScheme s) {
    switch (s) {
        case SubdivisionScheme::Catmark:
            return osd::Sdc::SCHEME_CATMARK;
        case SubdivisionScheme::Loop:
            return osd::Sdc::SCHEME_LOOP;
        case SubdivisionScheme::Bilinear:
            return osd::Sdc::SCHEME_BILINEAR;
    }
    return osd::Sdc::SCHEME_CATMARK;
}

osd::Sdc::Options sdcOptions(const Cage& cage) {
    osd::Sdc::Options o;
    switch (cage.boundary) {
        case BoundaryInterpolation::None:
            o.SetVtxBoundaryInterpolation(osd::Sdc::Options::VTX_BOUNDARY_NONE);
            break;
        case BoundaryInterpolation::EdgeOnly:
            o.SetVtxBoundaryInterpolation(osd::Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
            break;
        case BoundaryInterpolation::EdgeAndCorner:
            o.SetVtxBoundaryInterpolation(osd::Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER);
            break;
    }
    o.SetCreasingMethod(cage.creaseMethod == CreaseMethod::Chaikin
                            ? osd::Sdc::Options::CREASE_CHAIKIN
                            : osd::Sdc::Options::CREASE_UNIFORM);
    o.SetTriangleSubdivision(cage.smoothTriangles ? osd::Sdc::Options::TRI_SUB_SMOOTH
                                                  : osd::Sdc::Options::TRI_SUB_CATMARK);
    return o;
}

}  // namespace

// A factory whose cache of patch trees (shared by faces of the same neighbourhood) takes a lock,
// so that the faces' surfaces can be built on several threads.
using ThreadSafeSurfaceFactory = osd::Bfr::RefinerSurfaceFactory<
    osd::Bfr::SurfaceFactoryCacheThreaded<std::shared_mutex, std::shared_lock<std::shared_mutex>,
                                          std::unique_lock<std::shared_mutex>>>;

struct SubdivisionMesh::Impl {
    std::unique_ptr<osd::Far::TopologyRefiner> refiner;
    std::unique_ptr<ThreadSafeSurfaceFactory> factory;
    std::vector<osd::Bfr::Surface<float>>
        surfaces;             // one per face; invalid for holes and Far faces
    std::vector<char> onFar;  // per face: evaluated by `far`
    std::unique_ptr<FarLimitEvaluator> far;

    bool hasSurface(std::size_t face) const {
        return onFar[face] ? far->hasSurface(int(face)) : surfaces[face].IsValid();
    }
    osd::Bfr::Parameterization parameterization(int face) const {
        if (!onFar[std::size_t(face)]) return surfaces[std::size_t(face)].GetParameterization();
        return osd::Bfr::Parameterization(refiner->GetSchemeType(),
                                          refiner->GetLevel(0).GetFaceVertices(face).size());
    }
};

SubdivisionMesh::SubdivisionMesh(const Cage& cage, SubdivisionScheme scheme,
                                 const std::string& path, FarFaces farChoice, int threads)
    : scheme_(scheme), impl_(std::make_unique<Impl>()) {
    if (scheme == SubdivisionScheme::Loop) {
        for (int f = 0; f < cage.faceCount(); ++f) {
            if (cage.faceSizes[std::size_t(f)] != 3)
                throw InputError(path, "f",
                                 "face " + std::to_string(f + 1) + " has " +
                                     std::to_string(cage.faceSizes[std::size_t(f)]) +
                                     " sides; the Loop scheme needs triangles");
        }
    }
    std::vector<int> creasePairs;
    std::vector<float> creaseWeights;
    for (const CageCrease& c : cage.creases) {
        creasePairs.insert(creasePairs.end(), {c.v0, c.v1});
        creaseWeights.push_back(c.sharpness);
    }
    std::vector<int> cornerVertices;
    std::vector<float> cornerWeights;
    for (const CageCorner& c : cage.corners) {
        cornerVertices.push_back(c.vertex);
        cornerWeights.push_back(c.sharpness);
    }
    osd::Far::TopologyDescriptor desc;
    desc.numVertices = cage.vertexCount();
    desc.numFaces = cage.faceCount();
    desc.numVertsPerFace = cage.faceSizes.data();
    desc.vertIndicesPerFace = cage.faceVertices.data();
    desc.numCreases = int(creaseWeights.size());
    desc.creaseVertexIndexPairs = creasePairs.data();
    desc.creaseWeights = creaseWeights.data();
    desc.numCorners = int(cornerWeights.size());
    desc.cornerVertexIndices = cornerVertices.data();
    desc.cornerWeights = cornerWeights.data();
    desc.numHoles = int(cage.holes.size());
    desc.holeIndices = cage.holes.data();

    using Factory = osd::Far::TopologyRefinerFactory<osd::Far::TopologyDescriptor>;
    const Factory::Options options(toOsd(scheme), sdcOptions(cage));
    {
        static std::mutex farMutex;  // the error callback is process-wide
        std::lock_guard lock(farMutex);
        farError[0] = '\0';
        osd::Far::SetErrorCallback(onFarError);
        impl_->refiner.reset(Factory::Create(desc, options));
        osd::Far::SetErrorCallback(nullptr);
        if (!impl_->refiner)
            throw InputError(path, "f",
                             "OpenSubdiv rejected the topology: " +
                                 (farError[0] == '\0' ? "unknown error" : std::string(farError)));
    }
    const osd::Far::TopologyLevel& level = impl_->refiner->GetLevel(0);
    impl_->onFar.assign(std::size_t(level.GetNumFaces()), 0);
    std::vector<int> farFaces;
    for (int f = 0; f < level.GetNumFaces(); ++f) {
        if (farChoice != FarFaces::All && !bfrBuilderIsUnsafe(level, f)) continue;
        impl_->onFar[std::size_t(f)] = 1;
        farFaces.push_back(f);
    }
    if (!farFaces.empty())
        impl_->far = std::make_unique<FarLimitEvaluator>(desc, options, farFaces);
    buildEdges();

    impl_->factory = std::make_unique<ThreadSafeSurfaceFactory>(*impl_->refiner);
    impl_->surfaces.resize(std::size_t(level.GetNumFaces()));
    // Each face's surface into its slot: the same surfaces on any thread count.
    parallelFor(impl_->surfaces.size(), threads, [&](int, std::size_t f) {
        if (!impl_->onFar[f]) impl_->factory->InitVertexSurface(int(f), &impl_->surfaces[f]);
    });
    iaFarFaces += std::int64_t(farFaces.size());
    iaCageFaces += level.GetNumFaces();
    buildPatches();
    buildOwners();
}

SubdivisionMesh::~SubdivisionMesh() = default;

void SubdivisionMesh::buildEdges() {
    const osd::Far::TopologyLevel& level = impl_->refiner->GetLevel(0);
    const int regular = scheme_ == SubdivisionScheme::Loop ? 3 : 4;
    edgeVertices_.resize(std::size_t(2 * level.GetNumEdges()));
    sharedEdge_.resize(std::size_t(level.GetNumEdges()));
    std::unordered_map<std::uint64_t, int> firstWithEnds;
    for (int e = 0; e < level.GetNumEdges(); ++e) {
        auto v = level.GetEdgeVertices(e);
        edgeVertices_[std::size_t(2 * e)] = v[0];
        edgeVertices_[std::size_t(2 * e + 1)] = v[1];
        const int lo = std::min(v[0], v[1]), hi = std::max(v[0], v[1]);
        const std::uint64_t ends = std::uint64_t(std::uint32_t(lo)) << 32 | std::uint32_t(hi);
        sharedEdge_[std::size_t(e)] = lo == hi ? e : firstWithEnds.emplace(ends, e).first->second;
    }
    edgeNextToSubpatches_.assign(std::size_t(level.GetNumEdges()), false);
    faceVertices_.resize(std::size_t(level.GetNumFaces()));
    faceEdges_.resize(std::size_t(level.GetNumFaces()));
    for (int f = 0; f < level.GetNumFaces(); ++f) {
        auto fv = level.GetFaceVertices(f);
        auto fe = level.GetFaceEdges(f);
        faceVertices_[std::size_t(f)].assign(fv.begin(), fv.end());
        faceEdges_[std::size_t(f)].assign(fe.begin(), fe.end());
        if (fv.size() != regular)
            for (int e : fe) edgeNextToSubpatches_[std::size_t(sharedEdge(e))] = true;
    }
}

void SubdivisionMesh::buildPatches() {
    const int regular = scheme_ == SubdivisionScheme::Loop ? 3 : 4;
    for (std::size_t f = 0; f < faceVertices_.size(); ++f) {
        if (!impl_->hasSurface(f)) {  // hole, or no limit surface
            ++iaHoleFaces;
            continue;
        }
        const std::vector<int>& verts = faceVertices_[f];
        const std::vector<int>& edges = faceEdges_[f];
        const int n = int(verts.size());
        if (n == regular) {
            PatchInfo p;
            p.face = int(f);
            p.domain = n == 3 ? PatchDomain::Triangle : PatchDomain::Quad;
            for (int i = 0; i < n; ++i) {
                p.corners[i] = PointKey::make(PointKey::Vertex, verts[std::size_t(i)]);
                p.edgeSources[i] = {EdgeFactorSource::WholeCageEdge, edges[std::size_t(i)], -1};
            }
            patches_.push_back(p);
            continue;
        }
        for (int i = 0; i < n; ++i) {
            const int trailing = (i + n - 1) % n;
            PatchInfo p;
            p.face = int(f);
            p.subface = i;
            p.domain = PatchDomain::Quad;
            p.corners[0] = PointKey::make(PointKey::Vertex, verts[std::size_t(i)]);
            p.corners[1] = PointKey::make(PointKey::EdgeMidpoint, edges[std::size_t(i)]);
            p.corners[2] = PointKey::make(PointKey::FaceCentre, int(f));
            p.corners[3] = PointKey::make(PointKey::EdgeMidpoint, edges[std::size_t(trailing)]);
            p.edgeSources[0] = {EdgeFactorSource::HalfCageEdge, edges[std::size_t(i)], -1};
            p.edgeSources[1] = {EdgeFactorSource::Interior, edges[std::size_t(i)], int(f)};
            p.edgeSources[2] = {EdgeFactorSource::Interior, edges[std::size_t(trailing)], int(f)};
            p.edgeSources[3] = {EdgeFactorSource::HalfCageEdge, edges[std::size_t(trailing)], -1};
            patches_.push_back(p);
        }
    }
}

bool SubdivisionMesh::cageEdgeSpan(int patch, int edge, CageEdgeSpan& span) const {
    const PatchInfo& p = patches_[std::size_t(patch)];
    const EdgeFactorSource& source = p.edgeSources[edge];
    if (source.kind == EdgeFactorSource::Interior) return false;
    const PointKey a = p.corners[edge];
    const int lo = std::min(cageEdgeVertex(source.cageEdge, 0), cageEdgeVertex(source.cageEdge, 1));
    span.patch = patch;
    span.edge = edge;
    if (source.kind == EdgeFactorSource::WholeCageEdge) {
        span.start = 0;
        span.length = kCageEdgeOne;
        span.sameDirection = a.index() == lo;
        return true;
    }
    // Half of a cage edge: from (or to) the vertex end at `vertex`.
    const PointKey b = p.corners[(edge + 1) % p.cornerCount()];
    const int vertex = a.kind() == PointKey::Vertex ? a.index() : b.index();
    const bool fromLow = vertex == lo;
    span.start = fromLow ? 0 : kCageEdgeOne / 2;
    span.length = kCageEdgeOne / 2;
    // Canonical direction runs low -> high: in the low half from the vertex, in the high half
    // from the midpoint.
    span.sameDirection =
        fromLow ? a.kind() == PointKey::Vertex : a.kind() == PointKey::EdgeMidpoint;
    return true;
}

void SubdivisionMesh::buildOwners() {
    cageEdgeSpans_.assign(std::size_t(cageEdgeCount()), {});
    for (int pi = 0; pi < int(patches_.size()); ++pi) {
        const PatchInfo& p = patches_[std::size_t(pi)];
        const int n = p.cornerCount();
        for (int c = 0; c < n; ++c) {
            pointOwners_.emplace(p.corners[c].value, PointOwner{pi, c});
            CageEdgeSpan span;
            if (cageEdgeSpan(pi, c, span)) {
                cageEdgeSpans_[std::size_t(sharedEdge(p.edgeSources[c].cageEdge))].push_back(span);
                continue;
            }
            const PointKey a = p.corners[c], b = p.corners[(c + 1) % n];
            const auto key = std::minmax(a.value, b.value);
            edgeOwners_.emplace(std::make_pair(key.first, key.second),
                                EdgeOwner{pi, c, a.value <= b.value});
        }
    }
}

void patchCorner(PatchDomain domain, int corner, float uv[2]) {
    static constexpr float kQuad[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    static constexpr float kTri[3][2] = {{0, 0}, {1, 0}, {0, 1}};
    const float* c = domain == PatchDomain::Quad ? kQuad[corner] : kTri[corner];
    uv[0] = c[0];
    uv[1] = c[1];
}

void patchEdgePoint(PatchDomain domain, int edge, float s, float uv[2]) {
    float a[2], b[2];
    const int n = domain == PatchDomain::Quad ? 4 : 3;
    patchCorner(domain, edge, a);
    patchCorner(domain, (edge + 1) % n, b);
    // Exact for s a multiple of 2^-16: one of the two terms per coordinate is 0 or 1.
    for (int k = 0; k < 2; ++k) {
        if (a[k] == b[k])
            uv[k] = a[k];
        else
            uv[k] = a[k] < b[k] ? s : 1.0f - s;
    }
}

void SubdivisionMesh::faceCoord(const PatchInfo& patch, float u, float v, float faceUV[2]) const {
    if (patch.subface < 0) {
        faceUV[0] = u;
        faceUV[1] = v;
        return;
    }
    const float sub[2] = {u, v};
    impl_->parameterization(patch.face).ConvertNormalizedSubFaceToCoord(patch.subface, sub, faceUV);
}

int SubdivisionMesh::controlPointCount(int face) const {
    if (impl_->onFar[std::size_t(face)]) return int(impl_->far->controlPoints(face).size());
    return impl_->surfaces[std::size_t(face)].GetNumControlPoints();
}

void SubdivisionMesh::controlPointIndices(int face, std::vector<int>& out) const {
    if (impl_->onFar[std::size_t(face)]) {
        out = impl_->far->controlPoints(face);
        return;
    }
    const osd::Bfr::Surface<float>& surface = impl_->surfaces[std::size_t(face)];
    out.resize(std::size_t(surface.GetNumControlPoints()));
    if (!out.empty()) surface.GetControlPointIndices(out.data());
}

int SubdivisionMesh::farEvaluatedFaceCount() const {
    return int(std::count(impl_->onFar.begin(), impl_->onFar.end(), 1));
}

bool SubdivisionMesh::farEvaluated(int face) const {
    return impl_->onFar[std::size_t(face)] != 0;
}

void SubdivisionMesh::evaluateStencil(int face, const float faceUV[2], Stencil& out) const {
    if (impl_->onFar[std::size_t(face)]) {
        impl_->far->evaluate(face, faceUV, out);
        return;
    }
    const osd::Bfr::Surface<float>& surface = impl_->surfaces[std::size_t(face)];
    const std::size_t n = std::size_t(surface.GetNumControlPoints());
    out.position.resize(n);
    out.du.resize(n);
    out.dv.resize(n);
    out.controlPoints.resize(n);
    surface.GetControlPointIndices(out.controlPoints.data());
    surface.EvaluateStencil(faceUV, out.position.data(), out.du.data(), out.dv.data());
}

Vec3 SubdivisionMesh::applyStencil(int face, const Stencil& stencil,
                                   const std::vector<float>& weights,
                                   const std::vector<Vec3>& points) const {
    static_assert(sizeof(Vec3) == 3 * sizeof(float));
    Vec3 result(0);
    if (impl_->onFar[std::size_t(face)]) {
        for (std::size_t k = 0; k < weights.size(); ++k)
            result += weights[k] * points[std::size_t(stencil.controlPoints[k])];
        return result;
    }
    impl_->surfaces[std::size_t(face)].ApplyStencilFromMesh(
        weights.data(), &points.data()->x, osd::Bfr::Surface<float>::PointDescriptor(3), &result.x);
    return result;
}

void SubdivisionMesh::ownerOnCageEdge(int cageEdge, std::uint32_t k, std::uint32_t n,
                                      int& ownerPatch, float uv[2]) const {
    // Spans are in units of 2^-17 of the edge; compare k / n against them without rounding.
    const std::uint64_t position = std::uint64_t(k) * kCageEdgeOne;  // / n
    for (const CageEdgeSpan& span : spansOnCageEdge(cageEdge)) {
        if (position < std::uint64_t(span.start) * n ||
            position > std::uint64_t(span.start + span.length) * n)
            continue;
        // (k/n - start) / length, evaluated the same way whichever patch asks.
        const std::uint64_t numerator = position - std::uint64_t(span.start) * n;
        const double along = double(numerator) / (double(n) * double(span.length));
        ownerPatch = span.patch;
        const PatchInfo& o = patches_[std::size_t(span.patch)];
        const float a = float(along);
        patchEdgePoint(o.domain, span.edge, span.sameDirection ? a : 1.0f - a, uv);
        return;
    }
    throw std::logic_error("cage edge point without an owning patch");
}

void SubdivisionMesh::ownerOfEdgePoint(int patch, int edge, std::uint32_t s, const int segments[4],
                                       int& ownerPatch, float uv[2]) const {
    CageEdgeSpan span;
    if (!cageEdgeSpan(patch, edge, span)) {
        ownerOfInteriorEdgePoint(patch, edge, s, ownerPatch, uv);
        return;
    }
    const int cageEdge = patches_[std::size_t(patch)].edgeSources[edge].cageEdge;
    const int vertex = cageEdgeVertex(cageEdge, 0);
    if (vertex == cageEdgeVertex(cageEdge, 1)) {
        // A degenerate edge is sharp and both its ends are one sharp corner, so on the limit
        // surface all of it is that vertex's point; evaluated along the edge it would differ by
        // an ulp here and there and leave a slit.
        ownerOfPoint(PointKey::make(PointKey::Vertex, vertex), ownerPatch, uv);
        return;
    }
    const std::uint32_t canonical = span.sameDirection ? s : kCageEdgeOne - s;
    if (segments[edge] > 0) {
        // Integer partitioning: the point is the j-th of the edge's segments; name it by its
        // index on the whole cage edge, so half-edges and whole edges agree exactly.
        const std::uint32_t perSpan = std::uint32_t(segments[edge]);
        const std::uint32_t whole = span.length == kCageEdgeOne ? perSpan : 2 * perSpan;
        const auto j =
            std::uint32_t((std::uint64_t(canonical) * perSpan + kCageEdgeOne / 2) / kCageEdgeOne);
        const std::uint32_t k = (span.start == 0 ? 0 : whole / 2) + j;
        ownerOnCageEdge(cageEdge, k, whole, ownerPatch, uv);
        return;
    }
    ownerOnCageEdge(cageEdge, toCageEdge(span, s), kCageEdgeOne, ownerPatch, uv);
}

void SubdivisionMesh::ownerOfInteriorEdgePoint(int patch, int edge, std::uint32_t s,
                                               int& ownerPatch, float uv[2]) const {
    const PatchInfo& p = patches_[std::size_t(patch)];
    const PointKey a = p.corners[edge], b = p.corners[(edge + 1) % p.cornerCount()];
    const auto key = std::minmax(a.value, b.value);
    const EdgeOwner& owner = edgeOwners_.at({key.first, key.second});
    const bool sameAsCanonical = a.value <= b.value;
    const std::uint32_t canonical = sameAsCanonical ? s : kCageEdgeOne - s;
    const std::uint32_t ownerS = owner.sameDirection ? canonical : kCageEdgeOne - canonical;
    ownerPatch = owner.patch;
    const PatchInfo& o = patches_[std::size_t(owner.patch)];
    patchEdgePoint(o.domain, owner.edge, float(ownerS) / float(kCageEdgeOne), uv);
}

std::uint32_t SubdivisionMesh::toCageEdge(const CageEdgeSpan& span, std::uint32_t s) {
    const std::uint32_t along = span.sameDirection ? s : kCageEdgeOne - s;
    return std::uint32_t(span.start + std::uint64_t(along) * span.length / kCageEdgeOne);
}

std::uint32_t SubdivisionMesh::fromCageEdge(const CageEdgeSpan& span, std::uint32_t w) {
    const auto along = std::uint32_t(std::uint64_t(w - span.start) * kCageEdgeOne / span.length);
    return span.sameDirection ? along : kCageEdgeOne - along;
}

void SubdivisionMesh::ownerOfCorner(int patch, int corner, const int segments[4], int& ownerPatch,
                                    float uv[2]) const {
    const PatchInfo& p = patches_[std::size_t(patch)];
    const PointKey key = p.corners[corner];
    if (key.kind() == PointKey::EdgeMidpoint) {
        // A cage-edge midpoint is a point on that cage edge: the end of the half-edge before this
        // corner or the start of the one after it.
        const int before = (corner + p.cornerCount() - 1) % p.cornerCount();
        if (p.edgeSources[before].kind == EdgeFactorSource::HalfCageEdge)
            ownerOfEdgePoint(patch, before, kCageEdgeOne, segments, ownerPatch, uv);
        else
            ownerOfEdgePoint(patch, corner, 0, segments, ownerPatch, uv);
        return;
    }
    ownerOfPoint(key, ownerPatch, uv);
}

void SubdivisionMesh::ownerOfPoint(PointKey key, int& ownerPatch, float uv[2]) const {
    const PointOwner& owner = pointOwners_.at(key.value);
    ownerPatch = owner.patch;
    patchCorner(patches_[std::size_t(owner.patch)].domain, owner.corner, uv);
}

}  // namespace patchsim
