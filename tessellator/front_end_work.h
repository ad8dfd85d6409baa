#pragma once
// What the front end (IA, VS, HS, TS, DS) does for one patch of the rendered frame, with the
// operations each count charges the modelled hardware (DESIGN.md section 8).
//
// Representation
// --------------
// One row per count, in the form of core/work_counts.h. `FrontEnd::tessellate` fills a patch's
// `FrontEndWork` (its own work only: a neighbour tessellated again to stitch a shared edge is
// counted in `neighbourTessellations`, and charged nothing, since hardware has the neighbour's
// factors from the neighbour's own hull shader), adds it to the calling thread's counters, and
// keeps it with the patch, so the driver charges the timing model from the same numbers the
// counters report.

#include "core/work_counts.h"

// X(field, "Stage/Name", "unit", kind, "definition", charges...)
#define PATCHSIM_FRONT_END_WORK(X)                                                                 \
    X(patches, "IA/Patches", "patches", Sum,                                                       \
      "Tessellation domains made from cage faces and fetched with their control points; an "       \
      "N-gon of a Catmull-Clark cage is N quad sub-patches",                                       \
      Op::Patches)                                                                                 \
    X(patchControlPoints, "VS/Patch control points", "points", Sum,                                \
      "Control points of the patches' limit surfaces, transformed for each patch that uses them",  \
      Op::ControlPoints)                                                                           \
    X(hullPatches, "HS/Patches", "patches", Sum,                                                   \
      "Patches whose tessellation factors were computed")                                          \
    X(culledPatches, "HS/Patches culled", "patches", Sum,                                          \
      "Patches culled because an edge factor is <= 0 or NaN")                                      \
    X(edgeFactors, "HS/Edge factors", "factors", Sum,                                              \
      "Edge factors computed (4 per quad patch, 3 per triangle patch)", Op::EdgeFactors)           \
    X(neighbourTessellations, "TS/Neighbour tessellations", "patches", Sum,                        \
      "Neighbouring patches whose factors and edge points were computed again to stitch a shared " \
      "edge (fractional partitioning only); not charged: hardware has them from the neighbour's "  \
      "own hull shader")                                                                           \
    X(domainPoints, "TS/Domain points", "points", Sum,                                             \
      "Domain points emitted by the D3D11 fixed-function tessellator, plus any stitch points",     \
      Op::DomainPoints)                                                                            \
    X(stitchPoints, "TS/Stitch points", "points", Sum,                                             \
      "Points added on an edge where the neighbouring patch's fractional pattern differs (an "     \
      "N-gon's half edges against a whole edge), so no T-junction remains")                        \
    X(triangles, "TS/Triangles", "triangles", Sum, "Triangles emitted by the D3D11 tessellator",   \
      Op::Triangles)                                                                               \
    X(evaluations, "DS/Evaluations", "points", Sum,                                                \
      "Domain points evaluated on the limit surface (one stencil, applied at t=0 and t=1)",        \
      Op::Evaluations)                                                                             \
    X(ownerEvaluations, "DS/Shared-edge evaluations", "points", Sum,                               \
      "Domain points on an edge or corner shared with a lower-numbered patch, evaluated on that "  \
      "owner patch")                                                                               \
    X(stencilApplications, "DS/Stencil applications", "applications", Sum,                         \
      "Stencil weight sets applied to a control-point set (position, du, dv at both shutter "      \
      "ends)",                                                                                     \
      Op::StencilApplications)

namespace patchsim {

struct FrontEndWork {
    PATCHSIM_FRONT_END_WORK(PATCHSIM_WORK_FIELD)
    PATCHSIM_WORK_METHODS(FrontEndWork)
};

struct FrontEndCounters {
    PATCHSIM_FRONT_END_WORK(PATCHSIM_WORK_HANDLE)
};
const FrontEndCounters& frontEndCounters();

}  // namespace patchsim
