#include "backend/shading/t_fragment.h"

#include <cmath>

#include "core/counters.h"

namespace patchsim {

namespace {
const Counter psInvocations{"PS/Invocations", "invocations",
                            "Pixel shader runs (t-fragments shaded)"};
const Counter psReused{"PS/Reused", "samples",
                       "Samples that reused a colour shaded for the same pixel and triangle "
                       "(per-pixel-primitive rate)"};
}  // namespace

const ShadingCounters& shadingCounters() {
    static const ShadingCounters counters{psInvocations, psReused};
    return counters;
}

double shadingReuseRate(const CounterValues& values) {
    const std::int64_t shaded = values[psInvocations], reused = values[psReused];
    return shaded + reused ? double(reused) / double(shaded + reused) : 0.0;
}

const char* shadingRateName(ShadingRate r) {
    return r == ShadingRate::PerFragment ? "per-fragment" : "per-pixel-primitive";
}

namespace {

const MaterialDesc& materialOf(const ShadingContext& c, const TessellatedPatch& patch) {
    return c.frontEnd->objects()[std::size_t(patch.object)].desc.material;
}

float opacityAt(const MaterialDesc& m, float time) {
    return (1.0f - time) * m.opacity + time * m.closeOpacity;
}

}  // namespace

SurfaceAttributes interpolateAttributes(const ShadingContext& c, const VisibilityRecord& r) {
    SurfaceAttributes a;
    interpolateAttributes(c, r, a);
    return a;
}

void interpolateAttributes(const ShadingContext& c, const VisibilityRecord& r,
                           SurfaceAttributes& a) {
    const float time = r.time;
    const TessellatedPatch& patch = (*c.patches)[std::size_t(r.patch)];
    const MovingMesh& mesh = (*c.meshes)[std::size_t(r.patch)];
    const std::uint32_t* v = &patch.tessellation.indices[3 * std::size_t(r.triangle)];
    const float w[3] = {1.0f - r.b1 - r.b2, r.b1, r.b2};
    a.normal = a.cameraPosition0 = a.cameraPosition1 = Vec3(0);
    a.surfaceUV = a.domainUV = Vec2(0);
    for (int k = 0; k < 3; ++k) {
        a.normal += w[k] * lerp(patch.normal[0][v[k]], patch.normal[1][v[k]], time);
        a.surfaceUV += w[k] * patch.surfaceUV[v[k]];
        a.domainUV +=
            w[k] * Vec2(patch.tessellation.points[v[k]].u, patch.tessellation.points[v[k]].v);
        a.cameraPosition0 += w[k] * mesh.position0[v[k]];
        a.cameraPosition1 += w[k] * mesh.position1[v[k]];
    }
    const MaterialDesc& m = materialOf(c, patch);
    a.color = lerp(m.color, m.closeColor, time);
    a.opacity = opacityAt(m, time);
    a.unlit = m.unlit;
}

float surfaceOpacity(const ShadingContext& c, const VisibilityRecord& r) {
    return opacityAt(materialOf(c, (*c.patches)[std::size_t(r.patch)]), r.time);
}

Vec3 shadeFragment(const ShadingContext& c, const SurfaceAttributes& a, float time) {
    ++psInvocations;
    if (a.unlit) return a.color;
    // Normal to camera space with the camera of the fragment's time, turned towards the eye.
    Vec3 n = Vec3(c.camera->worldToCameraAt(time) * Vec4(a.normal, 0.0f));
    const float len = glm::length(n);
    n = len > 0 && std::isfinite(len) ? n / len : Vec3(0, 0, 1);
    if (n.z < 0) n = -n;
    const Vec3 light = glm::normalize(Vec3(0.4f, 0.6f, 0.7f));
    const float lambert = std::max(0.0f, glm::dot(n, light));
    const bool check =
        ((int(std::floor(a.surfaceUV.x * 8.0f)) + int(std::floor(a.surfaceUV.y * 8.0f))) & 1) != 0;
    return a.color * (check ? 0.55f : 1.0f) * (0.15f + 0.85f * lambert);
}

}  // namespace patchsim
