#pragma once
// `patchsim info`: what a scene holds, which effects it calls for and the mode chosen.

#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "core/effects.h"
#include "tessellator/front_end.h"

namespace patchsim {

struct SceneInfo {
    std::size_t objects = 0;
    std::size_t cageFaces = 0;
    std::size_t patches = 0;
    std::size_t culledPatches = 0;
    std::uint64_t domainPoints = 0;
    std::uint64_t triangles = 0;
    Effects called;
    Effects simulated;
};

// Runs HS and TS over every patch (no DS) to count points and triangles at the scene's factors.
SceneInfo gatherSceneInfo(const FrontEnd& frontEnd, const EffectOverrides& overrides, int threads);
void printSceneInfo(std::ostream& out, const FrontEnd& frontEnd, const SceneInfo& info);

// What a user should know about how an object is simulated: cage warnings, faces evaluated on
// Far's patch table, keyframes that return to the start. `info` lists them; `render` prints them.
std::vector<std::string> objectNotes(const SceneObject& object);

}  // namespace patchsim
