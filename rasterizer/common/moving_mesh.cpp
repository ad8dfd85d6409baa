#include "rasterizer/common/moving_mesh.h"

#include <cmath>

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

void storePositionsIn(MovingMesh& mesh, const NumberFormat& format) {
    if (format == NumberFormat::fp32()) return;
    const auto store = [&](Vec3& p) {
        for (int axis = 0; axis < 3; ++axis) {
            const float x = p[axis];
            p[axis] = roundTo(x, format);
            // A float format's overflow saturates at its largest value, as fixed point's does:
            // an infinite vertex would make every blend through it NaN.
            if (std::isinf(p[axis]) && std::isfinite(x))
                p[axis] = roundTo(x, format, x > 0 ? Rounding::Down : Rounding::Up);
        }
    };
    for (Vec3& p : mesh.position0) store(p);
    for (Vec3& p : mesh.position1) store(p);
}

}  // namespace patchsim
