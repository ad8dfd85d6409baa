#pragma once
// The per-patch hierarchy of linearly moving boxes (US 8,791,945).
//
// Representation
// --------------
// A complete binary tree in heap order: node i has children 2i+1 and 2i+2, the root is node 0,
// and all leaves sit on the bottom level `depth`, so leaf j is node (2^depth - 1 + j) and the
// leaves' bit mask is laid out in memory order (bit j for leaf j; at most 64 leaves). Each node
// holds an LBBox (box at t=0 and at t=1). Leaves hold up to `leafSize` triangles, listed in
// `triangles` from `leafBegin[j]` to `leafBegin[j+1]`; beside them, each leaf's distinct vertices
// and its triangles' corners among those (LeafVertexTable).
//
// Built from the tessellator's implicit grid: triangles are ordered by their domain centroids,
// split in half by u at even levels and by v at odd levels, so each subtree covers a compact
// region of the patch's domain. A patch with more triangles than a group may hold is first split
// the same way into groups, one hierarchy per group (`splitIntoGroups`). `hierarchyOrder` makes
// both orders at once, so the rasterizer builds each hierarchy from its group's list as it stands
// (`buildOrdered`) and shares the list between patches of one pattern (hierarchy_orders.h).

#include <cstdint>
#include <vector>

#include "core/lbbox.h"
#include "core/number_format.h"
#include "core/rasterizer_options.h"
#include "rasterizer/common/moving_mesh.h"

namespace patchsim {

inline constexpr int kMaxHierarchyDepth = 6;  // 2^6 = kMaxLeavesPerHierarchy leaves
static_assert((1 << kMaxHierarchyDepth) == kMaxLeavesPerHierarchy);

// Each leaf's distinct vertices (mesh vertex indices) from vertexBegin[j], and its triangles'
// corners among them, three per triangle in build order: for one group, made by
// leafVertexTable. It depends only on the index triples, so patches of one tessellation pattern
// share it (HierarchyOrder).
struct LeafVertexTable {
    std::vector<std::uint32_t> vertices, vertexBegin;
    std::vector<std::uint8_t> corners;
};

// How far outside its exact triangle, in camera-space units, a ray-triangle test in `format`
// may claim a hit whose vertices lie within `distance` of the ray's origin
// (watertight_triangle_rounded.h). In a float format four units in the last place at that
// distance (|x| + |y| + |z| of the box's farthest corner plus the lens): the coordinates are
// rounded three times on their way to the sheared frame, each by at most half a unit, and an
// edge function's rounding moves its edge by about as much again; the depth's roundings are
// relative. In fixed point, whose unit is absolute, 64 units times 1 + distance: the shear
// factors' rounding is multiplied by the coordinates, and sz = 1 / d[kz] of an oblique lens ray
// keeps only a few significant bits. Margins, not a proof (a sliver's edge function is
// ill-conditioned): each is twice the smallest power of two under which the hard-case suite
// still gives the reference's samples (1 unit fails the 50-unit aperture case in bf16, 2 holds;
// 16 fails it in fixed16.8, 32 holds).
float triangleTestReach(const NumberFormat& format, float distance);

class PatchHierarchy {
  public:
    // `triangles` are indices into `mesh` triangles (one group).
    void build(const MovingMesh& mesh, const std::uint32_t* triangles, std::size_t count,
               int leafSize);
    // The same tree from triangles already in the order `build` puts them in (a group of
    // hierarchyOrder): the boxes, and the leaves' vertex table: `shared` (the group's in its
    // HierarchyOrder, which must outlive this hierarchy) or, without one, made here.
    void buildOrdered(const MovingMesh& mesh, const std::uint32_t* triangles, std::size_t count,
                      int leafSize, const LeafVertexTable* shared = nullptr);

    int depth() const { return depth_; }
    int leafCount() const { return 1 << depth_; }
    int nodeCount() const { return int(nodes_.size()); }
    const LBBox& node(int i) const { return nodes_[std::size_t(i)]; }
    static int firstLeaf(int depth) { return (1 << depth) - 1; }
    bool isLeaf(int node) const { return node >= firstLeaf(depth_); }
    int levelOf(int node) const;
    // Triangles of leaf j.
    const std::uint32_t* leafTriangles(int leaf, std::size_t& count) const {
        const std::uint32_t b = leafBegin_[std::size_t(leaf)],
                            e = leafBegin_[std::size_t(leaf) + 1];
        count = e - b;
        return triangles_.data() + b;
    }
    // Leaf j's distinct vertices (mesh vertex indices, `count` of them; a tessellated grid's
    // triangles share most corners), and its triangles' corners as indices into them, three per
    // triangle of leafTriangles(j). The ray kernels move each vertex to a vector of rays once,
    // not once per corner; the table is made once per tessellation pattern (or per build, without
    // a shared one), not at each of a leaf's many visits.
    const std::uint32_t* leafVertices(int leaf, std::size_t& count) const {
        const LeafVertexTable& t = leafTable();
        const std::uint32_t b = t.vertexBegin[std::size_t(leaf)],
                            e = t.vertexBegin[std::size_t(leaf) + 1];
        count = e - b;
        return t.vertices.data() + b;
    }
    // Where leaf j's distinct vertices start among all leaves' (vertexBegin[j]).
    std::uint32_t leafVertexOffset(int leaf) const {
        return leafTable().vertexBegin[std::size_t(leaf)];
    }
    // All leaves' distinct vertices together.
    std::size_t leafVertexTotal() const { return leafTable().vertexBegin.back(); }
    const std::uint8_t* leafCorners(int leaf) const {
        return leafTable().corners.data() + 3 * std::size_t(leafBegin_[std::size_t(leaf)]);
    }
    // Bytes the hierarchy would occupy on chip: node boxes plus leaf triangle lists. (The vertex
    // table above is how the simulator lays out a leaf for its SIMD kernels, not modelled
    // storage: the triangle lists already say which vertices a leaf reads.)
    // Node boxes at nodeFormat()'s storage bits.
    std::size_t bytes() const;

    // Stores every node's box in `format` (issue 35): each lower bound rounded down and each
    // upper bound up (Rounding::Down), so the stored box holds the built one at both shutter ends
    // and, the blend being monotone in its ends, at every time between: the tile and ray tests
    // reject nothing more than with the exact boxes, they only accept more. A bound a fixed-point
    // format cannot hold opens to the largest float on its side (not to infinity, which times a
    // zero slab weight at t = 0 or 1 is NaN). `Rounding::Nearest` is the naive
    // variant, kept for the test that shows it loses samples; it is no option of the render.
    void storeNodesIn(const NumberFormat& format, Rounding rounding = Rounding::Down);
    // Grows every leaf's box (and so every node's) by the reach of a ray-triangle test in
    // `triangleFormat` (rasterizer.triangle_format; nothing for fp32): triangleTestReach of the
    // box's largest distance from the eye plus the lens. A rounded test claims hits up to that
    // far outside its exact triangle and in front of its exact depth, so every culling step
    // (bins, tile planes, time intervals, ray-box tests, z culling), which all derive from these
    // boxes, keeps each sample the rounded test would give, as the reference gives it.
    // Only the leaves set in `leaves` (bit j: leaf j) grow.
    void growForTriangleTest(const NumberFormat& triangleFormat, float lensRadius,
                             std::uint64_t leaves = ~std::uint64_t(0));
    const NumberFormat& nodeFormat() const { return nodeFormat_; }

  private:
    int depth_ = 0;
    NumberFormat nodeFormat_;
    std::vector<LBBox> nodes_;
    std::vector<std::uint32_t> triangles_;
    std::vector<std::uint32_t> leafBegin_;
    // A pattern's table is shared, not copied: at a million triangles a copy per hierarchy
    // cost more than the leaf visits it saves (docs/PERFORMANCE.md).
    const LeafVertexTable* sharedTable_ = nullptr;
    LeafVertexTable ownTable_;
    const LeafVertexTable& leafTable() const { return sharedTable_ ? *sharedTable_ : ownTable_; }
};

// `box` as PatchHierarchy::storeNodesIn stores a node in `format`: with Rounding::Down each
// lower bound rounded down and each upper bound up (a fixed-point bound out of range opened to
// the largest float), with Rounding::Nearest every bound to its nearest value (the naive variant).
LBBox storedIn(const LBBox& box, const NumberFormat& format, Rounding rounding);

// The leaf vertex table of a group's triangles in build order (the hierarchy buildOrdered makes).
LeafVertexTable leafVertexTable(const MovingMesh& mesh, const std::uint32_t* triangles,
                                std::size_t count, int leafSize);

// Orders all triangles of a mesh by the implicit-grid split and cuts them into groups of at most
// `maxPerGroup` (a power-of-two number of groups). `groupBegin` gets groups+1 offsets into `order`.
void splitIntoGroups(const MovingMesh& mesh, int maxPerGroup, std::vector<std::uint32_t>& order,
                     std::vector<std::uint32_t>& groupBegin);

// A mesh's triangles split into groups (splitIntoGroups), each group in the order its hierarchy
// is built from (PatchHierarchy::build). It depends only on the mesh's domain positions and index
// triples, its tessellation pattern, so meshes of one pattern have one order.
struct HierarchyOrder {
    std::vector<std::uint32_t> triangles;     // group after group
    std::vector<std::uint32_t> groupBegin;    // where each group starts, then the end
    std::vector<LeafVertexTable> leafTables;  // per group
};
HierarchyOrder hierarchyOrder(const MovingMesh& mesh, int maxPerGroup, int leafSize);

}  // namespace patchsim
