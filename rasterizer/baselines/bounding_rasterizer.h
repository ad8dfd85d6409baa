#pragma once
// The stochastic rasterizers the patent improves on (DESIGN.md section 5): every triangle's screen
// bounds, and every sample inside them tested against the triangle at the sample's time. Three
// ways to bound, sharing the rest:
//
// - triangle-bbox (Akenine-Moller et al. 2007; McGuire et al. 2010): the triangle's bounds over the
//   whole shutter and the whole lens. By default the bound is McGuire et al.'s convex hull of the
//   vertices at both shutter ends, each widened by its circle of confusion (screen_hull.h),
//   walked row by row as a rasterizer walks a polygon: a sample of the pixels it reaches is
//   ray-tested only when it falls inside the hull (a 2D edge test, as a rasterizer's coverage
//   test). With `TriangleBound::OrientedBox` the bound is the least-area rectangle, in any
//   orientation, that holds that hull (four edge tests a sample); with `TriangleBound::Box`
//   every sample of the triangle's pixel box is ray-tested.
// - interval (Fatahalian et al. 2009): the shutter split into K strata; per stratum the bounds of
//   the triangle over that stratum, and only that stratum's samples tested.
// - interleaved (accumulation buffer): sample index s has one time, lens point and sub-pixel shift
//   in every pixel (SamplePattern::Interleaved), so each index is a static pass: per pass the
//   triangle's exact screen bounds, and only that index's sample tested. Constant cost whatever
//   the blur; strobing where things move.
//
// Bounds: a point moving linearly in front of the camera projects, from any one lens point, to a
// segment between its projections at the ends; and over the lens disk it spreads by the circle of
// confusion R |1/F - 1/depth|, largest at the ends of its depth range. So the box of the vertices'
// projections at the ends of the time span, each widened by its own circle of confusion, holds the
// triangle at every time and lens point of the span. A vertex in front of the near plane makes the
// bounds the whole screen, unless the whole triangle is nearer than the near plane (behind the
// camera, say) at both ends of the shutter: then (linear motion, a convex half-space) it is so at
// every time, can hit no sample, and is culled after its setup without a test. Tests are the
// watertight ray-triangle test on the sample's own ray, so these methods find the same nearest hit
// as the patch rasterizer and the reference for the same samples. As the patch method's rays are
// made once per tile, a band's samples are made once as rays (band_samples.h), and the samples a
// triangle's bound reaches in a row are tested together, a SIMD vector at a time.

#include <functional>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/memory_trace.h"
#include "core/ray.h"
#include "core/samples.h"
#include "core/work_counts.h"
#include "rasterizer/common/frame_partition.h"
#include "rasterizer/common/moving_mesh.h"
#include "rasterizer/common/sample_rays.h"
#include "rasterizer/common/visibility_targets.h"

namespace patchsim {

enum class Bounding : std::uint8_t { TriangleBBox, Interval, Interleaved };

// triangle-bbox's bound: the convex hull of the moving, defocused triangle, the least-area
// rectangle (any orientation) that holds that hull, or its screen box.
enum class TriangleBound : std::uint8_t { Hull, OrientedBox, Box };
const char* triangleBoundName(TriangleBound bound);
bool parseTriangleBound(const std::string& name, TriangleBound& out);

// X(field, "Name", "unit", kind, "definition", charges...) (core/work_counts.h): one list, one
// counter per method and field ("BB/", "IV/", "IL/" + name).
#define PATCHSIM_BOUNDING_WORK(X)                                                                \
    X(triangleSetups, "Triangle setups", "setups", Sum,                                          \
      "Triangle screen bounds computed (per triangle; per time stratum; per interleaved pass), " \
      "or one for a triangle culled behind the camera",                                          \
      Op::TriangleSetups)                                                                        \
    X(screenTriangleSetups, "Screen triangle setups", "triangles", Sum,                          \
      "Static frames: triangles set up as three fixed-point edge functions (screen_triangle.h; " \
      "once per triangle, per interleaved pass)",                                                \
      Op::EdgeSetups)                                                                            \
    X(trianglesCulled, "Triangles culled behind the camera", "triangles", Sum,                   \
      "Triangles nearer than the near plane at both shutter ends, so at every time: no bounds, " \
      "no sample tested (their one setup is counted above)")                                     \
    X(fullScreenBounds, "Full-screen bounds", "setups", Sum,                                     \
      "Bounds that reached in front of the near plane: the whole screen")                        \
    X(samplesTested, "Samples tested", "samples", Sum,                                           \
      "Sample-triangle pairs tested: a watertight ray-triangle test each, or in a static frame " \
      "the three edge functions",                                                                \
      Op::SamplesTested)                                                                         \
    X(rayTriangleTests, "Ray-triangle tests", "tests", Sum,                                      \
      "Sample-triangle pairs tested with a watertight ray-triangle test", Op::RayTriangleTests)  \
    X(edgeTests, "Edge tests", "tests", Sum,                                                     \
      "Static frames: sample-triangle pairs tested with the three fixed-point edge functions "   \
      "(screen_triangle.h) instead of a ray",                                                    \
      Op::EdgeTests)                                                                             \
    X(lensTriangleSetups, "Lens triangle setups", "triangles", Sum,                              \
      "Defocus-only frames: triangles set up for the lens edge test (lens_triangle.h; once per " \
      "triangle, per interleaved pass)",                                                         \
      Op::LensEdgeSetups)                                                                        \
    X(lensEdgeTests, "Lens edge tests", "tests", Sum,                                            \
      "Defocus-only frames: sample-triangle pairs tested with the three lens edge functions "    \
      "(lens_triangle.h) instead of a ray",                                                      \
      Op::LensEdgeTests)                                                                         \
    X(samplesOutsideHull, "Samples outside the hull", "samples", Sum,                            \
      "Samples of the pixels a triangle's hull bound reaches found outside the hull by its 2D "  \
      "edge test, so not ray-tested (triangle-bbox with the hull or oriented-box bound)",        \
      Op::SamplesTested)                                                                         \
    X(visibilitySamples, "Visibility samples", "samples", Sum,                                   \
      "Tests that found a hit nearer than the sample's z-buffer entry", Op::DepthTests)          \
    X(transparentFragments, "Transparent fragments", "fragments", Sum,                           \
      "Transparent hits offered to a sample's layers", Op::TransparentFragments)                 \
    X(transparentOverflow, "Transparent overflow", "fragments", Sum,                             \
      "Transparent fragments dropped because a sample's layers were full")

struct BoundingCounters {
    PATCHSIM_BOUNDING_WORK(PATCHSIM_WORK_HANDLE)
};
const BoundingCounters& boundingCounters(Bounding method);

struct BoundingWork {
    PATCHSIM_BOUNDING_WORK(PATCHSIM_WORK_FIELD)
    void add(const BoundingWork& other);
    void flush(Bounding method) const;  // into that method's counters
    void charge(PatchOps& ops) const;
};

// Visibility samples / samples tested of one bounding method.
const RatioCounter& boundingSampleTestEfficiency(Bounding method);

// The interval method's K. `requested` > 0 is used as given; 0 gives one stratum per sample of a
// pixel, the setting of Fatahalian et al. 2009: the sampler stratifies time per pixel, one stratum
// per sample index, so every pixel then has exactly one sample in each stratum. When motion is not
// simulated every stratum's bounds are the same and K is 1: more strata would only set each
// triangle up again.
int intervalTimeStrata(int requested, int samplesPerPixel, bool motion);

// The K an interval render used (a Max counter: every render of a process raises it).
const Counter& intervalTimeStrataCounter();

struct BoundingOptions {
    Bounding method = Bounding::TriangleBBox;
    int timeStrata = 1;                         // interval: K (intervalTimeStrata)
    TriangleBound bound = TriangleBound::Hull;  // triangle-bbox
    int threads = 0;
    // The bands of rows this process rasterizes.
    FramePartition partition;
    // When the hardware models memory: each triangle's z reads and visibility writes, per band
    // (a trace of MemoryTrace::bands with FramePartition::kClasses bands).
    MemoryTrace* memoryTrace = nullptr;
};

// The bytes of samples prepared ahead (ray, screen position, lens, time; and for the interval
// method each sample's stratum order; band_samples.h) and of a row's candidate list that the
// bands rasterized at once hold: min(threads, bands) bands of the tallest band's rows. A render
// holds them to the memory budget with the film.
std::uint64_t boundingBandScratchBytes(int width, int height, int samplesPerPixel, Bounding method,
                                       int threads);

// Visibility of every mesh into `targets` (whose buffer must hold the frame); returns each
// mesh's work. Counters are not flushed.
std::vector<BoundingWork> rasterizeByBounds(const std::vector<MovingMesh>& meshes,
                                            const RayCaster& caster,
                                            const VisibilityTargets& targets,
                                            const BoundingOptions& options);

}  // namespace patchsim
