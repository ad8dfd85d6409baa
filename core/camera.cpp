#include "core/camera.h"

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

namespace patchsim {

namespace {
CameraKey blend(const CameraKey& a, const CameraKey& b, float t) {
    return {lerp(a.position, b.position, t), lerp(a.lookAt, b.lookAt, t), lerp(a.up, b.up, t)};
}
}  // namespace

Camera::Camera(const CameraDesc& desc, const ShutterDesc& shutter, int width, int height)
    : tanHalfFovY_(std::tan(glm::radians(desc.fovYDegrees) * 0.5f)),
      aspect_(float(width) / float(height)),
      near_(desc.nearPlane),
      far_(desc.farPlane),
      width_(width),
      height_(height) {
    keys_[0] = blend(desc.open, desc.close, shutter.open);
    keys_[1] = blend(desc.open, desc.close, shutter.close);
    for (int i = 0; i < 2; ++i)
        view_[i] = glm::lookAt(keys_[i].position, keys_[i].lookAt, keys_[i].up);
    moves_ = view_[0] != view_[1];
}

Mat4 Camera::worldToCameraAt(float t) const {
    if (!moves_ || t <= 0.0f) return view_[0];
    if (t >= 1.0f) return view_[1];
    const CameraKey k = blend(keys_[0], keys_[1], t);
    return glm::lookAt(k.position, k.lookAt, k.up);
}

bool Camera::cameraToRaster(const Vec3& p, Vec2& raster) const {
    const float depth = -p.z;
    if (!(depth >= near_)) return false;
    const float ndcX = p.x / (depth * tanHalfFovY_ * aspect_);
    const float ndcY = p.y / (depth * tanHalfFovY_);
    raster = {(ndcX * 0.5f + 0.5f) * float(width_), (0.5f - ndcY * 0.5f) * float(height_)};
    return true;
}

}  // namespace patchsim
