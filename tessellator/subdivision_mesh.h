#pragma once
// The input assembler's view of a control cage: OpenSubdiv topology, limit surfaces per face,
// and the list of patches the rest of the pipeline streams.
//
// Representation
// --------------
// Topology is a Far::TopologyRefiner built from the cage (Far::TopologyDescriptor), with creases,
// corners, holes and boundary interpolation from the OBJ tags. One Bfr::Surface<float> per base
// face (made with Bfr::RefinerSurfaceFactory when the mesh is built, on several threads through a
// locked cache, so evaluation afterwards is const and thread-safe) gives the limit stencils; the
// few faces that OpenSubdiv 3.5.0's Bfr cannot build safely are evaluated on Far's patch table
// instead (tessellator/far_limit_evaluator).
//
// A patch is one tessellation domain. A face of the scheme's regular size (4 for Catmull-Clark and
// bilinear, 3 for Loop) is one patch. Any other Catmull-Clark face of N sides is N quad
// sub-patches, as Bfr::Parameterization divides it: sub-patch i has its (0,0) corner at the face's
// vertex i, (1,0) at the midpoint of edge i, (1,1) at the face centre and (0,1) at the midpoint of
// edge i-1.
//
// To make shared edges watertight, a point that several patches share is evaluated once, on its
// "owner" (the lowest-numbered patch that has it), at the owner's coordinates, so every patch gets
// the same bits. Points on a cage edge are named by the edge and their parameter along it (from the
// lower-numbered vertex: k / n, with n the whole edge's segment count under integer partitioning,
// or in units of 2^-17 for fractional partitioning, so the halves an N-gon's sub-patches see are
// named exactly as the whole edge's points);
// other corners (cage vertices, face centres) by a PointKey; interior sub-patch edges by their two
// corner keys.
//
// A cage edge, for naming its points, is a pair of cage vertices. Far gives a face that uses one
// pair twice (it repeats a vertex) a second edge with the same ends, which no other face shares;
// yet both are one curve of the limit surface, since such edges are non-manifold, hence sharp, and
// end in sharp corners (Bfr sharpens a vertex with duplicate edges). So every Far edge takes its
// points, owner and factor from the lowest-numbered edge with its two vertices (`sharedEdge`).
// A degenerate edge (both ends one vertex) is sharp between two sharp corners at that vertex, so
// on the limit surface it is the vertex's point: its points are named as the vertex.
//
// Patch edges also carry where their tessellation factor comes from: a whole cage edge, half a
// cage edge (the sub-patches of an N-gon; factor halved), or an interior sub-patch edge.

#include <cstdint>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/obj_reader.h"
#include "core/scene.h"
#include "tessellator/limit_stencil.h"

namespace patchsim {

enum class PatchDomain : std::uint8_t { Quad, Triangle };

struct PointKey {
    enum Kind : std::uint8_t { Vertex, EdgeMidpoint, FaceCentre };
    std::uint64_t value = 0;  // kind in the top bits, index below

    static PointKey make(Kind kind, int index) {
        return {(std::uint64_t(kind) << 32) | std::uint32_t(index)};
    }
    Kind kind() const { return Kind(value >> 32); }
    int index() const { return int(value & 0xffffffffu); }
    bool operator==(const PointKey&) const = default;
    bool operator<(const PointKey& o) const { return value < o.value; }
};

// How a patch edge gets its tessellation factor.
struct EdgeFactorSource {
    enum Kind : std::uint8_t { WholeCageEdge, HalfCageEdge, Interior };
    Kind kind = WholeCageEdge;
    int cageEdge = -1;  // WholeCageEdge, HalfCageEdge
    int face = -1;      // Interior: the N-gon (edge from a cage-edge midpoint to its centre)
};

struct PatchInfo {
    int face = -1;
    int subface = -1;  // -1 when the face is the patch
    PatchDomain domain = PatchDomain::Quad;
    int cornerCount() const { return domain == PatchDomain::Quad ? 4 : 3; }
    PointKey corners[4];
    EdgeFactorSource edgeSources[4];  // patch edge i runs from corner i to corner i+1
};

class SubdivisionMesh {
  public:
    // Throws InputError (naming `path`) when OpenSubdiv rejects the topology or the scheme
    // does not fit the faces (Loop needs triangles).
    // Which faces Far's patch table evaluates: only those Bfr 3.5.0 cannot build (the default), or
    // every face (an independent evaluation of the same surface, for tests).
    // The faces' Bfr surfaces are built on `threads` (the most costly part: a creased cage's
    // irregular faces take a fraction of a millisecond each).
    enum class FarFaces : std::uint8_t { OnlyUnsafeForBfr, All };
    SubdivisionMesh(const Cage& cage, SubdivisionScheme scheme, const std::string& path,
                    FarFaces farFaces = FarFaces::OnlyUnsafeForBfr, int threads = 1);
    ~SubdivisionMesh();
    SubdivisionMesh(const SubdivisionMesh&) = delete;
    SubdivisionMesh& operator=(const SubdivisionMesh&) = delete;

    const std::vector<PatchInfo>& patches() const { return patches_; }
    int cageEdgeCount() const { return static_cast<int>(edgeVertices_.size() / 2); }
    int cageEdgeVertex(int edge, int end) const {
        return edgeVertices_[std::size_t(2 * edge + end)];
    }
    // The lowest-numbered Far edge with the same two vertices (`edge` itself when it is the only
    // one, or degenerate).
    int sharedEdge(int edge) const { return sharedEdge_[std::size_t(edge)]; }
    // True when the cage edge (or another with its vertices) borders a face that is split into
    // sub-patches.
    bool cageEdgeNextToSubpatches(int edge) const {
        return edgeNextToSubpatches_[std::size_t(sharedEdge(edge))];
    }
    const std::vector<int>& faceVertices(int face) const {
        return faceVertices_[std::size_t(face)];
    }

    // Control points of a face's limit surface (what a hull shader would read for the patch).
    int controlPointCount(int face) const;
    // Their cage vertex indices, in the order the surface's stencils use them.
    void controlPointIndices(int face, std::vector<int>& out) const;

    // Face-level (u,v) of the Bfr parameterization for a patch-local domain point.
    void faceCoord(const PatchInfo& patch, float u, float v, float faceUV[2]) const;

    using Stencil = LimitStencil;
    // Limit stencil of a face at face-level (u,v); reuses the buffers in `out`.
    void evaluateStencil(int face, const float faceUV[2], Stencil& out) const;
    // Applies one weight set of `stencil` (its position, du or dv) to a control-point set.
    Vec3 applyStencil(int face, const Stencil& stencil, const std::vector<float>& weights,
                      const std::vector<Vec3>& points) const;
    // Faces evaluated on Far's patch table (see far_limit_evaluator.h), for reports and tests.
    int farEvaluatedFaceCount() const;
    bool farEvaluated(int face) const;

    // The owner of a point on patch `patch`'s local edge `edge` at local parameter `s` (units of
    // 2^-17, from the edge's start corner): patch index and that patch's local (u,v).
    // `segments[e]` is the integer segment count of each patch edge under integer or pow2
    // partitioning (points then sit at k/N and are named by k), or 0 for fractional modes (points
    // are named by their fixed-point parameter).
    void ownerOfEdgePoint(int patch, int edge, std::uint32_t s, const int segments[4],
                          int& ownerPatch, float uv[2]) const;
    void ownerOfCorner(int patch, int corner, const int segments[4], int& ownerPatch,
                       float uv[2]) const;

    // A patch edge that lies on a cage edge covers [start, start + length] of the cage edge's
    // canonical parameter (from its lower-numbered vertex), in units of 2^-17.
    struct CageEdgeSpan {
        int patch;
        int edge;
        std::uint32_t start;
        std::uint32_t length;
        bool sameDirection;  // the patch edge runs in the canonical direction
    };
    // False for an edge inside an N-gon (between two of its sub-patches).
    bool cageEdgeSpan(int patch, int edge, CageEdgeSpan& span) const;
    // Every patch edge on a cage edge (or on another with its vertices), by increasing patch index.
    const std::vector<CageEdgeSpan>& spansOnCageEdge(int cageEdge) const {
        return cageEdgeSpans_[std::size_t(sharedEdge(cageEdge))];
    }
    // A patch-edge parameter (units of 2^-17) as a cage-edge parameter, and back.
    static std::uint32_t toCageEdge(const CageEdgeSpan& span, std::uint32_t s);
    static std::uint32_t fromCageEdge(const CageEdgeSpan& span, std::uint32_t w);

    SubdivisionScheme scheme() const { return scheme_; }

  private:
    struct Impl;
    void buildEdges();
    void buildPatches();
    void buildOwners();

    SubdivisionScheme scheme_;
    std::unique_ptr<Impl> impl_;
    std::vector<PatchInfo> patches_;
    std::vector<int> edgeVertices_;
    std::vector<int> sharedEdge_;
    std::vector<bool> edgeNextToSubpatches_;  // by shared edge
    std::vector<std::vector<int>> faceVertices_;
    std::vector<std::vector<int>> faceEdges_;

    struct EdgeOwner {
        int patch;
        int edge;
        bool sameDirection;  // the owner's edge runs in the same corner order
    };
    struct PointOwner {
        int patch;
        int corner;
    };
    struct KeyPairHash {
        std::size_t operator()(const std::pair<std::uint64_t, std::uint64_t>& k) const {
            return std::hash<std::uint64_t>()(k.first * 0x9e3779b97f4a7c15ull ^ k.second);
        }
    };
    // A point on an edge between two sub-patches of one N-gon.
    void ownerOfInteriorEdgePoint(int patch, int edge, std::uint32_t s, int& ownerPatch,
                                  float uv[2]) const;
    // A cage vertex or face centre.
    void ownerOfPoint(PointKey key, int& ownerPatch, float uv[2]) const;
    // The point at k / n along a cage edge (canonical direction), n the whole edge's segments.
    void ownerOnCageEdge(int cageEdge, std::uint32_t k, std::uint32_t n, int& ownerPatch,
                         float uv[2]) const;
    // Patch edges on each shared edge, by increasing patch index (empty for the other edges).
    std::vector<std::vector<CageEdgeSpan>> cageEdgeSpans_;
    // Interior sub-patch edges (between sub-patches of one N-gon), keyed by their corner keys.
    std::unordered_map<std::pair<std::uint64_t, std::uint64_t>, EdgeOwner, KeyPairHash> edgeOwners_;
    std::unordered_map<std::uint64_t, PointOwner> pointOwners_;
};

// Local (u,v) of the point at parameter s (in [0,1]) along a patch's local edge.
void patchEdgePoint(PatchDomain domain, int edge, float s, float uv[2]);
// Local (u,v) of a patch corner.
void patchCorner(PatchDomain domain, int corner, float uv[2]);

}  // namespace patchsim
