// What one operation of each kind does, counted in the code that counts it (the patch method's
// site where several methods count a kind). Operand bytes are a test's reads from its stage's
// buffers, a read that lanes share divided among them: the 16 rays of a stream share a box or a
// triangle, a node visit's 16 plane-and-end tests its box. docs/HARDWARE.md "Energy" gives each
// row's derivation; a test holds that table to this one. Loads, stores and their address arithmetic
// are the memory model's, not counted here.

#include "pipeline/timing/energy_model.h"

namespace patchsim {

namespace {

// {op, adds, multiplies, compares, divides, intAdds, intMultiplies, intBits, operandBytes, how}
constexpr std::array<OpArithmetic, kOpCount> kArithmetic = {{
    // Patches (IA): the object's patch range found by a binary search; the fetch is memory.
    {Op::Patches, 0, 0, 0, 0, 4, 0, 32, 0, "binary search of the objects' patch offsets, an index"},
    // ControlPoints (VS): a 4x4 transform at each shutter end, finite and equality checks.
    {Op::ControlPoints, 24, 32, 16, 0, 0, 0, 32, 0,
     "two Mat4 x Vec4 (shutter ends), 16 finite/equal tests"},
    // EdgeFactors (HS): clean-up and clamp per edge; the two inside factors' mean, shared by 4.
    {Op::EdgeFactors, 0.5, 0, 8, 0.5, 3, 0, 32, 0,
     "clamp and clean-up (8), inside mean shared by 4, ceil"},
    // DomainPoints (TS): D3D11's 16.16 fixed-point placement, converted to float.
    {Op::DomainPoints, 2, 2, 0, 0, 16, 4, 32, 0,
     "16.16 placement: 4 multiplies, 12 adds, 4 conversions"},
    // Triangles (TS): index arithmetic of the stitch.
    {Op::Triangles, 0, 0, 0, 0, 7, 0, 32, 0, "index arithmetic: 5 adds, 2 compares"},
    // Evaluations (DS): OpenSubdiv's regular B-spline basis with derivatives (an estimate), and
    // the normal at both shutter ends.
    {Op::Evaluations, 36, 96, 6, 8, 14, 0, 32, 0,
     "B-spline basis and derivatives (est.), two normals"},
    // StencilApplications (DS): 16 weights times a point's 3 coordinates, summed.
    {Op::StencilApplications, 45, 48, 0, 0, 0, 0, 32, 0,
     "16 control points x 3 coordinates: multiply-accumulate"},
    // NodesBuilt (RS): leaves of 4 triangles (192 min/max), interior nodes (12), averaged.
    {Op::NodesBuilt, 0, 0, 102, 0, 0, 0, 32, 96,
     "min/max of moving boxes: leaf 192, interior 12, mean 102"},
    // PlaneTests (RS): the plane's distance to the box's n-vertex, its sign, the interval's
    // bookkeeping.
    {Op::PlaneTests, 3, 3, 3, 0, 0, 0, 32, 1.5, "dot product and offset, sign, interval min/max"},
    // TimeIntervals (RS): d0 / (d0 - d1), guarded and clamped to the shutter.
    {Op::TimeIntervals, 2, 0, 1, 1, 0, 0, 32, 0, "d0 / (d0 - d1), guard, clamp"},
    // SamplesTested (RS): the sample's time against the tile's range, and its index mask.
    {Op::SamplesTested, 0, 0, 2, 0, 3, 0, 32, 4, "time window (2), index mask"},
    // RayBoxTests (RS): both slabs per axis from the box at the ray's time, min/max, slack.
    {Op::RayBoxTests, 13.5, 16, 15, 0, 0, 0, 32, 3,
     "per axis 2 faces at time t (FMA), 4 min/max; slack"},
    // RayTriangleTests (RS): watertight test at the ray's time, leaf vertices blended and
    // sheared once per ray (1.5 a triangle).
    {Op::RayTriangleTests, 17.5, 25.5, 13, 1, 0, 0, 32, 4.5,
     "edge functions, determinant, depth, reciprocal"},
    // EdgeTests (RS): three integer edge functions (exact in 32 bits for small triangles), and
    // the perspective-correct depth and barycentrics, charged with every test.
    {Op::EdgeTests, 2, 7, 2, 1, 12, 6, 32, 8, "3 integer edge functions; depth and barycentrics"},
    // Invocations (PS): attribute interpolation and the shader.
    {Op::Invocations, 76, 96, 5, 4, 5, 0, 32, 0,
     "interpolation (57 mul) and Lambert/checker shading"},
    // DepthTests (OM): the hit's depth, nearer-than and tie rule, the ray's end shortened.
    {Op::DepthTests, 0, 2, 5, 1, 3, 0, 32, 0, "depth, nearer-than with tie rule, ray end"},
    // TransparentFragments (OM): merge and insert among the layers held, taken as 3 (the count
    // does not record how many are held).
    {Op::TransparentFragments, 1, 4, 4, 0, 8, 0, 32, 0,
     "tolerance, object and depth per held layer (3 held)"},
    // TriangleSetups (RS): six points projected across the lens, the pixel box, the hull's
    // inputs (the hull's own fp64 build is not charged).
    {Op::TriangleSetups, 45, 21, 43, 47, 14, 0, 32, 72,
     "6 lens-corner projections, pixel box, hull inputs"},
    // PostSamples (PS): one gather tap of the reconstruction filter.
    {Op::PostSamples, 28, 24, 17, 8, 15, 0, 32, 0,
     "a gather tap: weights, soft depth, two cylinders"},
    // EdgeSetups (RS): edge coefficients, area, orientation, tie rule, box, charged in fp32
    // (the code computes them in double).
    {Op::EdgeSetups, 11, 8, 21, 0, 22, 0, 32, 36, "edges, area, orientation, tie rule, pixel box"},
    // LensEdgeTests (RS): three edge functions of the sample's screen point and lens point (seven
    // multiplies and seven adds each), the all-or-none sign test, then the depth and barycentrics.
    {Op::LensEdgeTests, 25, 27, 7, 1, 3, 0, 32, 16,
     "3 lens edge functions (7 mul, 7 add each); signs; depth and barycentrics"},
    // LensEdgeSetups (RS): canonical edge order, differences, the box across the lens in pixels.
    {Op::LensEdgeSetups, 29, 15, 39, 0, 6, 0, 32, 48,
     "canonical order, 3 edge differences, box across the lens, guard band, pixels"},
}};

constexpr bool inOpOrder() {
    for (int k = 0; k < kOpCount; ++k)
        if (kArithmetic[std::size_t(k)].op != Op(k)) return false;
    return true;
}
static_assert(inOpOrder(), "one row per operation kind, in core/stage_ops.h's order");

}  // namespace

const OpArithmetic& opArithmetic(Op op) {
    return kArithmetic[std::size_t(op)];
}

}  // namespace patchsim
