#pragma once
// The small camera the screen- and lens-triangle tests share, and the point it sees at a raster
// position.

#include "core/camera.h"
#include "core/ray.h"

namespace patchsim::test {

// 64 x 48 pixels, 60 degrees vertically, looking down -z from the origin.
inline Camera smallCamera() {
    CameraDesc desc;
    desc.open = {{0, 0, 0}, {0, 0, -1}, {0, 1, 0}};
    desc.close = desc.open;
    desc.fovYDegrees = 60.0f;
    return Camera(desc, ShutterDesc{}, 64, 48);
}

// The camera-space point the pinhole sees at raster (x, y) pixels, at depth `depth`.
inline Vec3 atRaster(const Camera& camera, float x, float y, float depth) {
    const Vec2 screen = rasterToScreen(camera, Vec2(x, y));
    return {screen.x * depth, screen.y * depth, -depth};
}

}  // namespace patchsim::test
