#include "backend/tfragment/tfragment_generation.h"

#include <algorithm>
#include <cmath>

#include "tessellator/front_end.h"

namespace patchsim {

namespace {

// A raster of the screen plus the guard band, indexed from (-guard, -guard).
struct GuardRaster {
    int guard, width, height;  // width and height include the band
    std::size_t index(int x, int y) const {
        return std::size_t(y + guard) * std::size_t(width) + std::size_t(x + guard);
    }
    bool contains(int x, int y) const {
        return x >= -guard && y >= -guard && x < width - guard && y < height - guard;
    }
};

struct RasterFragment {
    float depth;
    std::int32_t patch;
    std::uint32_t triangle;
    float b1, b2;  // perspective-correct, vertices 1 and 2
};

// Calls visit(x, y, fragment) for every pixel centre the triangle covers at t = 1.
// `frontOnly`: skip triangles facing away from the camera (closed surfaces' far sides).
template <typename Visit>
void rasterizeTriangle(const Camera& camera, const MovingMesh& mesh, std::uint32_t tri,
                       const GuardRaster& raster, bool frontOnly, const Visit& visit) {
    const std::uint32_t* v = &mesh.indices[3 * std::size_t(tri)];
    Vec2 s[3];
    float depth[3];
    for (int k = 0; k < 3; ++k) {
        const Vec3& p = mesh.position1[v[k]];
        depth[k] = -p.z;
        if (!camera.cameraToRaster(p, s[k])) return;  // reaches the near plane: not rasterized
    }
    const float area =
        (s[1].x - s[0].x) * (s[2].y - s[0].y) - (s[2].x - s[0].x) * (s[1].y - s[0].y);
    if (area == 0.0f || !std::isfinite(area)) return;
    // Raster y points down: a triangle counter-clockwise in camera space (facing the camera)
    // has a negative area here.
    if (frontOnly && area > 0.0f) return;
    // Clamped as floats first: a vertex near the near plane can project far outside int range.
    auto pixel = [](float value, int lo, int hi) {
        return int(std::clamp(value, float(lo), float(hi)));
    };
    const int xHi = raster.width - raster.guard - 1, yHi = raster.height - raster.guard - 1;
    const int x0 = pixel(std::floor(std::min({s[0].x, s[1].x, s[2].x})), -raster.guard, xHi);
    const int x1 = pixel(std::ceil(std::max({s[0].x, s[1].x, s[2].x})), -raster.guard, xHi);
    const int y0 = pixel(std::floor(std::min({s[0].y, s[1].y, s[2].y})), -raster.guard, yHi);
    const int y1 = pixel(std::ceil(std::max({s[0].y, s[1].y, s[2].y})), -raster.guard, yHi);
    for (int y = y0; y <= y1; ++y) {
        for (int x = x0; x <= x1; ++x) {
            const Vec2 c(float(x) + 0.5f, float(y) + 0.5f);
            auto edge = [&](const Vec2& a, const Vec2& b) {
                return (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
            };
            const float w0 = edge(s[1], s[2]) / area, w1 = edge(s[2], s[0]) / area,
                        w2 = edge(s[0], s[1]) / area;
            if (w0 < 0 || w1 < 0 || w2 < 0) continue;
            // Perspective-correct barycentrics: screen weights over depth, normalised.
            const float q0 = w0 / depth[0], q1 = w1 / depth[1], q2 = w2 / depth[2];
            const float sum = q0 + q1 + q2;
            visit(x, y,
                  RasterFragment{1.0f / sum, mesh.patchOf(tri), mesh.triangleInPatchOf(tri),
                                 q1 / sum, q2 / sum});
        }
    }
}

Vec3 pointAt(const MovingMesh& mesh, std::uint32_t tri, float b1, float b2, bool close) {
    const std::uint32_t* v = &mesh.indices[3 * std::size_t(tri)];
    const auto& p = close ? mesh.position1 : mesh.position0;
    return (1.0f - b1 - b2) * p[v[0]] + b1 * p[v[1]] + b2 * p[v[2]];
}

// Disocclusion map flags: what may show behind a pixel's first layer during the frame.
constexpr std::uint8_t kMotionEdge = 1, kDepthEdge = 2;

// The motion disocclusion map OR'ed with depth edges.
std::vector<std::uint8_t> disocclusionMap(const Camera& camera, const GuardRaster& r,
                                          const std::vector<float>& depth1,
                                          const std::vector<Vec2>& velocity, bool defocus,
                                          const TFragmentOptions& o) {
    std::vector<std::uint8_t> map(depth1.size(), 0);
    const int x0 = -r.guard, y0 = -r.guard, x1 = r.width - r.guard, y1 = r.height - r.guard;
    for (int y = y0; y < y1; ++y) {
        for (int x = x0; x < x1; ++x) {
            const std::size_t i = r.index(x, y);
            float spread = 0;
            for (const auto& [nx, ny] : {std::pair{x + 1, y}, std::pair{x, y - 1}}) {
                if (!r.contains(nx, ny)) continue;
                spread = std::max(spread, glm::length(velocity[r.index(nx, ny)] - velocity[i]));
            }
            if (spread > o.disocclusionPixels) {
                // At most the raster's size (a velocity can be huge near the camera plane).
                const int radius = int(std::ceil(std::min(spread, float(r.width + r.height))));
                for (int dy = -radius; dy <= radius; ++dy)
                    for (int dx = -radius; dx <= radius; ++dx)
                        if (r.contains(x + dx, y + dy)) map[r.index(x + dx, y + dy)] |= kMotionEdge;
            }
            if (!defocus || !std::isfinite(depth1[i]) || x == x0 || y == y0 || x == x1 - 1 ||
                y == y1 - 1)
                continue;
            const float far = camera.farPlane();
            auto d = [&](int px, int py) {
                const float z = depth1[r.index(px, py)];
                return std::isfinite(z) ? z : far;
            };
            const float laplacian =
                d(x + 1, y) + d(x - 1, y) + d(x, y + 1) + d(x, y - 1) - 4 * d(x, y);
            if (std::abs(laplacian) / d(x, y) > o.laplacianThreshold) map[i] |= kDepthEdge;
        }
    }
    return map;
}

// Whether the triangle stays put over the frame (camera space, so a moving camera moves it).
bool stays(const MovingMesh& mesh, std::uint32_t tri) {
    const std::uint32_t* v = &mesh.indices[3 * std::size_t(tri)];
    return std::all_of(v, v + 3,
                       [&](std::uint32_t k) { return mesh.position0[k] == mesh.position1[k]; });
}

// The depth behind which nothing seen at the pixel during the frame lies; `still` is the depth of
// its nearest surface that stays put.
float cullingDepth(std::uint8_t flags, float depth1, float depth2, float still) {
    // Lens rays look past a depth edge to the second layer (the paper's limited disocclusion).
    const float lens = flags & kDepthEdge ? depth2 : depth1;
    // Motion can uncover anything behind surfaces that move; only one that stays put hides what
    // is behind it for the whole frame. The paper's second layer is no such bound: where two
    // moving objects overlap at t = 1, the static wall behind both is the third layer.
    const float motion = flags & kMotionEdge ? still : depth1;
    return std::max(lens, motion);
}

}  // namespace

TFragmentSet generateTFragments(const ShadingContext& c, bool defocus, const TFragmentOptions& o,
                                TFragmentWork& work) {
    const Camera& camera = *c.camera;
    const GuardRaster r{o.guardBand, camera.width() + 2 * o.guardBand,
                        camera.height() + 2 * o.guardBand};
    const std::size_t n = std::size_t(r.width) * std::size_t(r.height);
    const float inf = std::numeric_limits<float>::infinity();
    std::vector<float> depth1(n, inf), depth2(n, inf), still(n, inf);
    std::vector<RasterFragment> first(n, RasterFragment{inf, -1, 0, 0, 0});
    const std::vector<MovingMesh>& meshes = *c.meshes;
    // Pass 1: the opaque surfaces' two nearest depth layers (a second layer is another surface:
    // farther by more than a relative 1e-3, so a shared edge is not a layer), and the nearest one
    // that stays put.
    for (const MovingMesh& m : meshes) {
        if (!m.opaque) continue;
        for (std::uint32_t t = 0; t < m.triangleCount(); ++t) {
            const bool stationary = stays(m, t);
            rasterizeTriangle(camera, m, t, r, true, [&](int x, int y, const RasterFragment& f) {
                ++work.rasterizedFragments;
                const std::size_t i = r.index(x, y);
                if (stationary) still[i] = std::min(still[i], f.depth);
                if (f.depth < depth1[i]) {
                    if (depth1[i] > f.depth * 1.001f) depth2[i] = depth1[i];
                    depth1[i] = f.depth;
                    first[i] = f;
                } else if (f.depth > depth1[i] * 1.001f && f.depth < depth2[i]) {
                    depth2[i] = f.depth;
                }
            });
        }
    }
    // The first layer's velocity (pixels over the frame).
    std::vector<Vec2> velocity(n, Vec2(0));
    for (std::size_t i = 0; i < n; ++i) {
        const RasterFragment& f = first[i];
        if (f.patch < 0) continue;
        const MovingMesh& m = meshes[std::size_t(f.patch)];
        Vec2 a, b;
        if (camera.cameraToRaster(pointAt(m, f.triangle, f.b1, f.b2, false), a) &&
            camera.cameraToRaster(pointAt(m, f.triangle, f.b1, f.b2, true), b))
            velocity[i] = b - a;
    }
    const std::vector<std::uint8_t> map = disocclusionMap(camera, r, depth1, velocity, defocus, o);
    std::vector<float> culling(n);
    for (std::size_t i = 0; i < n; ++i) {
        culling[i] = cullingDepth(map[i], depth1[i], depth2[i], still[i]);
        work.disoccludedPixels += map[i] != 0;
    }
    // Pass 2: every fragment in front of the culling depth becomes a t-fragment.
    TFragmentSet set;
    const float pixelPerDepth = 2.0f * camera.tanHalfFovY() / float(camera.height());
    for (const MovingMesh& m : meshes) {
        for (std::uint32_t t = 0; t < m.triangleCount(); ++t) {
            rasterizeTriangle(camera, m, t, r, m.opaque,
                              [&](int x, int y, const RasterFragment& f) {
                                  ++work.rasterizedFragments;
                                  if (!(f.depth <= culling[r.index(x, y)] * 1.0001f)) {
                                      ++work.culled;
                                      return;
                                  }
                                  const MovingMesh& own = meshes[std::size_t(f.patch)];
                                  // The fragment's triangle in its own patch's mesh (its hit ids
                                  // are patch-local).
                                  TFragment tf{pointAt(own, f.triangle, f.b1, f.b2, false),
                                               pointAt(own, f.triangle, f.b1, f.b2, true),
                                               0.8660254f * pixelPerDepth * f.depth,
                                               f.patch,
                                               f.triangle,
                                               f.b1,
                                               f.b2};
                                  (m.opaque ? set.opaque : set.transparent).push_back(tf);
                              });
        }
    }
    work.generatedOpaque += std::int64_t(set.opaque.size());
    work.generatedTransparent += std::int64_t(set.transparent.size());
    return set;
}

}  // namespace patchsim
