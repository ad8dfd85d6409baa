// The ray kernels, compiled once per SIMD target (Highway's foreach_target re-includes this file).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "rasterizer/patent/ray_stream.cpp"
#include "rasterizer/patent/ray_stream.h"

#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>

#include <bit>
#include <cstdint>
#include <limits>

#include "rasterizer/common/conservative_margins.h"
#include "rasterizer/common/watertight_triangle_rounded.h"
#include "rasterizer/common/z_culling.h"
#include "rasterizer/patent/moving_box_ray_rounded.h"

HWY_BEFORE_NAMESPACE();
namespace patchsim {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using DF = hn::CappedTag<float, kMaxLanes>;
using DI = hn::RebindToSigned<DF>;
using DU = hn::RebindToUnsigned<DF>;
using VF = hn::Vec<DF>;
using VI = hn::Vec<DI>;
using VU = hn::Vec<DU>;
using MF = hn::Mask<DF>;

HWY_INLINE MF maskOf(DF d, std::uint16_t bits) {
    const std::uint8_t bytes[8] = {std::uint8_t(bits & 0xffu), std::uint8_t(bits >> 8)};
    return hn::LoadMaskBits(d, bytes);
}

HWY_INLINE std::uint16_t bitsOf(DF d, MF m) {
    std::uint8_t bytes[8] = {};
    hn::StoreMaskBits(d, m, bytes);
    return std::uint16_t(bytes[0] | bytes[1] << 8);
}

// A vector of rays by their sample indices. Compaction keeps indices ascending, and in a coherent
// tile most vectors are consecutive samples: those load their data in one go instead of a gather.
struct Indices {
    VI index;
    std::int32_t first;
    bool contiguous;
};

// The lanes' values of a per-sample array.
template <class D, typename T>
HWY_INLINE hn::Vec<D> fetch(D d, const T* array, const Indices& at) {
    return at.contiguous ? hn::LoadU(d, array + at.first) : hn::GatherIndex(d, array, at.index);
}

// lanes[axis] for a per-lane axis index (0, 1 or 2).
HWY_INLINE VF axisOf(DI di, VI axis, VF x, VF y, VF z) {
    const DF d;
    return hn::IfThenElse(hn::RebindMask(d, hn::Eq(axis, hn::Zero(di))), x,
                          hn::IfThenElse(hn::RebindMask(d, hn::Eq(axis, hn::Set(di, 1))), y, z));
}

// The rays of one vector, loaded once for a leaf's triangles.
struct LaneRays {
    VF time, weight0, originX, originY, shearX, shearY, shearZ, end;
    VI axisX, axisY, axisZ;
    bool alongZ;  // every lane shears along z (kx = 1, ky = 0, kz = 2)
};

struct TriangleHits {
    MF hit;
    VF lambda, b1, b2;
};

// A vector of rays' box-test data as a ray list carries it (TileRays::RayList).
struct ListedRays {
    VF time, inverseX, inverseY, c0, c1;
};

using RayList = TileRays::RayList;

// One pass of one group over one tile (ray_stream.h). kEveryHit: a transparent mesh, every hit
// goes to the layers. kCount: per-sample work is kept for heat maps.
//
// The rays at each level of the descent are a list (TileRays::levelList): sample indices and the
// box test's data, packed by vector compression, so every vector of rays tested against a box is
// full however few rays reach that box, and loads its data instead of gathering it. What the list
// does not carry (the ray end, the triangle test's data) is loaded where the indices are
// consecutive, else gathered. kEmulated: a site computes in a narrower format
// (StreamPass::rayBoxArithmetic, StreamPass::triangleFormat), lane by lane; a template parameter,
// as a run-time branch in the box test cost the fp32 walk 2% of a render.
template <bool kEveryHit, bool kCount, bool kEmulated>
class Pass {
  public:
    Pass(TileRays& rays, const StreamPass& pass, RasterWork& work)
        : rays_(rays),
          pass_(pass),
          h_(*pass.hierarchy),
          mesh_(*pass.mesh),
          work_(work),
          lanes_(int(hn::Lanes(d_))) {}

    void run() {
        const TileTraversal& traversal = *pass_.traversal;
        const int start = pass_.branchNode, startLevel = h_.levelOf(start);
        nodeTimes(traversal.leafMask, start, startLevel);
        work_.branchDepthSum += startLevel;
        int first, last;
        rays_.indexRange(times_[start], first, last);
        for (int b = first / kMaxLanes; b < (last + kMaxLanes - 1) / kMaxLanes; ++b)
            rays_.passImproved()[b] = 0;
        std::int64_t tested = 0;
        const int n = rays_.allAtOrigin()
                          ? startRays<true>(times_[start], first, last, start, tested)
                          : startRays<false>(times_[start], first, last, start, tested);
        if (n > 0) descend(start, rays_.levelList(1, 0), n, 1);
        if (rays_.trace != nullptr) rays_.traceReads(first, last, times_[start]);
        work_.samplesTested += tested;
        work_.samplesRejectedTime += std::int64_t(rays_.count()) - tested;
        work_.raysCast += tested;
        work_.rayBoxTests += boxTests_;
        work_.rayTriangleTests += triangleTests_;
        finish(first, last);
    }

  private:
    // The time range of each node below `start`, at `startLevel` (the descent reads no other):
    // the union (hull) of the intervals of its leaves in `leaves`; empty when it has none. The
    // subtree's nodes at each level are a run of consecutive indices.
    void nodeTimes(std::uint64_t leaves, int start, int startLevel) {
        const TileTraversal& t = *pass_.traversal;
        const int below = h_.depth() - startLevel;  // levels from start down to the leaves
        const int firstLeaf = PatchHierarchy::firstLeaf(h_.depth());
        const int leavesFrom = ((start + 1) << below) - 1;
        for (int node = leavesFrom; node < leavesFrom + (1 << below); ++node) {
            const int j = node - firstLeaf;
            times_[node] = (leaves >> j & 1u) ? t.leafTimes[std::size_t(j)] : TimeRange::empty();
        }
        for (int level = below - 1; level >= 0; --level) {
            const int from = ((start + 1) << level) - 1;
            for (int node = from; node < from + (1 << level); ++node) {
                times_[node] = times_[2 * node + 1];
                times_[node].extend(times_[2 * node + 2]);
            }
        }
    }

    // The pass's rays are the samples [first, last) whose time is in `hull`, each ending at its
    // depth bound; those that meet the start node's box go to the level-1 list. Returns its
    // length; `tested` gets the rays.
    //
    // kAtOrigin: every ray of the tile starts at +0 (a pinhole), so c = -o / d is a zero, which
    // the box test leaves out and the lists do not carry (see hitsBox).
    template <bool kAtOrigin>
    int startRays(TimeRange hull, int first, int last, int start, std::int64_t& tested) {
        const VF lower = hn::Set(d_, hull.lower), upper = hn::Set(d_, hull.upper);
        const VI firstIndex = hn::Set(di_, first), lastIndex = hn::Set(di_, last);
        const LBBox& box = h_.node(start);
        const RayList out = rays_.levelList(1, 0);
        // The tile's own arrays, read as a list whose entries are the samples themselves.
        const RayList tile{
            nullptr, rays_.time, rays_.inverseX, rays_.inverseY, {rays_.slabC[0], rays_.slabC[1]}};
        int count = 0;
        for (int at = first / lanes_ * lanes_; at < last; at += lanes_) {
            const VI index = hn::Add(hn::Iota(di_, 0), hn::Set(di_, at));
            const MF mine =
                hn::RebindMask(d_, hn::AndNot(hn::Lt(index, firstIndex), hn::Lt(index, lastIndex)));
            const VF t = hn::Load(d_, rays_.time + at);
            const MF m = hn::And(mine, hn::And(hn::Ge(t, lower), hn::Le(t, upper)));
            // With z culling, TileRays::rayEnd holds each ray's depth-bound end already.
            if (!pass_.zCulling)
                hn::BlendedStore(endWithoutCulling(at), mine, d_, rays_.rayEnd + at);
            const std::size_t n = hn::CountTrue(d_, m);
            if (n == 0) continue;
            tested += std::int64_t(n);
            if (kCount) {
                addWork(SampleWork::Tested, index, m, 1);
                addWork(SampleWork::Rays, index, m, 1);
                addWork(SampleWork::BoxTests, index, m, 1);
            }
            const ListedRays data = listedAt<kAtOrigin>(tile, at);
            const VF end = hn::Load(d_, rays_.rayEnd + at);
            const MF hit =
                boxHits(box, index, m, SlabLanes<false, kAtOrigin>::of(d_, rays_, data, end));
            count = append<kAtOrigin>(out, count, hit, index, data);
        }
        boxTests_ += tested;
        return count;
    }

    // A vector of lanes of list entries [i, i + lanes), the tail masked off.
    Indices indicesAt(const std::int32_t* list, int i, int n, MF& valid) const {
        const bool full = n - i >= lanes_;
        valid = hn::FirstN(d_, std::size_t(std::min(lanes_, n - i)));
        return {hn::IfThenElseZero(hn::RebindMask(di_, valid), hn::LoadU(di_, list + i)), list[i],
                full && list[i + lanes_ - 1] - list[i] == lanes_ - 1};
    }

    // Without z culling a pass ends its rays at the far plane, or, when it keeps every hit, at
    // their depth bound (samples [at, at + lanes)).
    VF endWithoutCulling(int at) const {
        const float far = rays_.farDepth();
        if constexpr (!kEveryHit) return hn::Set(d_, rayEndAtDepth(far, rays_.depthPerLambda()));
        const VF depth = hn::Load(d_, rays_.bestDepth + at);
        const VF bound = hn::IfThenElse(hn::Lt(depth, hn::Set(d_, far)), depth, hn::Set(d_, far));
        return hn::Mul(hn::Div(bound, hn::Set(d_, rays_.depthPerLambda())),
                       hn::Set(d_, 1.0f + kDepthTieWidening));
    }

    template <bool kAtOrigin>
    ListedRays listedAt(const RayList& list, int i) const {
        ListedRays r{hn::LoadU(d_, list.time + i), hn::LoadU(d_, list.inverseX + i),
                     hn::LoadU(d_, list.inverseY + i), hn::Zero(d_), hn::Zero(d_)};
        if constexpr (!kAtOrigin) {
            r.c0 = hn::LoadU(d_, list.slabC[0] + i);
            r.c1 = hn::LoadU(d_, list.slabC[1] + i);
        }
        return r;
    }

    // Appends the lanes `keep` of a vector of rays to `out`, which holds `count`; returns the new
    // count. Every array has room for a whole vector past its end. kToLeaf: `out` goes to a leaf,
    // which reads only the indices and times, so the box-test data is not written.
    template <bool kAtOrigin, bool kToLeaf = false>
    int append(const RayList& out, int count, MF keep, VI index, const ListedRays& r) const {
        hn::StoreU(hn::Compress(index, hn::RebindMask(di_, keep)), di_, out.index + count);
        hn::StoreU(hn::Compress(r.time, keep), d_, out.time + count);
        if constexpr (!kToLeaf) {
            hn::StoreU(hn::Compress(r.inverseX, keep), d_, out.inverseX + count);
            hn::StoreU(hn::Compress(r.inverseY, keep), d_, out.inverseY + count);
        }
        if constexpr (!kAtOrigin && !kToLeaf) {
            hn::StoreU(hn::Compress(r.c0, keep), d_, out.slabC[0] + count);
            hn::StoreU(hn::Compress(r.c1, keep), d_, out.slabC[1] + count);
        }
        return count + int(hn::CountTrue(d_, keep));
    }

    void addWork(SampleWork what, VI index, MF m, std::uint32_t amount) {
        alignas(64) std::int32_t lanes[kMaxLanes];
        hn::Store(index, di_, lanes);
        std::uint32_t* counts = rays_.work[std::size_t(what)];
        for (std::uint16_t rest = bitsOf(d_, m); rest; rest &= std::uint16_t(rest - 1))
            counts[lanes[std::countr_zero(rest)]] += amount;
    }

    // The slab-test constants of a vector of rays: a = (1 - t) / d and b = t / d from 1/d, in
    // makeSlabRay's operations; c = -o / d; the ray's end. In a tile whose every sample is at
    // shutter open, a is 1/d itself and b is a zero that hitsBox leaves out (see there); in a tile
    // whose rays all start at the origin, so is c.
    template <bool kStill, bool kAtOrigin>
    struct SlabLanes {
        VF a[3], b[3], c[2], end;
        static SlabLanes of(DF d, const TileRays& r, const ListedRays& rays, VF end) {
            SlabLanes s;
            const VF t = rays.time;
            const VF inverse[3] = {rays.inverseX, rays.inverseY, hn::Set(d, r.inverseZ())};
            if constexpr (kStill) {
                for (int k = 0; k < 3; ++k) s.a[k] = inverse[k];  // (1 - 0) / d, to the bit
            } else {
                const VF w0 = hn::Sub(hn::Set(d, 1.0f), t);
                for (int k = 0; k < 3; ++k) {
                    s.a[k] = hn::Mul(w0, inverse[k]);
                    s.b[k] = hn::Mul(t, inverse[k]);
                }
            }
            s.c[0] = rays.c0;
            s.c[1] = rays.c1;
            s.end = end;
            return s;
        }
    };

    // A child's box test: its box, time range and output list.
    struct ChildTest {
        const LBBox* box;
        VF lower, upper;
        RayList out;
        int count = 0;
    };

    ChildTest childTest(int node, const RayList& out) const {
        const TimeRange range = times_[node];
        return {&h_.node(node), hn::Set(d_, range.lower), hn::Set(d_, range.upper), out};
    }

    // One vector of rays (`index`, `valid`, `rays`, their slab constants `s`) against one child:
    // those whose time is in its range and that meet its box are appended to its list.
    template <bool kStill, bool kAtOrigin, bool kToLeaf>
    void testChild(ChildTest& c, VI index, MF valid, const ListedRays& rays,
                   const SlabLanes<kStill, kAtOrigin>& s) {
        const VF t = rays.time;
        const MF active = hn::And(valid, hn::And(hn::Ge(t, c.lower), hn::Le(t, c.upper)));
        const std::size_t tests = hn::CountTrue(d_, active);
        if (tests == 0) return;
        boxTests_ += std::int64_t(tests);
        if (kCount) addWork(SampleWork::BoxTests, index, active, 1);
        const MF hit = boxHits(*c.box, index, active, s);
        c.count = append<kAtOrigin, kToLeaf>(c.out, c.count, hit, index, rays);
    }

    // The rays of `in` (n of them) against the live ones of `children` (1 or 2): each vector's
    // data is loaded once for both boxes. kToLeaf: the children are leaves.
    template <bool kStill, bool kAtOrigin, bool kToLeaf>
    HWY_NOINLINE void filter(const RayList& in, int n, ChildTest* children, int count) {
        for (int i = 0; i < n; i += lanes_) {
            MF valid;
            const Indices at = indicesAt(in.index, i, n, valid);
            const ListedRays rays = listedAt<kAtOrigin>(in, i);
            const auto s =
                SlabLanes<kStill, kAtOrigin>::of(d_, rays_, rays, fetch(d_, rays_.rayEnd, at));
            for (int c = 0; c < count; ++c)
                testChild<kStill, kAtOrigin, kToLeaf>(children[c], at.index, valid, rays, s);
        }
    }

    // The 12-multiply-add test of moving_box_ray.h, lane by lane, in the same operations. At
    // shutter open the t = 1 terms are x1 * 0: a zero (the walk passes no empty box, so x1 is
    // finite), which leaves the sum as it is or changes only the sign of a zero sum, and no
    // comparison below sees that sign. So the six multiply-adds left give the scalar answer. The
    // same holds for c when every ray starts at +0: c = -0 x 1/d is a zero, and adding it changes
    // at most the sign of a zero sum, so it is left out.
    template <bool kStill, bool kAtOrigin>
    HWY_INLINE MF hitsBox(const LBBox& box, const SlabLanes<kStill, kAtOrigin>& s) const {
        VF nearest = hn::Set(d_, rays_.lambdaMin());
        VF farthest = s.end;
        for (int k = 0; k < 3; ++k) {
            VF e0 = hn::Mul(hn::Set(d_, box.bounds0.lower[k]), s.a[k]);
            VF e1 = hn::Mul(hn::Set(d_, box.bounds0.upper[k]), s.a[k]);
            if constexpr (!kStill) {
                e0 = hn::Add(e0, hn::Mul(hn::Set(d_, box.bounds1.lower[k]), s.b[k]));
                e1 = hn::Add(e1, hn::Mul(hn::Set(d_, box.bounds1.upper[k]), s.b[k]));
            }
            if (k < 2 && !kAtOrigin) {  // the origin is on the lens plane: c is 0 along z
                e0 = hn::Add(e0, s.c[k]);
                e1 = hn::Add(e1, s.c[k]);
            }
            nearest = hn::Max(nearest, hn::Min(e0, e1));
            farthest = hn::Min(farthest, hn::Max(e0, e1));
        }
        const VF slack = hn::Mul(hn::Set(d_, kRayBoxRelativeSlack),
                                 hn::Add(hn::Abs(nearest), hn::Abs(farthest)));
        return hn::Le(nearest,
                      hn::Add(hn::Add(farthest, slack), hn::Set(d_, kRayBoxAbsoluteSlack)));
    }

    // Which active lanes meet `box`: the vector test (rays parallel to an axis take the scalar
    // one), or with rasterizer.ray_box_format the emulated one.
    template <bool kStill, bool kAtOrigin>
    HWY_INLINE MF boxHits(const LBBox& box, VI index, MF active,
                          const SlabLanes<kStill, kAtOrigin>& s) const {
        if constexpr (kEmulated)
            if (pass_.rayBoxArithmetic != nullptr) return roundedLanes(box, index, active);
        const MF hit = hn::And(active, hitsBox(box, s));
        return rays_.anyParallel() ? parallelLanes(box, index, active, hit) : hit;
    }

    // rasterizer.ray_box_format: every active lane through the emulated, bounded test; slabRay
    // ends each ray where the vector test does (its z-culled end).
    HWY_NOINLINE MF roundedLanes(const LBBox& box, VI index, MF active) const {
        alignas(64) std::int32_t lanes[kMaxLanes];
        hn::Store(index, di_, lanes);
        std::uint16_t bits = 0;
        for (std::uint16_t rest = bitsOf(d_, active); rest; rest &= std::uint16_t(rest - 1)) {
            const int lane = std::countr_zero(rest);
            const int i = lanes[lane];
            if (hitsMovingBoxRounded(rays_.slabRay(i), box, *pass_.rayBoxArithmetic,
                                     PlaneErrorHandling::Bounded))
                bits = std::uint16_t(bits | (1u << lane));
        }
        return maskOf(d_, bits);
    }

    // Rays parallel to an axis take the scalar test.
    MF parallelLanes(const LBBox& box, VI index, MF active, MF hit) const {
        alignas(64) std::int32_t lanes[kMaxLanes];
        hn::Store(index, di_, lanes);
        std::uint16_t bits = bitsOf(d_, hit);
        for (std::uint16_t rest = bitsOf(d_, active); rest; rest &= std::uint16_t(rest - 1)) {
            const int lane = std::countr_zero(rest);
            const int i = lanes[lane];
            if (!rays_.parallelAxes[i]) continue;
            const auto bit = std::uint16_t(1u << lane);
            bits = hitsMovingBox(rays_.slabRay(i), box) ? std::uint16_t(bits | bit)
                                                        : std::uint16_t(bits & ~bit);
        }
        return maskOf(d_, bits);
    }

    // The rays of `in` (n of them, at `level`) met `node`: both children are tested together,
    // then visited nearer first; only children a leaf of which overlaps the tile.
    void descend(int node, const RayList& in, int n, int level) {
        if (h_.isLeaf(node)) {
            leaf(node, in, n);
            return;
        }
        int first = 2 * node + 1, second = 2 * node + 2;
        // The camera looks down -z: the box reaching higher z (at mid-shutter) is nearer.
        const LBBox &a = h_.node(first), &b = h_.node(second);
        if (b.bounds0.upper.z + b.bounds1.upper.z > a.bounds0.upper.z + a.bounds1.upper.z)
            std::swap(first, second);
        ChildTest tests[2];
        int nodes[2], count = 0;
        for (int child : {first, second}) {
            if (times_[child].isEmpty()) continue;
            tests[count] = childTest(child, rays_.levelList(level + 1, count));
            nodes[count++] = child;
        }
        if (count == 0) return;
        const bool still = rays_.allAtShutterOpen(), atOrigin = rays_.allAtOrigin();
        const bool toLeaves = h_.isLeaf(first);  // both children sit on one level
        if (still && atOrigin)
            filterInto<true, true>(in, n, tests, count, toLeaves);
        else if (still)
            filterInto<true, false>(in, n, tests, count, toLeaves);
        else if (atOrigin)
            filterInto<false, true>(in, n, tests, count, toLeaves);
        else
            filterInto<false, false>(in, n, tests, count, toLeaves);
        for (int c = 0; c < count; ++c)
            if (tests[c].count > 0) descend(nodes[c], tests[c].out, tests[c].count, level + 1);
    }

    template <bool kStill, bool kAtOrigin>
    void filterInto(const RayList& in, int n, ChildTest* children, int count, bool toLeaves) {
        if (toLeaves)
            filter<kStill, kAtOrigin, true>(in, n, children, count);
        else
            filter<kStill, kAtOrigin, false>(in, n, children, count);
    }

    LaneRays fetchRays(const Indices& at, VF time) const {
        LaneRays r;
        r.time = time;
        r.weight0 = hn::Sub(hn::Set(d_, 1.0f), r.time);  // 1 - t, as the reference lerps
        // A pinhole's rays all start at +0 (moving a vertex to it subtracts +0: the same bits).
        const bool atOrigin = rays_.allAtOrigin();
        r.originX = atOrigin ? hn::Zero(d_) : fetch(d_, rays_.originX, at);
        r.originY = atOrigin ? hn::Zero(d_) : fetch(d_, rays_.originY, at);
        r.shearX = fetch(d_, rays_.shearX, at);
        r.shearY = fetch(d_, rays_.shearY, at);
        // Along z, sz = 1 / dz, the same for every camera ray.
        r.shearZ =
            rays_.allShearAlongZ() ? hn::Set(d_, rays_.shearAlongZ()) : fetch(d_, rays_.shearZ, at);
        r.end = fetch(d_, rays_.rayEnd, at);
        r.alongZ = rays_.allShearAlongZ();
        if (!r.alongZ) {
            r.axisX = fetch(di_, rays_.axisX, at);
            r.axisY = fetch(di_, rays_.axisY, at);
            r.axisZ = fetch(di_, rays_.axisZ, at);
        }
        return r;
    }

    // A vertex blended to each lane's time and moved to the ray origin, as `a - r.origin` with
    // `a = lerp(p0, p1, t)` in watertight_triangle.h (the origin's z is 0, so z stays).
    void relative(const LaneRays& r, const Vec3& p0, const Vec3& p1, VF& x, VF& y, VF& z) const {
        if (rays_.allAtShutterOpen()) {  // (1 - 0) p0 + 0 p1 is p0, to the bit
            x = hn::Sub(hn::Set(d_, p0.x), r.originX);
            y = hn::Sub(hn::Set(d_, p0.y), r.originY);
            z = hn::Set(d_, p0.z);
            return;
        }
        x = hn::Sub(
            hn::Add(hn::Mul(r.weight0, hn::Set(d_, p0.x)), hn::Mul(r.time, hn::Set(d_, p1.x))),
            r.originX);
        y = hn::Sub(
            hn::Add(hn::Mul(r.weight0, hn::Set(d_, p0.y)), hn::Mul(r.time, hn::Set(d_, p1.y))),
            r.originY);
        z = hn::Add(hn::Mul(r.weight0, hn::Set(d_, p0.z)), hn::Mul(r.time, hn::Set(d_, p1.z)));
    }

    // A vertex blended to each lane's time, moved to the ray origin and sheared:
    // A[kx] - sx A[kz], A[ky] - sy A[kz], sz A[kz] (watertight_triangle.h).
    struct ShearedVertex {
        VF x, y, z;
    };

    HWY_INLINE ShearedVertex shear(const LaneRays& r, std::uint32_t vertex) const {
        VF A[3];
        relative(r, mesh_.position0[vertex], mesh_.position1[vertex], A[0], A[1], A[2]);
        if (r.alongZ)
            return {hn::Sub(A[1], hn::Mul(r.shearX, A[2])), hn::Sub(A[0], hn::Mul(r.shearY, A[2])),
                    hn::Mul(r.shearZ, A[2])};
        const VF kz = axisOf(di_, r.axisZ, A[0], A[1], A[2]);
        return {hn::Sub(axisOf(di_, r.axisX, A[0], A[1], A[2]), hn::Mul(r.shearX, kz)),
                hn::Sub(axisOf(di_, r.axisY, A[0], A[1], A[2]), hn::Mul(r.shearY, kz)),
                hn::Mul(r.shearZ, kz)};
    }

    // Every distinct vertex of the leaf sheared for this vector of rays, into the scratch.
    void shearVertices(const LaneRays& r) {
        float* out = rays_.vertexScratch();
        const std::size_t n = std::size_t(lanes_);
        for (std::size_t k = 0; k < vertexCount_; ++k) {
            const ShearedVertex v = shear(r, vertices_[k]);
            hn::Store(v.x, d_, out + (3 * std::size_t(k)) * n);
            hn::Store(v.y, d_, out + (3 * std::size_t(k) + 1) * n);
            hn::Store(v.z, d_, out + (3 * std::size_t(k) + 2) * n);
        }
    }

    ShearedVertex sheared(int k) const {
        const float* in = rays_.vertexScratch();
        const std::size_t n = std::size_t(lanes_);
        return {hn::Load(d_, in + (3 * std::size_t(k)) * n),
                hn::Load(d_, in + (3 * std::size_t(k) + 1) * n),
                hn::Load(d_, in + (3 * std::size_t(k) + 2) * n)};
    }

    // The watertight test of watertight_triangle.h for every lane, in the same operations, on
    // the leaf's triangle `k` (its vertices sheared by shearVertices).
    HWY_INLINE TriangleHits intersect(const LaneRays& r, std::size_t k, MF active) const {
        if constexpr (kEmulated)
            if (pass_.triangleFormat != nullptr) return roundedHits(k, active);
        const ShearedVertex a = sheared(corners_[3 * k]), b = sheared(corners_[3 * k + 1]),
                            c = sheared(corners_[3 * k + 2]);
        const VF ax = a.x, ay = a.y, bx = b.x, by = b.y, cx = c.x, cy = c.y;
        VF u = hn::Sub(hn::Mul(cx, by), hn::Mul(cy, bx));
        VF w_ = hn::Sub(hn::Mul(bx, ay), hn::Mul(by, ax));
        VF v = hn::Sub(hn::Mul(ax, cy), hn::Mul(ay, cx));
        const VF zero = hn::Zero(d_);
        const MF onEdge =
            hn::And(active, hn::Or(hn::Or(hn::Eq(u, zero), hn::Eq(v, zero)), hn::Eq(w_, zero)));
        if (!hn::AllFalse(d_, onEdge)) inDouble(onEdge, ax, ay, bx, by, cx, cy, u, v, w_);
        const MF negative = hn::Or(hn::Or(hn::Lt(u, zero), hn::Lt(v, zero)), hn::Lt(w_, zero));
        const MF positive = hn::Or(hn::Or(hn::Gt(u, zero), hn::Gt(v, zero)), hn::Gt(w_, zero));
        const MF inside = hn::AndNot(hn::And(negative, positive), active);
        TriangleHits hits;
        hits.hit = inside;
        // Most rays pass outside an edge: the depth and its division only for those inside.
        if (hn::AllFalse(d_, inside)) return hits;
        const VF det = hn::Add(hn::Add(u, v), w_);
        const VF t = hn::Add(hn::Add(hn::Mul(u, a.z), hn::Mul(v, b.z)), hn::Mul(w_, c.z));
        const VF rcp = hn::Div(hn::Set(d_, 1.0f), det);
        hits.lambda = hn::Mul(t, rcp);
        hits.b1 = hn::Mul(v, rcp);
        hits.b2 = hn::Mul(w_, rcp);
        const MF inRange = hn::And(hn::Ge(hits.lambda, hn::Set(d_, rays_.lambdaMin())),
                                   hn::Le(hits.lambda, r.end));
        const MF valid = hn::AndNot(hn::Eq(det, zero), hn::IsFinite(det));
        hits.hit = hn::And(inside, hn::And(valid, inRange));
        return hits;
    }

    // rasterizer.triangle_format: every active lane through the rounded scalar test on the
    // triangle blended to its time, as the reference tests it (laneRays_ from shearLanes).
    HWY_NOINLINE TriangleHits roundedHits(std::size_t k, MF active) const {
        alignas(64) float lambda[kMaxLanes] = {}, b1[kMaxLanes] = {}, b2[kMaxLanes] = {};
        const std::uint32_t a = vertices_[corners_[3 * k]], b = vertices_[corners_[3 * k + 1]],
                            c = vertices_[corners_[3 * k + 2]];
        std::uint16_t bits = 0;
        for (std::uint16_t rest = bitsOf(d_, active); rest; rest &= std::uint16_t(rest - 1)) {
            const int lane = std::countr_zero(rest);
            const Ray& ray = laneRays_[lane];
            TriangleHit hit;
            if (!intersectTriangleRounded(laneShears_[lane], mesh_.vertexAt(a, ray.time),
                                          mesh_.vertexAt(b, ray.time), mesh_.vertexAt(c, ray.time),
                                          ray.lambdaMin, ray.lambdaMax, *pass_.triangleFormat, hit))
                continue;
            bits = std::uint16_t(bits | (1u << lane));
            lambda[lane] = hit.lambda;
            b1[lane] = hit.b1;
            b2[lane] = hit.b2;
        }
        return {maskOf(d_, bits), hn::Load(d_, lambda), hn::Load(d_, b1), hn::Load(d_, b2)};
    }

    // The scalar rays of the active lanes, for roundedHits.
    HWY_NOINLINE void shearLanes(VI index, MF active) {
        alignas(64) std::int32_t lanes[kMaxLanes];
        hn::Store(index, di_, lanes);
        for (std::uint16_t rest = bitsOf(d_, active); rest; rest &= std::uint16_t(rest - 1)) {
            const int lane = std::countr_zero(rest);
            const int i = lanes[lane];
            laneRays_[lane] = rays_.ray(i);
            // The set-up's shear (tile_ray_setup.cpp), which the tests hold to shearRay of the
            // reference's ray bit for bit, as the vector test uses it.
            ShearedRay& shear = laneShears_[lane];
            shear.origin = laneRays_[lane].origin;
            shear.kx = rays_.axisX[i];
            shear.ky = rays_.axisY[i];
            shear.kz = rays_.axisZ[i];
            shear.sx = rays_.shearX[i];
            shear.sy = rays_.shearY[i];
            shear.sz = rays_.shearZ[i];
        }
    }

    // Lanes with an edge function exactly zero: all three again in double precision.
    HWY_NOINLINE void inDouble(MF lanes, VF ax, VF ay, VF bx, VF by, VF cx, VF cy, VF& u, VF& v,
                               VF& w) const {
        alignas(64) float s[9][kMaxLanes];
        const VF in[9] = {ax, ay, bx, by, cx, cy, u, v, w};
        for (int k = 0; k < 9; ++k) hn::Store(in[k], d_, s[k]);
        for (std::uint16_t rest = bitsOf(d_, lanes); rest; rest &= std::uint16_t(rest - 1)) {
            const int i = std::countr_zero(rest);
            const double dax = s[0][i], day = s[1][i], dbx = s[2][i], dby = s[3][i], dcx = s[4][i],
                         dcy = s[5][i];
            s[6][i] = float(dcx * dby - dcy * dbx);
            s[7][i] = float(dax * dcy - day * dcx);
            s[8][i] = float(dbx * day - dby * dax);
        }
        u = hn::Load(d_, s[6]);
        v = hn::Load(d_, s[7]);
        w = hn::Load(d_, s[8]);
    }

    void leaf(int node, const RayList& in, int n) {
        std::size_t count;
        const int leafIndex = node - PatchHierarchy::firstLeaf(h_.depth());
        const std::uint32_t* triangles = h_.leafTriangles(leafIndex, count);
        if (count == 0) return;
        vertices_ = h_.leafVertices(leafIndex, vertexCount_);
        corners_ = h_.leafCorners(leafIndex);
        for (int i = 0; i < n; i += lanes_) {
            MF active;
            const Indices at = indicesAt(in.index, i, n, active);
            triangleTests_ += std::int64_t(hn::CountTrue(d_, active) * count);
            if (kCount) addWork(SampleWork::TriangleTests, at.index, active, std::uint32_t(count));
            LaneRays r = fetchRays(at, hn::LoadU(d_, in.time + i));
            if (kEmulated && pass_.triangleFormat != nullptr)
                shearLanes(at.index, active);
            else
                shearVertices(r);
            if (kEveryHit)
                offerEveryHit(r, triangles, count, active, at.index);
            else
                keepNearest(r, triangles, count, active, at);
        }
    }

    // A hit per lane, or the nearest so far: VisibilityRecord's depth, patch, triangle,
    // barycentrics.
    struct Candidate {
        VF depth;
        VI patch;
        VU triangle;
        VF b1, b2;
    };

    // VisibilityRecord::nearerThan lane by lane: depth, then patch, then triangle (unsigned).
    MF nearerThan(const Candidate& a, const Candidate& b) const {
        const VU patchA = hn::BitCast(du_, a.patch), patchB = hn::BitCast(du_, b.patch);
        const auto tieLess =
            hn::Or(hn::Lt(patchA, patchB),
                   hn::And(hn::Eq(patchA, patchB), hn::Lt(a.triangle, b.triangle)));
        return hn::Or(hn::Lt(a.depth, b.depth),
                      hn::And(hn::Eq(a.depth, b.depth), hn::RebindMask(d_, tieLess)));
    }

    Candidate select(MF m, const Candidate& yes, const Candidate& no) const {
        return {hn::IfThenElse(m, yes.depth, no.depth),
                hn::IfThenElse(hn::RebindMask(di_, m), yes.patch, no.patch),
                hn::IfThenElse(hn::RebindMask(du_, m), yes.triangle, no.triangle),
                hn::IfThenElse(m, yes.b1, no.b1), hn::IfThenElse(m, yes.b2, no.b2)};
    }

    // The leaf's nearest hit per ray first (most vectors have none), then against the sample's
    // nearest so far: the same minimum in (depth, patch, triangle) order either way.
    void keepNearest(LaneRays& r, const std::uint32_t* triangles, std::size_t count, MF active,
                     const Indices& at) {
        const VI index = at.index;
        const VF perLambda = hn::Set(d_, rays_.depthPerLambda());
        const VF widen = hn::Set(d_, 1.0f + kDepthTieWidening);
        Candidate leafBest{hn::Set(d_, std::numeric_limits<float>::infinity()), hn::Set(di_, -1),
                           hn::Zero(du_), hn::Zero(d_), hn::Zero(d_)};
        MF found = hn::FirstN(d_, 0);
        for (std::size_t k = 0; k < count; ++k) {
            const std::uint32_t tri = triangles[k];
            const TriangleHits hits = intersect(r, k, active);
            if (hn::AllFalse(d_, hits.hit)) continue;
            const Candidate hit{hn::Mul(hits.lambda, perLambda),
                                hn::Set(di_, std::int32_t(mesh_.patchOf(tri))),
                                hn::Set(du_, mesh_.triangleInPatchOf(tri)), hits.b1, hits.b2};
            const MF take = hn::And(hits.hit, nearerThan(hit, leafBest));
            leafBest = select(take, hit, leafBest);
            // The ray ends at its nearest hit so far (z_culling.h's rayEndAtDepth).
            r.end = hn::IfThenElse(
                take, hn::Min(r.end, hn::Mul(hn::Div(hit.depth, perLambda), widen)), r.end);
            found = hn::Or(found, take);
        }
        if (hn::AllFalse(d_, found)) return;
        // nearerThan(leafBest, the sample's nearest so far): the depths decide unless they are
        // equal, so the nearest's patch and triangle are read only for such ties, and its
        // barycentrics never (an improved sample takes all of leafBest's).
        const VF bestDepth = fetch(d_, rays_.bestDepth, at);
        MF improved = hn::And(found, hn::Lt(leafBest.depth, bestDepth));
        const MF tied = hn::And(found, hn::Eq(leafBest.depth, bestDepth));
        if (!hn::AllFalse(d_, tied)) {
            const Candidate best{bestDepth, fetch(di_, rays_.bestPatch, at),
                                 fetch(du_, rays_.bestTriangle, at), hn::Zero(d_), hn::Zero(d_)};
            improved = hn::Or(improved, hn::And(tied, nearerThan(leafBest, best)));
        }
        if (hn::AllFalse(d_, improved)) return;
        alignas(64) std::int32_t lanes[kMaxLanes], patches[kMaxLanes];
        alignas(64) std::uint32_t triangleLanes[kMaxLanes];
        alignas(64) float depths[kMaxLanes], b1s[kMaxLanes], b2s[kMaxLanes], ends[kMaxLanes];
        hn::Store(index, di_, lanes);
        hn::Store(leafBest.patch, di_, patches);
        hn::Store(leafBest.triangle, du_, triangleLanes);
        hn::Store(leafBest.depth, d_, depths);
        hn::Store(leafBest.b1, d_, b1s);
        hn::Store(leafBest.b2, d_, b2s);
        hn::Store(r.end, d_, ends);
        for (std::uint16_t rest = bitsOf(d_, improved); rest; rest &= std::uint16_t(rest - 1)) {
            const int lane = std::countr_zero(rest);
            const auto i = std::size_t(lanes[lane]);
            rays_.bestDepth[i] = depths[lane];
            rays_.bestPatch[i] = patches[lane];
            rays_.bestTriangle[i] = triangleLanes[lane];
            rays_.bestB1[i] = b1s[lane];
            rays_.bestB2[i] = b2s[lane];
            // The new nearest hit's end (or, for a hit within the tie widening beyond the far
            // plane, the far plane's, which the ray already had): TileRays::rayEnd's rule.
            rays_.rayEnd[i] = ends[lane];
            rays_.passImproved()[i / kMaxLanes] |= std::uint16_t(1u << (i % kMaxLanes));
        }
    }

    void offerEveryHit(const LaneRays& r, const std::uint32_t* triangles, std::size_t count,
                       MF active, VI index) {
        alignas(64) float lambda[kMaxLanes], b1[kMaxLanes], b2[kMaxLanes];
        alignas(64) std::int32_t lanes[kMaxLanes];
        hn::Store(index, di_, lanes);
        for (std::size_t k = 0; k < count; ++k) {
            const std::uint32_t tri = triangles[k];
            const TriangleHits hits = intersect(r, k, active);
            if (hn::AllFalse(d_, hits.hit)) continue;
            hn::Store(hits.lambda, d_, lambda);
            hn::Store(hits.b1, d_, b1);
            hn::Store(hits.b2, d_, b2);
            for (std::uint16_t rest = bitsOf(d_, hits.hit); rest; rest &= std::uint16_t(rest - 1)) {
                const int lane = std::countr_zero(rest);
                const auto i = std::size_t(lanes[lane]);
                VisibilityRecord record;
                record.depth = lambda[lane] * rays_.depthPerLambda();
                record.patch = mesh_.patchOf(tri);
                record.triangle = mesh_.triangleInPatchOf(tri);
                record.b1 = b1[lane];
                record.b2 = b2[lane];
                record.time = rays_.time[i];
                record.lens = {rays_.lensU[i], rays_.lensV[i]};
                ++work_.transparentFragments;
                if (kCount) ++rays_.work[std::size_t(SampleWork::Visible)][i];
                if (!offerToLayers(*pass_.transparent, rays_.record[i], pass_.pool,
                                   LayerFragment{record, mesh_.objectId}, rays_.trace))
                    ++work_.transparentOverflow;
            }
        }
    }

    // Samples whose nearest hit changed in this pass (samples [first, last)) are visibility
    // samples.
    void finish(int first, int last) { work_.visibilitySamples += rays_.commitPass(first, last); }

    const DF d_{};
    const DI di_{};
    const DU du_{};
    TileRays& rays_;
    const StreamPass& pass_;
    const PatchHierarchy& h_;
    const MovingMesh& mesh_;
    RasterWork& work_;
    const int lanes_;
    std::int64_t boxTests_ = 0, triangleTests_ = 0;
    // The current leaf's distinct vertices and its triangles' corners among them
    // (PatchHierarchy::leafVertices).
    const std::uint32_t* vertices_ = nullptr;
    const std::uint8_t* corners_ = nullptr;
    std::size_t vertexCount_ = 0;
    TimeRange times_[2 * kMaxLeavesPerHierarchy - 1];
    // The current vector's rays, scalar, for the rounded triangle test (kEmulated only).
    Ray laneRays_[kEmulated ? kMaxLanes : 1];
    ShearedRay laneShears_[kEmulated ? kMaxLanes : 1];
};

template <bool kEmulated>
void trace(TileRays& rays, const StreamPass& pass, RasterWork& work) {
    const bool everyHit = pass.transparent != nullptr;
    const bool counting = rays.work[0] != nullptr;
    if (everyHit && counting)
        Pass<true, true, kEmulated>(rays, pass, work).run();
    else if (everyHit)
        Pass<true, false, kEmulated>(rays, pass, work).run();
    else if (counting)
        Pass<false, true, kEmulated>(rays, pass, work).run();
    else
        Pass<false, false, kEmulated>(rays, pass, work).run();
}

void TraceImpl(TileRays& rays, const StreamPass& pass, RasterWork& work) {
    if (pass.rayBoxArithmetic != nullptr || pass.triangleFormat != nullptr)
        trace<true>(rays, pass, work);
    else
        trace<false>(rays, pass, work);
}

float FarthestImpl(const float* depth, int count, float farDepth) {
    const DF d;
    const VF far = hn::Set(d, farDepth);
    VF deepest = hn::Zero(d);
    for (int i = 0; i < count; i += int(hn::Lanes(d))) {
        const VF v = hn::Load(d, depth + i);
        deepest = hn::Max(deepest, hn::IfThenElse(hn::Lt(v, far), v, far));
    }
    return hn::GetLane(hn::MaxOfLanes(d, deepest));
}

const char* TargetImpl() {
    return hwy::TargetName(HWY_TARGET);
}

}  // namespace HWY_NAMESPACE
}  // namespace patchsim
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace patchsim {

HWY_EXPORT(TraceImpl);
HWY_EXPORT(FarthestImpl);
HWY_EXPORT(TargetImpl);

void traceRayStream(TileRays& rays, const StreamPass& pass, RasterWork& work) {
    HWY_DYNAMIC_DISPATCH(TraceImpl)(rays, pass, work);
}

float farthestBoundOf(const float* depth, int count, float farDepth) {
    return HWY_DYNAMIC_DISPATCH(FarthestImpl)(depth, count, farDepth);
}

const char* rayStreamTarget() {
    return HWY_DYNAMIC_DISPATCH(TargetImpl)();
}

}  // namespace patchsim
#endif
