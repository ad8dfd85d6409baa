#pragma once
// The pipeline's stages and the operations each performs: the vocabulary in which every
// component charges its counted work to the timing model (pipeline/timing, DESIGN.md section 8).
//
// Representation
// --------------
// `PATCHSIM_STAGE_OPS` lists every operation kind once, as (enumerator, JSON key, stage,
// definition). From that list come the `Op` enum, its names (the keys of a hardware file's
// "throughput" objects), the stage that performs each, and its definition (docs/HARDWARE.md lists
// them; a test keeps the page equal to the list). `PatchOps` is one patch's count of every kind:
// what a stage's service time is computed from. Components count their own work in their own
// lists (core/work_counts.h), each count naming the operations it charges.

#include <algorithm>
#include <array>
#include <cstdint>

// X(Enumerator, "json_key", Stage, "definition")
#define PATCHSIM_STAGE_OPS(X)                                                                     \
    X(Patches, "patches", IA, "Patches fetched with their control points")                        \
    X(ControlPoints, "control_points", VS,                                                        \
      "Control points transformed (at shutter open and close)")                                   \
    X(EdgeFactors, "edge_factors", HS, "Tessellation factors computed (edges and inside)")        \
    X(DomainPoints, "domain_points", TS, "Domain points the tessellator generates")               \
    X(Triangles, "triangles", TS, "Triangles the tessellator generates")                          \
    X(Evaluations, "evaluations", DS, "Limit stencils evaluated at domain points")                \
    X(StencilApplications, "stencil_applications", DS,                                            \
      "Stencils applied to control points (position and derivatives, at open and close)")         \
    X(NodesBuilt, "nodes_built", RS, "Hierarchy nodes built or converted to a bounds space")      \
    X(PlaneTests, "plane_tests", RS, "Moving boxes tested against one tile plane at one time")    \
    X(TimeIntervals, "time_intervals", RS, "Plane crossing times computed at leaves")             \
    X(SamplesTested, "samples_tested", RS, "Samples considered against a tile or a triangle")     \
    X(RayBoxTests, "ray_box_tests", RS, "Rays against a moving box at their time")                \
    X(RayTriangleTests, "ray_triangle_tests", RS, "Watertight ray-triangle tests at a time")      \
    X(EdgeTests, "edge_tests", RS,                                                                \
      "Samples tested against a static triangle's three fixed-point edge functions")              \
    X(Invocations, "invocations", PS, "Pixel shader invocations")                                 \
    X(DepthTests, "depth_tests", OM, "Visibility samples written to the z-buffer")                \
    X(TransparentFragments, "transparent_fragments", OM,                                          \
      "Transparent fragments offered to a sample's layers")                                       \
    X(TriangleSetups, "triangle_setups", RS, "Triangle screen bounds computed")                   \
    X(PostSamples, "post_samples", PS, "Pixels read by full-screen passes (image-space methods)") \
    X(EdgeSetups, "edge_setups", RS,                                                              \
      "Static triangles set up for edge-function tests: three edges, tie rule, pixel box")        \
    X(LensEdgeTests, "lens_edge_tests", RS,                                                       \
      "Samples (x, y, u, v) tested against a triangle's three edge functions seen from the lens") \
    X(LensEdgeSetups, "lens_edge_setups", RS,                                                     \
      "Triangles set up for the lens edge test: canonical edges, pixel box across the lens")

namespace patchsim {

enum class Stage : std::uint8_t { IA, VS, HS, TS, DS, RS, PS, OM };
inline constexpr int kStageCount = 8;
const char* stageName(Stage s);

enum class Op : std::uint8_t {
#define PATCHSIM_OP_ENUM(op, key, stage, definition) op,
    PATCHSIM_STAGE_OPS(PATCHSIM_OP_ENUM)
#undef PATCHSIM_OP_ENUM
};

inline constexpr int kOpCount = 0
#define PATCHSIM_OP_COUNT(op, key, stage, definition) +1
    PATCHSIM_STAGE_OPS(PATCHSIM_OP_COUNT)
#undef PATCHSIM_OP_COUNT
    ;

const char* opName(Op op);        // the JSON key, e.g. "ray_box_tests"
const char* opDefinition(Op op);  // one line
Stage stageOf(Op op);

// One patch's counted operations, and the largest hierarchy its groups built (held against the
// on-chip scratch budget).
struct PatchOps {
    std::array<double, kOpCount> ops{};
    std::uint64_t hierarchyBytes = 0;
    double& operator[](Op op) { return ops[std::size_t(op)]; }
    double operator[](Op op) const { return ops[std::size_t(op)]; }
    void add(const PatchOps& o) {
        for (std::size_t k = 0; k < ops.size(); ++k) ops[k] += o.ops[k];
        hierarchyBytes = std::max(hierarchyBytes, o.hierarchyBytes);
    }
};

}  // namespace patchsim
