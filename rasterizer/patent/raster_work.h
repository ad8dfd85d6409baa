#pragma once
// The patch rasterizer's work counts (DESIGN.md section 8): what it counts, defined once.
//
// Representation
// --------------
// `PATCHSIM_RASTER_WORK` lists every count as (field, counter name, unit, kind, definition,
// charges), in the form of core/work_counts.h. From that one list come the plain struct the hot
// loops count into (`RasterWork`, one int64 per count, no allocation, added field by field), the
// registered counters that hold the frame's totals (docs/COUNTERS.md), the flush of a RasterWork
// into them, and its charge to the timing model. A RasterWork is kept per patch, since the timing
// model charges each patch its own work, and flushed once when its worker is done. A Max count
// keeps the largest value instead of the sum.

#include <cstdint>

#include "core/work_counts.h"

// X(field, "Stage/Name", "unit", kind, "definition", charges...)
#define PATCHSIM_RASTER_WORK(X)                                                                    \
    X(patches, "RS/Patches", "patches", Sum, "Patches given to the patch rasterizer")              \
    X(patchesMerged, "RS/Patches merged", "patches", Sum,                                          \
      "Patches rasterized in a hierarchy shared with their neighbours (merge_triangles_below)")    \
    X(groups, "RS/Groups", "groups", Sum,                                                          \
      "Triangle groups rasterized (a patch is one group unless split)")                            \
    X(nodesBuilt, "RS/Nodes built", "nodes", Sum, "Hierarchy nodes built (moving boxes)",          \
      Op::NodesBuilt)                                                                              \
    X(hierarchyBytes, "RS/Hierarchy bytes", "bytes", Sum,                                          \
      "Bytes of all hierarchies built (node boxes and leaf triangle lists)")                       \
    X(peakHierarchyBytes, "RS/Peak hierarchy bytes", "bytes", Max,                                 \
      "Largest single hierarchy, against the on-chip scratch budget", kScratchPeak)                \
    X(nodesConverted, "RS/Nodes converted", "nodes", Sum,                                          \
      "Hierarchy nodes converted to the 2DH or 2D bounds space (bounds_space), per group",         \
      Op::NodesBuilt)                                                                              \
    X(fullScreenBounds, "RS/Full-screen bounds", "groups", Sum,                                    \
      "Groups whose boxes reach in front of the near plane: bounds fall back to the whole screen") \
    X(tilesInBounds, "RS/Tiles in bounds", "tiles", Sum,                                           \
      "Tiles inside a group's screen bounds (each is tested)")                                     \
    X(tilesRejectedSpace, "RS/Tiles rejected by space", "tiles", Sum,                              \
      "Tiles whose frustum misses every box at every time")                                        \
    X(tilesRejectedTime, "RS/Tiles rejected by time", "tiles", Sum,                                \
      "Tiles whose leaves overlap in space but whose time intervals are all empty")                \
    X(tilesOverlapping, "RS/Tiles overlapping", "tiles", Sum,                                      \
      "Tiles whose samples were considered")                                                       \
    X(frustumNodeVisits, "RS/Frustum node visits", "nodes", Sum,                                   \
      "Hierarchy nodes tested against a tile frustum")                                             \
    X(planeTests, "RS/Plane tests", "tests", Sum,                                                  \
      "Box n-vertex (or p-vertex) against one frustum plane at one time", Op::PlaneTests)          \
    X(timeIntervals, "RS/Leaf time intervals", "crossings", Sum,                                   \
      "Plane crossing times computed at leaves (d0 / (d0 - d1))", Op::TimeIntervals)               \
    X(branchDepthSum, "RS/Branch node depth", "levels", Sum,                                       \
      "Sum over overlapping tiles of the level of the node rays start from")                       \
    X(samplesTested, "RS/Samples tested", "samples", Sum,                                          \
      "Samples of overlapping tiles considered", Op::SamplesTested)                                \
    X(samplesRejectedTime, "RS/Samples rejected by time", "samples", Sum,                          \
      "Samples outside the tile's [tmin, tmax], rejected without a ray")                           \
    X(raysCast, "RS/Rays cast", "rays", Sum,                                                       \
      "Per-sample rays traversed from the branch node (static and defocus-only frames: only "      \
      "against triangles with no screen or lens form)")                                            \
    X(rayBoxTests, "RS/Ray-box tests", "tests", Sum,                                               \
      "Ray against a moving box at the sample's time (12 multiply-adds)", Op::RayBoxTests)         \
    X(rayTriangleTests, "RS/Ray-triangle tests", "tests", Sum,                                     \
      "Watertight ray-triangle tests on triangles blended to the sample's time",                   \
      Op::RayTriangleTests)                                                                        \
    X(screenVertices, "RS/Screen vertices", "vertices", Sum,                                       \
      "Static and defocus-only frames: leaf vertices projected (static: snapped to fixed point), " \
      "once per group (the viewport transform, not charged)")                                      \
    X(screenTriangleSetups, "RS/Screen triangle setups", "triangles", Sum,                         \
      "Static frames: triangles of overlapping leaves snapped to fixed point and set up as edge "  \
      "functions, once per tile",                                                                  \
      Op::EdgeSetups)                                                                              \
    X(edgeTests, "RS/Edge tests", "tests", Sum,                                                    \
      "Static frames: samples tested against a triangle's three edge functions", Op::EdgeTests)    \
    X(lensTriangleSetups, "RS/Lens triangle setups", "triangles", Sum,                             \
      "Defocus-only frames: triangles of overlapping leaves set up for the lens edge test, once "  \
      "per tile",                                                                                  \
      Op::LensEdgeSetups)                                                                          \
    X(lensEdgeTests, "RS/Lens edge tests", "tests", Sum,                                           \
      "Defocus-only frames: samples (x, y, u, v) tested against a triangle's three edge "          \
      "functions seen from their lens point",                                                      \
      Op::LensEdgeTests)                                                                           \
    X(visibilitySamples, "RS/Visibility samples", "samples", Sum,                                  \
      "Ray hits nearer than the sample's z-buffer depth, sent to the back end", Op::DepthTests)    \
    X(transparentFragments, "OM/Transparent fragments", "fragments", Sum,                          \
      "Transparent hits offered to a sample's layers", Op::TransparentFragments)                   \
    X(transparentOverflow, "OM/Transparent overflow", "fragments", Sum,                            \
      "Transparent fragments dropped because a sample's layers were full (the farthest goes)")

namespace patchsim {

struct RasterWork {
    PATCHSIM_RASTER_WORK(PATCHSIM_WORK_FIELD)
    PATCHSIM_WORK_METHODS(RasterWork)
};

// The frame totals, by handle (e.g. `values[rasterCounters().raysCast]`).
struct RasterCounters {
    PATCHSIM_RASTER_WORK(PATCHSIM_WORK_HANDLE)
};
const RasterCounters& rasterCounters();

// Visibility samples / samples tested.
const RatioCounter& sampleTestEfficiency();

}  // namespace patchsim
