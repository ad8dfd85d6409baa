#include "tessellator/vertex_stage.h"

#include "pipeline/core/counters.h"

namespace patchsim {

PATCHSIM_COUNTER("VS/Control points", "points",
                 "Cage control points transformed (both shutter ends count once)", vsControlPoints);

ControlPoints runVertexStage(const ObjectDesc& object, const Cage& cage, const Cage* closeCage,
                             const ShutterDesc& shutter) {
    const Mat4 keyMatrix[2] = {object.open.matrix(), object.close.matrix()};
    const std::vector<Vec3>& keyPositions0 = cage.positions;
    const std::vector<Vec3>& keyPositions1 = closeCage ? closeCage->positions : cage.positions;
    const float shutterTime[2] = {shutter.open, shutter.close};
    ControlPoints out;
    for (int end = 0; end < 2; ++end) out.at[end].resize(cage.positions.size());
    const bool keysEqual = keyMatrix[0] == keyMatrix[1] && closeCage == nullptr;
    for (std::size_t i = 0; i < cage.positions.size(); ++i) {
        const Vec3 key0 = Vec3(keyMatrix[0] * Vec4(keyPositions0[i], 1.0f));
        const Vec3 key1 = keysEqual ? key0 : Vec3(keyMatrix[1] * Vec4(keyPositions1[i], 1.0f));
        for (int end = 0; end < 2; ++end) {
            const float t = shutterTime[end];
            // Exact at the keyframes and for points that do not move, so static is bitwise static.
            out.at[end][i] = (t == 0.0f || key0 == key1) ? key0
                             : t == 1.0f                 ? key1
                                                         : lerp(key0, key1, t);
        }
    }
    vsControlPoints += std::int64_t(cage.positions.size());
    return out;
}

}  // namespace patchsim
