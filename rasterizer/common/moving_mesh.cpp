#include "rasterizer/common/moving_mesh.h"

namespace patchsim {

void toMovingMesh(const TessellatedPatch& patch, const Camera& camera, bool motion, int patchId,
                  bool opaque, MovingMesh& out) {
    const std::size_t n = patch.tessellation.points.size();
    out.patchId = patchId;
    out.objectId = patch.object;
    out.opaque = opaque;
    out.position0.resize(n);
    out.position1.resize(n);
    out.domain.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        out.position0[i] = camera.toCamera(patch.position[0][i], ShutterEnd::Open);
        out.position1[i] =
            motion ? camera.toCamera(patch.position[1][i], ShutterEnd::Close) : out.position0[i];
        out.domain[i] = {patch.tessellation.points[i].u, patch.tessellation.points[i].v};
    }
    out.indices = patch.tessellation.indices;
}

}  // namespace patchsim
