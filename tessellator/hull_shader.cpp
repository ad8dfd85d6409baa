#include "tessellator/hull_shader.h"

#include <algorithm>
#include <bit>
#include <cmath>

namespace patchsim {

namespace {

bool isNaN(float f) {
    return f != f;
}

// Clamp to [1, inf), NaN to 1.
float cleanup(float f) {
    return (isNaN(f) || f < 1.0f) ? 1.0f : f;
}

float clampToMode(float f, Partitioning p) {
    switch (p) {
        case Partitioning::Pow2:
        case Partitioning::Integer:
            return std::clamp(f, 1.0f, 64.0f);
        case Partitioning::FractionalOdd:
            return std::clamp(f, 1.0f, 63.0f);
        case Partitioning::FractionalEven:
            return std::clamp(f, 2.0f, 64.0f);
    }
    return f;
}

float roundUp(float f, Partitioning p) {
    if (p == Partitioning::Pow2) {
        // Next power of two via the exponent field, as the HLSL helper does.
        const std::uint32_t bits = std::bit_cast<std::uint32_t>(f);
        if (bits & 0x007fffffu) return std::bit_cast<float>((bits & 0x7f800000u) + 0x00800000u);
        return f;
    }
    if (p == Partitioning::Integer) return std::ceil(f);
    return f;
}

bool integerLike(Partitioning p) {
    return p == Partitioning::Integer || p == Partitioning::Pow2;
}

bool oddInside(float inside, Partitioning p) {
    if (integerLike(p)) return !(static_cast<int>(inside) % 2 == 0 || inside == 1.0f);
    return p == Partitioning::FractionalOdd;
}

float reduce(InsideReduction r, float a, float b) {
    switch (r) {
        case InsideReduction::Min:
            return std::min(a, b);
        case InsideReduction::Max:
            return std::max(a, b);
        case InsideReduction::Average:
            return (a + b) / 2;
    }
    return a;
}

// An odd inside factor under 3 comes in to the average (or max) of its edges, capped at 3.
float raisePictureFrame(float inside, float a, float b, const HullShaderConfig& c) {
    if (!oddInside(inside, c.partitioning) || inside >= 3.0f) return inside;
    const float r = c.insideReduction == InsideReduction::Max ? std::max(a, b) : (a + b) / 2;
    float raised = clampToMode(std::min(3.0f, r), c.partitioning);
    if (c.partitioning == Partitioning::Integer) raised = std::ceil(raised);
    return raised;
}

}  // namespace

QuadTessFactors processQuadFactors(const float edges[4], const HullShaderConfig& c) {
    QuadTessFactors f;
    for (int e = 0; e < 4; ++e) f.edge[e] = edges[e];
    for (int e = 0; e < 4; ++e) {
        if (!(edges[e] > 0)) {  // culled: pass through, the TS culls
            f.inside[0] = f.inside[1] = 0;
            return f;
        }
    }
    float cleaned[4];
    for (int e = 0; e < 4; ++e) {
        cleaned[e] = cleanup(edges[e]);
        f.edge[e] = clampToMode(roundUp(cleaned[e], c.partitioning), c.partitioning);
    }
    // Inside along u spans the v=0 and v=1 edges; inside along v the u=0 and u=1 edges.
    float inside[2] = {reduce(c.insideReduction, cleaned[1], cleaned[3]),
                       reduce(c.insideReduction, cleaned[0], cleaned[2])};
    for (float& in : inside)
        in = clampToMode(roundUp(clampToMode(in, c.partitioning), c.partitioning), c.partitioning);
    inside[0] = raisePictureFrame(inside[0], cleaned[1], cleaned[3], c);
    inside[1] = raisePictureFrame(inside[1], cleaned[0], cleaned[2], c);
    // The picture frame interpolates in on all sides as much as the smaller axis allows.
    for (int axis = 0; axis < 2; ++axis) {
        const float other = inside[(axis + 1) & 1];
        if (oddInside(inside[axis], c.partitioning) && inside[axis] < 3.0f && inside[axis] < other)
            inside[axis] = std::min(other, 3.0f);
    }
    f.inside[0] = inside[0];
    f.inside[1] = inside[1];
    return f;
}

TriTessFactors processTriFactors(const float edges[3], const HullShaderConfig& c) {
    TriTessFactors f;
    for (int e = 0; e < 3; ++e) f.edge[e] = edges[e];
    for (int e = 0; e < 3; ++e) {
        if (!(edges[e] > 0)) {
            f.inside = 0;
            return f;
        }
    }
    float cleaned[3];
    for (int e = 0; e < 3; ++e) {
        cleaned[e] = cleanup(edges[e]);
        f.edge[e] = clampToMode(roundUp(cleaned[e], c.partitioning), c.partitioning);
    }
    float inside = 0;
    switch (c.insideReduction) {
        case InsideReduction::Min:
            inside = std::min({cleaned[0], cleaned[1], cleaned[2]});
            break;
        case InsideReduction::Max:
            inside = std::max({cleaned[0], cleaned[1], cleaned[2]});
            break;
        case InsideReduction::Average:
            inside = (cleaned[0] + cleaned[1] + cleaned[2]) / 3;
            break;
    }
    inside = clampToMode(inside, c.partitioning);
    inside = roundUp(inside, c.partitioning);
    if (oddInside(inside, c.partitioning) && inside < 3.0f) {
        const float r = c.insideReduction == InsideReduction::Max
                            ? std::max({cleaned[0], cleaned[1], cleaned[2]})
                            : (cleaned[0] + cleaned[1] + cleaned[2]) / 3;
        inside = clampToMode(std::min(3.0f, r), c.partitioning);
        if (c.partitioning == Partitioning::Integer) inside = std::ceil(inside);
    }
    f.inside = inside;
    return f;
}

}  // namespace patchsim
