#include "backend/shading.h"

#include <cmath>

#include "pipeline/core/counters.h"

namespace patchsim {

PATCHSIM_COUNTER("PS/Invocations", "invocations",
                 "Pixel shader runs: one per visible sample, at its own time", psInvocations);

Vec3 shadeRecord(const ShadingContext& c, const VisibilityRecord& r, float time) {
    if (!r.hit()) return kBackground;
    ++psInvocations;
    const TessellatedPatch& patch = (*c.patches)[std::size_t(r.patch)];
    const std::uint32_t* v = &patch.tessellation.indices[3 * std::size_t(r.triangle)];
    const float w[3] = {1.0f - r.b1 - r.b2, r.b1, r.b2};
    Vec3 normal(0);
    Vec2 uv(0);
    for (int k = 0; k < 3; ++k) {
        normal += w[k] * lerp(patch.normal[0][v[k]], patch.normal[1][v[k]], time);
        uv += w[k] * patch.surfaceUV[v[k]];
    }
    // Normals to camera space (rotation of the view at the nearer shutter end), facing the eye.
    const ShutterEnd end = time < 0.5f ? ShutterEnd::Open : ShutterEnd::Close;
    Vec3 n = Vec3(c.camera->worldToCamera(end) * Vec4(normal, 0.0f));
    const float len = glm::length(n);
    n = len > 0 ? n / len : Vec3(0, 0, 1);
    if (n.z < 0) n = -n;
    const Vec3 light = glm::normalize(Vec3(0.4f, 0.6f, 0.7f));
    const float lambert = std::max(0.0f, glm::dot(n, light));
    const MaterialDesc& material = c.frontEnd->objects()[std::size_t(patch.object)].desc.material;
    const bool check = ((int(std::floor(uv.x * 8.0f)) + int(std::floor(uv.y * 8.0f))) & 1) != 0;
    const Vec3 albedo = material.color * (check ? 0.55f : 1.0f);
    return albedo * (0.15f + 0.85f * lambert);
}

Image resolveBox(const ShadingContext& c, const VisibilityBuffer& buffer) {
    Image image(buffer.width(), buffer.height());
    const int spp = buffer.samplesPerPixel();
    for (int y = 0; y < buffer.height(); ++y) {
        for (int x = 0; x < buffer.width(); ++x) {
            Vec3 sum(0);
            for (int s = 0; s < spp; ++s)
                sum += shadeRecord(c, buffer.at(x, y, s), c.samples->sample(x, y, s).time);
            image.set(x, y, sum / float(spp));
        }
    }
    return image;
}

}  // namespace patchsim
