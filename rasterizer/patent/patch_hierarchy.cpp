#include "rasterizer/patent/patch_hierarchy.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

namespace patchsim {

namespace {

// A float's bits as an unsigned integer in the same order (negative values reversed below the
// positive ones), so keys compare as integers.
std::uint32_t orderedBits(float f) {
    const std::uint32_t bits = std::bit_cast<std::uint32_t>(f);
    return bits & 0x80000000u ? ~bits : bits | 0x80000000u;
}

// A triangle with its domain centroid, the key the implicit-grid split orders by.
struct Keyed {
    std::uint32_t centroid[2];  // orderedBits of u and v
    std::uint32_t triangle;
    // Centroid along `axis`, ties by index.
    std::uint64_t key(int axis) const { return std::uint64_t(centroid[axis]) << 32 | triangle; }
};

Keyed keyed(const MovingMesh& mesh, std::uint32_t triangle) {
    const std::uint32_t* v = &mesh.indices[3 * std::size_t(triangle)];
    const Vec2 c = (mesh.domain[v[0]] + mesh.domain[v[1]] + mesh.domain[v[2]]) / 3.0f;
    return {{orderedBits(c.x), orderedBits(c.y)}, triangle};
}

// Splits [begin, end) at its middle by centroid u (even level) or v (odd level), ties by index,
// and recurses on the two halves down to `levels` splits. Only the halves' contents matter (a
// leaf's triangles are tested in any order), so a partition does the work of a sort.
void orderRange(Keyed* begin, Keyed* end, int level, int levels) {
    if (levels == 0 || end - begin <= 1) return;
    const int axis = level & 1;
    Keyed* mid = begin + (end - begin + 1) / 2;
    std::nth_element(begin, mid, end,
                     [axis](const Keyed& a, const Keyed& b) { return a.key(axis) < b.key(axis); });
    orderRange(begin, mid, level + 1, levels - 1);
    orderRange(mid, end, level + 1, levels - 1);
}

// `triangles` ordered by the implicit-grid split of `levels` levels.
void orderTriangles(const MovingMesh& mesh, std::uint32_t* triangles, std::size_t count,
                    int levels) {
    std::vector<Keyed> keys(count);
    for (std::size_t i = 0; i < count; ++i) keys[i] = keyed(mesh, triangles[i]);
    orderRange(keys.data(), keys.data() + count, 0, levels);
    for (std::size_t i = 0; i < count; ++i) triangles[i] = keys[i].triangle;
}

// [begin, end) halved `levels` times the way orderRange splits it: the ends of its 2^levels
// ranges, left to right, from `ends` on.
std::uint32_t* halvedEnds(std::size_t begin, std::size_t end, int levels, std::uint32_t* ends) {
    if (levels == 0) {
        *ends = std::uint32_t(end);
        return ends + 1;
    }
    const std::size_t mid = begin + (end - begin + 1) / 2;
    return halvedEnds(mid, end, levels - 1, halvedEnds(begin, mid, levels - 1, ends));
}

int ceilLog2(std::size_t n) {
    int l = 0;
    while ((std::size_t(1) << l) < n) ++l;
    return l;
}

int depthFor(std::size_t count, int leafSize) {
    const std::size_t leavesNeeded = (count + std::size_t(leafSize) - 1) / std::size_t(leafSize);
    return std::min(ceilLog2(std::max<std::size_t>(leavesNeeded, 1)), kMaxHierarchyDepth);
}

}  // namespace

void splitIntoGroups(const MovingMesh& mesh, int maxPerGroup, std::vector<std::uint32_t>& order,
                     std::vector<std::uint32_t>& groupBegin) {
    const std::size_t n = mesh.triangleCount();
    order.resize(n);
    for (std::size_t i = 0; i < n; ++i) order[i] = std::uint32_t(i);
    const int levels =
        ceilLog2((n + std::size_t(maxPerGroup) - 1) / std::size_t(std::max(1, maxPerGroup)));
    orderTriangles(mesh, order.data(), n, levels);
    // The same halving as orderRange, so group g is the g-th range at depth `levels`.
    groupBegin.assign((std::size_t(1) << levels) + 1, 0);
    halvedEnds(0, n, levels, groupBegin.data() + 1);
}

int PatchHierarchy::levelOf(int node) const {
    int level = 0;
    while (node >= (1 << (level + 1)) - 1) ++level;
    return level;
}

HierarchyOrder hierarchyOrder(const MovingMesh& mesh, int maxPerGroup, int leafSize) {
    HierarchyOrder order;
    splitIntoGroups(mesh, maxPerGroup, order.triangles, order.groupBegin);
    for (std::size_t g = 0; g + 1 < order.groupBegin.size(); ++g) {
        const std::size_t begin = order.groupBegin[g], count = order.groupBegin[g + 1] - begin;
        orderTriangles(mesh, order.triangles.data() + begin, count, depthFor(count, leafSize));
        order.leafTables.push_back(
            leafVertexTable(mesh, order.triangles.data() + begin, count, leafSize));
    }
    return order;
}

void PatchHierarchy::build(const MovingMesh& mesh, const std::uint32_t* triangles,
                           std::size_t count, int leafSize) {
    std::vector<std::uint32_t> ordered(triangles, triangles + count);
    orderTriangles(mesh, ordered.data(), count, depthFor(count, leafSize));
    buildOrdered(mesh, ordered.data(), count, leafSize);
}

void PatchHierarchy::buildOrdered(const MovingMesh& mesh, const std::uint32_t* triangles,
                                  std::size_t count, int leafSize, const LeafVertexTable* shared) {
    depth_ = depthFor(count, leafSize);
    nodeFormat_ = NumberFormat::fp32();
    triangles_.assign(triangles, triangles + count);
    const int leaves = 1 << depth_;
    nodes_.assign(std::size_t(2 * leaves - 1), LBBox{});
    leafBegin_.assign(std::size_t(leaves) + 1, 0);
    // Leaf ranges follow orderRange's halving.
    halvedEnds(0, count, depth_, leafBegin_.data() + 1);
    const int first = firstLeaf(depth_);
    for (int j = 0; j < leaves; ++j) {
        LBBox& box = nodes_[std::size_t(first + j)];
        for (std::size_t k = leafBegin_[std::size_t(j)]; k < leafBegin_[std::size_t(j) + 1]; ++k)
            box.extend(mesh.triangleBounds(triangles_[k]));
    }
    for (int i = first - 1; i >= 0; --i) {
        nodes_[std::size_t(i)] = nodes_[std::size_t(2 * i + 1)];
        nodes_[std::size_t(i)].extend(nodes_[std::size_t(2 * i + 2)]);
    }
    sharedTable_ = shared;
    if (shared)
        ownTable_ = {};
    else
        ownTable_ = leafVertexTable(mesh, triangles, count, leafSize);
}

LeafVertexTable leafVertexTable(const MovingMesh& mesh, const std::uint32_t* triangles,
                                std::size_t count, int leafSize) {
    static_assert(3 * kMaxLeafTriangles <= 256, "a corner's index must fit a byte");
    const int depth = depthFor(count, leafSize);
    std::vector<std::uint32_t> leafEnd(std::size_t(1) << depth);
    halvedEnds(0, count, depth, leafEnd.data());
    LeafVertexTable table;
    table.vertices.reserve(3 * count);
    table.vertexBegin.assign(leafEnd.size() + 1, 0);
    table.corners.resize(3 * count);
    std::size_t k = 0;
    for (std::size_t j = 0; j < leafEnd.size(); ++j) {
        const std::size_t begin = table.vertices.size();
        for (; k < leafEnd[j]; ++k)
            for (std::size_t corner = 0; corner < 3; ++corner) {
                const std::uint32_t v = mesh.indices[3 * std::size_t(triangles[k]) + corner];
                std::size_t at = begin;
                while (at < table.vertices.size() && table.vertices[at] != v) ++at;
                if (at == table.vertices.size()) table.vertices.push_back(v);
                table.corners[3 * k + corner] = std::uint8_t(at - begin);
            }
        table.vertexBegin[j + 1] = std::uint32_t(table.vertices.size());
    }
    return table;
}

namespace {

// `x` stored in `format`, toward `outward` (-1 down, +1 up), or with `nearest` to the nearest.
float stored(float x, const NumberFormat& format, int outward, bool nearest) {
    if (!std::isfinite(x)) return x;  // an empty leaf's box stays empty
    // Beyond a fixed-point range the bound opens to the largest float, not to infinity: the
    // ray-box slabs weigh a box's two ends by (1-t) and t, and infinity times a zero weight at
    // t = 0 or 1 is NaN, which would reject the ray. A lower bound can only open downward and
    // an upper one upward, so no slab adds the two infinities its sums could overflow to.
    if (!representable(x, format)) return float(outward) * std::numeric_limits<float>::max();
    return roundTo(x, format,
                   nearest       ? Rounding::Nearest
                   : outward < 0 ? Rounding::Down
                                 : Rounding::Up);
}

void storeBox(Box3& box, const NumberFormat& format, bool nearest) {
    for (int axis = 0; axis < 3; ++axis) {
        box.lower[axis] = stored(box.lower[axis], format, -1, nearest);
        box.upper[axis] = stored(box.upper[axis], format, +1, nearest);
    }
}

}  // namespace

LBBox storedIn(const LBBox& box, const NumberFormat& format, Rounding rounding) {
    LBBox stored = box;
    if (format == NumberFormat::fp32()) return stored;
    storeBox(stored.bounds0, format, rounding == Rounding::Nearest);
    storeBox(stored.bounds1, format, rounding == Rounding::Nearest);
    return stored;
}

float triangleTestReach(const NumberFormat& format, float distance) {
    if (format == NumberFormat::fp32()) return 0.0f;
    const double unit = unitInLastPlace(distance, format);
    if (format.kind == NumberFormat::Kind::Fixed) return float(64.0 * unit * (1.0 + distance));
    return float(4.0 * unit);
}

namespace {

// The largest |x| + |y| + |z| over a box's corners: a bound on their distance from the eye.
float farthestCorner(const Box3& box) {
    const Vec3 m = glm::max(glm::abs(box.lower), glm::abs(box.upper));
    return m.x + m.y + m.z;
}

void grow(Box3& box, float by) {
    box.lower -= Vec3(by);
    box.upper += Vec3(by);
}

}  // namespace

void PatchHierarchy::growForTriangleTest(const NumberFormat& triangleFormat, float lensRadius,
                                         std::uint64_t leaves) {
    if (triangleFormat == NumberFormat::fp32() || leaves == 0) return;
    const int first = firstLeaf(depth_);
    for (int j = 0; j < leafCount(); ++j) {
        LBBox& box = nodes_[std::size_t(first + j)];
        if (box.bounds0.empty() || !(leaves >> j & 1)) continue;
        const float distance =
            std::max(farthestCorner(box.bounds0), farthestCorner(box.bounds1)) + lensRadius;
        // Beyond the format's range the reach is infinite: open to the largest float instead,
        // as stored() does (infinity times a zero slab weight would be NaN).
        const float reach = std::min(triangleTestReach(triangleFormat, distance),
                                     std::numeric_limits<float>::max());
        grow(box.bounds0, reach);
        grow(box.bounds1, reach);
    }
    for (int i = first - 1; i >= 0; --i) {
        nodes_[std::size_t(i)] = nodes_[std::size_t(2 * i + 1)];
        nodes_[std::size_t(i)].extend(nodes_[std::size_t(2 * i + 2)]);
    }
}

void PatchHierarchy::storeNodesIn(const NumberFormat& format, Rounding rounding) {
    nodeFormat_ = format;
    if (format == NumberFormat::fp32()) return;
    for (LBBox& node : nodes_) node = storedIn(node, format, rounding);
}

std::size_t PatchHierarchy::bytes() const {
    constexpr std::size_t kBoundsPerNode = 12;  // two boxes of two corners of three coordinates
    return nodes_.size() * kBoundsPerNode * std::size_t(storageBits(nodeFormat_)) / 8 +
           triangles_.size() * sizeof(std::uint16_t) + leafBegin_.size() * sizeof(std::uint16_t);
}

}  // namespace patchsim
