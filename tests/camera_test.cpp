#include "core/camera.h"

#include <gtest/gtest.h>

namespace patchsim {
namespace {

TEST(Camera, ProjectsTheLookAtPointToTheImageCentre) {
    CameraDesc desc;
    desc.open = {{0, 0, 5}, {0, 0, 0}, {0, 1, 0}};
    desc.close = desc.open;
    const Camera camera(desc, {}, 200, 100);
    Vec2 r;
    ASSERT_TRUE(camera.cameraToRaster(camera.toCamera({0, 0, 0}, ShutterEnd::Open), r));
    EXPECT_FLOAT_EQ(r.x, 100.0f);
    EXPECT_FLOAT_EQ(r.y, 50.0f);
    // +y in the world is up in the image (smaller raster y).
    ASSERT_TRUE(camera.cameraToRaster(camera.toCamera({0, 1, 0}, ShutterEnd::Open), r));
    EXPECT_LT(r.y, 50.0f);
    EXPECT_FALSE(camera.cameraToRaster(camera.toCamera({0, 0, 6}, ShutterEnd::Open), r));
    EXPECT_FALSE(camera.moves());
}

TEST(Camera, ShutterReKeysAMovingCamera) {
    CameraDesc desc;
    desc.open = {{0, 0, 5}, {0, 0, 0}, {0, 1, 0}};
    desc.close = {{4, 0, 5}, {4, 0, 0}, {0, 1, 0}};
    ShutterDesc shutter{0.25f, 0.5f};
    const Camera camera(desc, shutter, 100, 100);
    EXPECT_TRUE(camera.moves());
    EXPECT_NEAR(camera.toCamera({1, 0, 0}, ShutterEnd::Open).x, 0.0f, 1e-6f);
    EXPECT_NEAR(camera.toCamera({2, 0, 0}, ShutterEnd::Close).x, 0.0f, 1e-6f);
}

}  // namespace
}  // namespace patchsim
