#include "tessellator/vertex_stage.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/counters.h"

namespace patchsim {

const Counter vsControlPoints{"VS/Control points", "points",
                              "Cage control points transformed (both shutter ends count once)"};

namespace {

// Keyframe positions that differ from the open ones by rounding only (relative to the cage's size).
constexpr float kReturnTolerance = 1e-5f;

// In double: the float length of a cage wider than about 1e19 overflows, and an infinite
// tolerance would take any motion for none. A keyframe beyond the float range is never back where
// it started: it is kept, for the front end to refuse (front_end.cpp), not hidden.
bool returnsToStart(const std::vector<Vec3>& key0, const std::vector<Vec3>& key1) {
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    double moved = 0;
    for (std::size_t i = 0; i < key0.size(); ++i) {
        const glm::dvec3 a(key0[i]), b(key1[i]);
        if (!std::isfinite(b.x) || !std::isfinite(b.y) || !std::isfinite(b.z)) return false;
        lo = glm::min(lo, a);
        hi = glm::max(hi, a);
        moved = std::max(moved, glm::length(b - a));
    }
    return moved > 0 && moved <= double(kReturnTolerance) * glm::length(hi - lo);
}

}  // namespace

ControlPoints runVertexStage(const ObjectDesc& object, const Cage& cage, const Cage* closeCage,
                             const ShutterDesc& shutter) {
    const Mat4 keyMatrix[2] = {object.open.matrix(), object.close.matrix()};
    const std::vector<Vec3>& keyPositions0 = cage.positions;
    const std::vector<Vec3>& keyPositions1 = closeCage ? closeCage->positions : cage.positions;
    const bool keysEqual = keyMatrix[0] == keyMatrix[1] && closeCage == nullptr;
    std::vector<Vec3> key[2];
    for (int k = 0; k < 2; ++k) key[k].resize(cage.positions.size());
    for (std::size_t i = 0; i < cage.positions.size(); ++i) {
        key[0][i] = Vec3(keyMatrix[0] * Vec4(keyPositions0[i], 1.0f));
        key[1][i] = keysEqual ? key[0][i] : Vec3(keyMatrix[1] * Vec4(keyPositions1[i], 1.0f));
    }
    ControlPoints out;
    if (!keysEqual && returnsToStart(key[0], key[1])) {
        out.keyframesReturnToStart = true;
        key[1] = key[0];
    }
    const float shutterTime[2] = {shutter.open, shutter.close};
    for (int end = 0; end < 2; ++end) {
        out.at[end].resize(cage.positions.size());
        const float t = shutterTime[end];
        for (std::size_t i = 0; i < cage.positions.size(); ++i) {
            const Vec3& a = key[0][i];
            const Vec3& b = key[1][i];
            // Exact at the keyframes and for points that do not move, so static is bitwise static.
            out.at[end][i] = (t == 0.0f || a == b) ? a : t == 1.0f ? b : lerp(a, b, t);
        }
    }
    vsControlPoints += std::int64_t(cage.positions.size());
    return out;
}

}  // namespace patchsim
