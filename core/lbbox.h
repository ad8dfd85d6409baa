#pragma once
// Axis-aligned boxes and linearly moving boxes (after Embree's LBBox).
//
// Representation
// --------------
// A Box3 is min and max corners; an empty box has min > max (+inf / -inf), so merging with it is
// the identity. An LBBox is two boxes, at shutter open (t=0) and close (t=1); at time t the bound
// is the component-wise blend B(t) = (1-t) B0 + t B1. Merging merges the two ends separately.
// Blending uses the same float expression as the vertex blend (lerp), and rounded multiply and add
// are monotone, so a vertex blended to t always lies inside its box blended to t.

#include <limits>

#include "core/math.h"

namespace patchsim {

struct Box3 {
    Vec3 lower{std::numeric_limits<float>::infinity()};
    Vec3 upper{-std::numeric_limits<float>::infinity()};

    bool empty() const { return lower.x > upper.x || lower.y > upper.y || lower.z > upper.z; }
    void extend(const Vec3& p) {
        lower = glm::min(lower, p);
        upper = glm::max(upper, p);
    }
    void extend(const Box3& b) {
        lower = glm::min(lower, b.lower);
        upper = glm::max(upper, b.upper);
    }
    Vec3 corner(int i) const {
        return {(i & 1) ? upper.x : lower.x, (i & 2) ? upper.y : lower.y,
                (i & 4) ? upper.z : lower.z};
    }
};

struct LBBox {
    Box3 bounds0;  // t = 0
    Box3 bounds1;  // t = 1

    void extend(const Vec3& p0, const Vec3& p1) {
        bounds0.extend(p0);
        bounds1.extend(p1);
    }
    void extend(const LBBox& b) {
        bounds0.extend(b.bounds0);
        bounds1.extend(b.bounds1);
    }
    bool empty() const { return bounds0.empty(); }
    Box3 at(float t) const {
        return {lerp(bounds0.lower, bounds1.lower, t), lerp(bounds0.upper, bounds1.upper, t)};
    }
    bool isStatic() const {
        return bounds0.lower == bounds1.lower && bounds0.upper == bounds1.upper;
    }
};

}  // namespace patchsim
