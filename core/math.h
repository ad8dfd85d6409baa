#pragma once
// Small math vocabulary on top of GLM. Geometry is single precision (as a GPU would keep it);
// accumulations that must not drift use double explicitly where they happen.

#include <glm/glm.hpp>

namespace patchsim {

using Vec2 = glm::vec2;
using Vec3 = glm::vec3;
using Vec4 = glm::vec4;
using Mat4 = glm::mat4;

inline Vec3 lerp(const Vec3& a, const Vec3& b, float t) {
    return (1.0f - t) * a + t * b;
}

// Shutter time: 0 is the shutter opening, 1 its closing. Geometry moves linearly in between.
enum class ShutterEnd : int { Open = 0, Close = 1 };

}  // namespace patchsim
