#pragma once
// A range of shutter times [lower, upper] (after Embree's BBox1f).
//
// Representation
// --------------
// Two floats in [0, 1]; empty when not lower <= upper (the `empty()` range is [1, 0], the identity
// of `extend`). Used for a tile's times of possible overlap, narrowed at the hierarchy's leaves.

#include <algorithm>

namespace patchsim {

struct TimeRange {
    float lower = 0.0f;
    float upper = 1.0f;

    static constexpr TimeRange shutter() { return {0.0f, 1.0f}; }
    static constexpr TimeRange empty() { return {1.0f, 0.0f}; }

    bool isEmpty() const { return !(lower <= upper); }  // NaN bounds count as empty
    bool contains(float t) const { return t >= lower && t <= upper; }
    void extend(const TimeRange& o) {
        lower = std::min(lower, o.lower);
        upper = std::max(upper, o.upper);
    }
    void intersect(const TimeRange& o) {
        lower = std::max(lower, o.lower);
        upper = std::min(upper, o.upper);
    }
    bool operator==(const TimeRange&) const = default;
};

}  // namespace patchsim
