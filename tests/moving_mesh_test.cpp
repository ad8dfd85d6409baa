#include "rasterizer/common/moving_mesh.h"

#include <gtest/gtest.h>

#include <cmath>

namespace patchsim {
namespace {

MovingMesh twoTriangles() {
    MovingMesh m;
    m.position0 = {
        {0.1f, 0.2f, -5.3f}, {1.7f, 0.2f, -5.3f}, {0.1f, 1.9f, -5.1f}, {1.7f, 1.9f, -5.0f}};
    m.position1 = {
        {0.4f, 0.2f, -5.3f}, {2.0f, 0.3f, -5.3f}, {0.4f, 1.9f, -5.1f}, {2.1f, 1.9f, 3e5f}};
    m.indices = {0, 1, 2, 1, 3, 2};
    return m;
}

// Issue 35's vertex_format: every coordinate to the format's nearest value (fixed point's range
// ends for those beyond it), each vertex once for every triangle that shares it; fp32 as it is.
TEST(MovingMesh, PositionsAreStoredInTheVertexFormat) {
    const MovingMesh exact = twoTriangles();
    MovingMesh same = exact;
    storePositionsIn(same, NumberFormat::fp32());
    EXPECT_EQ(same.position0, exact.position0);
    EXPECT_EQ(same.position1, exact.position1);
    for (const NumberFormat format :
         {NumberFormat::fp16(), NumberFormat::bf16(), NumberFormat::fixed(16, 8)}) {
        MovingMesh m = exact;
        storePositionsIn(m, format);
        for (std::size_t v = 0; v < m.position0.size(); ++v)
            for (int a = 0; a < 3; ++a) {
                EXPECT_EQ(m.position0[v][a], roundTo(exact.position0[v][a], format));
                const float x = exact.position1[v][a];
                const float nearest = roundTo(x, format);
                EXPECT_EQ(m.position1[v][a],
                          std::isinf(nearest) ? roundTo(x, format, Rounding::Down) : nearest);
                EXPECT_LE(std::abs(m.position0[v][a] - exact.position0[v][a]),
                          0.5 * unitInLastPlace(exact.position0[v][a], format))
                    << formatName(format);
            }
        EXPECT_NE(m.position0[0].x, exact.position0[0].x) << formatName(format);  // 0.1 moved
        EXPECT_EQ(m.indices, exact.indices);  // shared vertices stay shared
    }
    MovingMesh fixed = exact;
    storePositionsIn(fixed, NumberFormat::fixed(16, 8));
    EXPECT_EQ(fixed.position1[3].z, 32768.0f - 1.0f / 256.0f);  // 3e5 saturates at the range end
    MovingMesh half = exact;
    storePositionsIn(half, NumberFormat::fp16());
    EXPECT_EQ(half.position1[3].z, 65504.0f);  // saturates at fp16's largest, not infinity
}

}  // namespace
}  // namespace patchsim
