#pragma once
// Sample-for-sample comparison of two renders, shared by the rasterizer and hard-case tests.

#include <array>
#include <cstddef>
#include <string>

#include "pipeline/driver/render.h"

namespace patchsim::test {

struct Comparison {
    std::size_t samples = 0, hits = 0;
    // Different nearest opaque hit (patch, triangle, depth or barycentric bits) or layers.
    std::size_t mismatches = 0;
    std::size_t falseRejects = 0;  // the second render hits where the first does not
};

Comparison compare(const RenderResult& a, const RenderResult& b);

// Renders with the patch method (1 and 2 threads, twice) and the reference method, and checks:
// no NaN or Inf in any depth, image or AOV; the patch method equals the reference sample for
// sample (so it never rejects a sample that holds a hit); identical images and counters for 1
// and 2 threads and across runs; and the same samples with the hierarchy's boxes stored in fp16,
// bf16 and fixed16.8 (rasterizer.node_format). Returns the patch render's comparison with the
// reference.
Comparison expectStableAndExact(const SceneDesc& scene, const std::string& what);

// The per-sample ray tests in fp16, bf16 and fixed16.8, emulated (slow: for the hard cases that
// name it). The ray-box tests (rasterizer.ray_box_format), bounded: the patch method equals the
// fp32 reference sample for sample. The ray-triangle tests (rasterizer.triangle_format), lossy,
// in both methods: no NaN or Inf, and the patch method equals the reference testing in the same
// format sample for sample (its culling grown by the test's reach keeps every sample the test
// gives). Returns the hits with each triangle format, in that order.
std::array<std::size_t, 3> expectNarrowRayTestsExact(const SceneDesc& scene,
                                                     const std::string& what);

}  // namespace patchsim::test
