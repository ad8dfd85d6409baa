#pragma once
// `patchsim tessellate`: the whole scene through IA, VS, HS, TS and DS, written as an OBJ mesh
// at a chosen shutter time, for any mesh viewer. Points that patches share (bitwise-identical
// positions at both shutter ends) are welded, so shared edges show as connected.

#include <ostream>

#include "tessellator/front_end.h"

namespace patchsim {

struct TessellateOptions {
    float time = 0.0f;  // shutter time in [0, 1]
    int threads = 0;    // 0: all hardware threads
};

struct TessellationSummary {
    std::size_t patches = 0;
    std::size_t vertices = 0;  // after welding
    std::size_t triangles = 0;
};

TessellationSummary writeTessellationObj(const FrontEnd& frontEnd, const TessellateOptions& options,
                                         std::ostream& out);

}  // namespace patchsim
