#pragma once
// The camera at shutter open and close.
//
// Representation
// --------------
// Two world-to-camera matrices (glm::lookAt convention: the camera looks down -z, +y up), one per
// shutter end, already re-keyed to the shutter interval; a symmetric perspective frustum given by
// tan(fov/2) and the aspect ratio; and the raster mapping (x right, y down, pixel centres at
// +0.5). A point's camera-space position between the ends is the linear blend of its positions
// at the ends, which is what the rasterizer's moving boxes bound.

#include "core/math.h"
#include "core/scene.h"

namespace patchsim {

class Camera {
  public:
    Camera(const CameraDesc& desc, const ShutterDesc& shutter, int width, int height);

    const Mat4& worldToCamera(ShutterEnd end) const { return view_[int(end)]; }
    // The camera at shutter time t (its keyframes blended, as the scene describes its motion),
    // e.g. to shade a t-fragment with the view it was seen from.
    Mat4 worldToCameraAt(float t) const;
    Vec3 toCamera(const Vec3& world, ShutterEnd end) const {
        return Vec3(view_[int(end)] * Vec4(world, 1.0f));
    }
    // Camera space to raster; false when the point is not in front of the near plane.
    bool cameraToRaster(const Vec3& p, Vec2& raster) const;

    bool moves() const { return moves_; }
    float tanHalfFovY() const { return tanHalfFovY_; }
    float aspect() const { return aspect_; }
    float nearPlane() const { return near_; }
    float farPlane() const { return far_; }
    int width() const { return width_; }
    int height() const { return height_; }

  private:
    Mat4 view_[2];
    CameraKey keys_[2];  // at shutter open and close
    float tanHalfFovY_;
    float aspect_;
    float near_, far_;
    int width_, height_;
    bool moves_;
};

}  // namespace patchsim
