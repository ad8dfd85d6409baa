#pragma once
// The vertex shader stage (VS): a cage's control points placed in the world at shutter open and
// close. Object keyframes are the scene's transforms (and optional per-vertex close positions);
// the stage re-keys them to the shutter interval, so t=0 and t=1 here are the shutter's ends.
// Motion in between is linear in the control points, hence linear for every limit-surface point.

#include <vector>

#include "core/math.h"
#include "core/obj_reader.h"
#include "core/scene.h"

namespace patchsim {

struct ControlPoints {
    std::vector<Vec3> at[2];  // indexed by ShutterEnd
    // The keyframes differ but put every control point back where it started (a 360-degree
    // turn): with straight-line motion between the shutter ends that is no motion, and the close
    // positions are made exactly the open ones.
    bool keyframesReturnToStart = false;
    bool moves() const { return at[0] != at[1]; }
};

// `closeCage` is null when the object has no per-vertex close positions.
ControlPoints runVertexStage(const ObjectDesc& object, const Cage& cage, const Cage* closeCage,
                             const ShutterDesc& shutter);

}  // namespace patchsim
