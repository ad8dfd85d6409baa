#include "backend/image_space/hybrid_motion_blur.h"

#include <algorithm>
#include <cmath>

#include "core/counters.h"
#include "core/ray.h"
#include "rasterizer/common/watertight_triangle.h"
#include "rasterizer/patent/patch_hierarchy.h"
#include "tessellator/front_end.h"

namespace patchsim {

namespace {

// Per pixel, of its opaque hits (as the sharp frame's depth and motion are): the object most of
// them show (-1: none) and that object's camera-space normal at its first sample. The object must
// be the hits' and not the first sample's: a silhouette pixel whose first sample misses still has
// the depth and motion of the object its other samples hit, and a ray that skipped "no object"
// from there would find that object's own far side behind it.
struct GBuffer {
    int width = 0, height = 0;
    std::vector<int> object;
    std::vector<Vec3> normal;
    std::vector<float> depth;  // far plane where nothing is hit
    std::size_t index(int x, int y) const {
        return std::size_t(y) * std::size_t(width) + std::size_t(x);
    }
};

int objectOf(const ShadingContext& c, const VisibilityRecord& r) {
    return r.hit() ? (*c.patches)[std::size_t(r.patch)].object : -1;
}

// The object of most of the pixel's hits (Boyer-Moore vote over its samples; without a majority,
// one of the objects hit), -1 when none is hit.
int dominantObject(const ShadingContext& c, const VisibilityBuffer& vis, int x, int y) {
    int candidate = -1, votes = 0;
    for (int s = 0; s < vis.samplesPerPixel(); ++s) {
        const int object = objectOf(c, vis.at(x, y, s));
        if (object < 0) continue;
        if (votes == 0) candidate = object;
        votes += object == candidate ? 1 : -1;
    }
    return candidate;
}

Vec3 cameraNormal(const ShadingContext& c, const VisibilityBuffer& vis, int x, int y, int object,
                  const Mat4& view) {
    for (int s = 0; s < vis.samplesPerPixel(); ++s) {
        const VisibilityRecord& r = vis.at(x, y, s);
        if (objectOf(c, r) != object) continue;
        const Vec3 normal = Vec3(view * Vec4(interpolateAttributes(c, r).normal, 0.0f));
        const float len = glm::length(normal);
        return len > 0 ? normal / len : Vec3(0);
    }
    return Vec3(0);
}

GBuffer gBuffer(const ShadingContext& c, const ResolvedFrame& sharp, const VisibilityBuffer& vis) {
    GBuffer g{vis.width(), vis.height(), {}, {}, {}};
    const std::size_t n = std::size_t(g.width) * std::size_t(g.height);
    g.object.assign(n, -1);
    g.normal.assign(n, Vec3(0));
    g.depth.assign(n, c.camera->farPlane());
    const Mat4 view = c.camera->worldToCameraAt(0.5f);
    for (int y = 0; y < g.height; ++y) {
        for (int x = 0; x < g.width; ++x) {
            const std::size_t i = g.index(x, y);
            if (sharp.depth[i] > 0) g.depth[i] = sharp.depth[i];
            g.object[i] = dominantObject(c, vis, x, y);
            if (g.object[i] >= 0) g.normal[i] = cameraNormal(c, vis, x, y, g.object[i], view);
        }
    }
    return g;
}

// Step 2's x_n at pixel (x, y): the 5x5 Sobel of depth (relative to the pixel's, so the threshold
// does not depend on the scene's units) and of the normals, unnormalised as the paper applies the
// kernel, so that its e (0.9 to 0.98) means what it means there: a depth step of about a fifth of
// the pixel's depth, or a crease of about 11 degrees, gives x_n = 0.9.
float edgeMeasure(const GBuffer& g, int x, int y) {
    constexpr float smooth[5] = {1, 4, 6, 4, 1}, derive[5] = {-1, -2, 0, 2, 1};
    float dzx = 0, dzy = 0;
    Vec3 dnx(0), dny(0);
    for (int j = -2; j <= 2; ++j) {
        for (int i = -2; i <= 2; ++i) {
            const std::size_t k =
                g.index(std::clamp(x + i, 0, g.width - 1), std::clamp(y + j, 0, g.height - 1));
            const float wx = derive[i + 2] * smooth[j + 2], wy = smooth[i + 2] * derive[j + 2];
            dzx += wx * g.depth[k];
            dzy += wy * g.depth[k];
            dnx += wx * g.normal[k];
            dny += wy * g.normal[k];
        }
    }
    const float dd = std::sqrt(dzx * dzx + dzy * dzy) / g.depth[g.index(x, y)];
    const float dn = std::sqrt(glm::dot(dnx, dnx) + glm::dot(dny, dny));
    const float xs = dd + dn;
    return std::clamp(1.0f - 1.0f / (xs + 1.0f), 0.0f, 1.0f);
}

// The hybrid's planes in a trace (0: not recorded).
struct HybridPlanes {
    PostprocessPlanes post;
    std::uint16_t object = 0, normal = 0, edge = 0, mask = 0, revealed = 0;
};

HybridPlanes declareHybridPlanes(ImagePassTrace* trace, int width, int height) {
    HybridPlanes p;
    if (!trace) return p;
    const auto pixels = std::uint64_t(width) * std::uint64_t(height);
    p.post = recordResolveAovs(*trace, width, height);
    p.object = trace->addPlane("object", pixels, 4);
    p.normal = trace->addPlane("normal", pixels, 8);  // camera space, three fp16 and a pad
    p.edge = trace->addPlane("edge", pixels, 1);
    p.mask = trace->addPlane("ray mask", pixels, 1);
    p.revealed = trace->addPlane("revealed", pixels, kResolvedImagePixelBytes);
    trace->beginPass("resolve object and normal");
    for (std::uint64_t i = 0; i < pixels; ++i) trace->write(std::uint16_t(p.object | p.normal), i);
    p.post.revealed = std::uint16_t(p.object | p.revealed);  // the composite's reads of a tap
    return p;
}

// The edge test's 5 x 5 depths and normals around (x, y), clamped at the border, in its order.
void recordEdgeReads(ImagePassTrace& trace, const HybridPlanes& p, const GBuffer& g, int x, int y) {
    for (int j = -2; j <= 2; ++j)
        for (int i = -2; i <= 2; ++i)
            trace.read(
                std::uint16_t(p.post.depth | p.normal),
                g.index(std::clamp(x + i, 0, g.width - 1), std::clamp(y + j, 0, g.height - 1)));
}

// Whether pixel (x, y) is a foreground edge its motion uncovers (steps 1 and 2).
std::uint8_t edgeAt(const ResolvedFrame& sharp, const GBuffer& g, const HybridOptions& o,
                    HybridWork& work, int x, int y, const HybridPlanes& planes) {
    ImagePassTrace* trace = planes.post.trace;
    const int w = g.width, h = g.height;
    const std::size_t i = g.index(x, y);
    const Vec2 motion(sharp.motionX[i], sharp.motionY[i]);
    if (trace) trace->read(std::uint16_t(planes.object | planes.post.velocity), i);
    if (g.object[i] < 0 || glm::length(motion) <= 0.5f) return 0;
    // Clamped as floats: a motion AOV can be huge near the camera plane.
    const int nx = int(std::lround(std::clamp(float(x) + motion.x, 0.0f, float(w - 1))));
    const int ny = int(std::lround(std::clamp(float(y) + motion.y, 0.0f, float(h - 1))));
    const std::size_t next = g.index(nx, ny);
    ++work.maskReads;
    if (trace) trace->read(planes.object, next);
    if (g.object[next] == g.object[i]) return 0;
    if (trace) {
        trace->read(planes.post.depth, i);
        trace->read(planes.post.depth, next);
    }
    if (!(g.depth[next] - g.depth[i] > o.post.softZExtent)) return 0;
    ++work.candidates;
    work.maskReads += 25;
    if (trace) recordEdgeReads(*trace, planes, g, x, y);
    if (edgeMeasure(g, x, y) <= o.edgeThreshold) return 0;
    ++work.edgePixels;
    return 1;
}

std::vector<std::uint8_t> rayMask(const ResolvedFrame& sharp, const GBuffer& g,
                                  const HybridOptions& o, HybridWork& work,
                                  const HybridPlanes& planes) {
    ImagePassTrace* trace = planes.post.trace;
    if (trace) trace->beginPass("edge");
    const int w = g.width, h = g.height;
    const float k = float(std::max(1, o.post.tileSize));
    std::vector<std::uint8_t> edge(std::size_t(w) * std::size_t(h), 0), mask(edge.size(), 0);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const std::size_t i = g.index(x, y);
            edge[i] = edgeAt(sharp, g, o, work, x, y, planes);
            if (trace) trace->write(planes.edge, i);
        }
    }
    if (trace) trace->beginPass("ray mask");
    const int S = std::max(3, o.post.samples | 1);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const std::size_t i = g.index(x, y);
            const Vec2 v = pixelVelocity(sharp, i, k);
            if (trace) trace->read(planes.post.velocity, i);
            if (glm::length(v) > 0.25f) {
                for (int s = 0; s < S && !mask[i]; ++s) {
                    const float t = -1.0f + 2.0f * float(s) / float(S - 1);
                    const int sx = std::clamp(int(std::lround(float(x) + v.x * t)), 0, w - 1);
                    const int sy = std::clamp(int(std::lround(float(y) + v.y * t)), 0, h - 1);
                    ++work.maskReads;
                    mask[i] = edge[g.index(sx, sy)];
                    if (trace) trace->read(planes.edge, g.index(sx, sy));
                }
                work.maskedPixels += mask[i];
            }
            if (trace) trace->write(planes.mask, i);
        }
    }
    return mask;
}

// The frame's opaque patches for second rays at mid-shutter: per patch its groups' hierarchies
// (as the patch rasterizer builds them), walked with boxes blended to t = 0.5.
struct RevealScene {
    struct Group {
        std::size_t mesh;
        PatchHierarchy hierarchy;
    };
    std::vector<Group> groups;
    // The meshes' orders, kept because their hierarchies share the orders' leaf vertex tables
    // (the tables live in each order's heap storage, which a move of the order keeps).
    std::vector<HierarchyOrder> orders;

    explicit RevealScene(const std::vector<MovingMesh>& meshes) {
        for (std::size_t m = 0; m < meshes.size(); ++m) {
            if (!meshes[m].opaque || meshes[m].triangleCount() == 0) continue;
            orders.push_back(hierarchyOrder(meshes[m], 256, 4));
            const HierarchyOrder& order = orders.back();
            const std::vector<std::uint32_t>& begin = order.groupBegin;
            for (std::size_t g = 0; g + 1 < begin.size(); ++g) {
                if (begin[g] == begin[g + 1]) continue;
                groups.push_back({m, {}});
                groups.back().hierarchy.buildOrdered(meshes[m], order.triangles.data() + begin[g],
                                                     begin[g + 1] - begin[g], 4,
                                                     &order.leafTables[g]);
            }
        }
    }
    RevealScene(const RevealScene&) = delete;  // its hierarchies point into its own orders
    RevealScene& operator=(const RevealScene&) = delete;

    // The nearest hit of `ray` on an object other than `skipObject`.
    VisibilityRecord trace(const std::vector<MovingMesh>& meshes, Ray& ray, int skipObject,
                           HybridWork& work) const {
        const ShearedRay sheared = shearRay(ray);
        VisibilityRecord best;
        for (const Group& g : groups) {
            const MovingMesh& m = meshes[g.mesh];
            if (m.objectId == skipObject) continue;
            const PatchHierarchy& h = g.hierarchy;
            int stack[2 * kMaxLeavesPerHierarchy];
            int top = 0;
            stack[top++] = 0;
            while (top > 0) {
                const int node = stack[--top];
                ++work.rayBoxTests;
                float entry;
                if (!rayHitsBox(ray, h.node(node).at(0.5f), ray.lambdaMin, ray.lambdaMax, entry,
                                1e-5f))
                    continue;
                if (!h.isLeaf(node)) {
                    stack[top++] = 2 * node + 2;
                    stack[top++] = 2 * node + 1;
                    continue;
                }
                std::size_t count;
                const std::uint32_t* tris =
                    h.leafTriangles(node - PatchHierarchy::firstLeaf(h.depth()), count);
                for (std::size_t k = 0; k < count; ++k) {
                    const std::uint32_t t = tris[k];
                    const std::uint32_t* v = &m.indices[3 * std::size_t(t)];
                    ++work.rayTriangleTests;
                    TriangleHit hit;
                    if (!intersectTriangle(sheared, m.vertexAt(v[0], 0.5f), m.vertexAt(v[1], 0.5f),
                                           m.vertexAt(v[2], 0.5f), ray.lambdaMin, ray.lambdaMax,
                                           hit))
                        continue;
                    const VisibilityRecord r{hit.lambda * ray.depthPerLambda,
                                             m.patchOf(t),
                                             m.triangleInPatchOf(t),
                                             hit.b1,
                                             hit.b2,
                                             0.5f,
                                             Vec2(0.5f)};
                    if (r.nearerThan(best)) best = r;
                    ray.lambdaMax = hit.lambda;
                }
            }
        }
        return best;
    }
};

}  // namespace

PATCHSIM_WORK_DEFINE(HybridWork, HybridCounters, hybridCounters, PATCHSIM_HYBRID_WORK)

Image hybridMotionBlur(const ShadingContext& c, const ResolvedFrame& sharp,
                       const VisibilityBuffer& vis, const HybridOptions& o, PostprocessWork& post,
                       HybridWork& work, ImagePassTrace* trace) {
    const GBuffer g = gBuffer(c, sharp, vis);
    const HybridPlanes planes = declareHybridPlanes(trace, g.width, g.height);
    const std::vector<std::uint8_t> mask = rayMask(sharp, g, o, work, planes);
    const RevealScene scene(*c.meshes);
    RevealedBackground revealed{std::vector<Vec3>(mask.size(), kBackground),
                                std::vector<std::uint8_t>(mask.size(), 0), g.object};
    const Camera& camera = *c.camera;
    if (trace) trace->beginPass("ray reveal");
    for (int y = 0; y < g.height; ++y) {
        for (int x = 0; x < g.width; ++x) {
            const std::size_t i = g.index(x, y);
            if (trace) trace->read(planes.mask, i);
            if (!mask[i]) continue;
            if (trace) {  // what the ray starts from, and what it reveals (or nothing)
                trace->read(std::uint16_t(planes.post.depth | planes.object), i);
                trace->write(planes.revealed, i);
            }
            // The first ray's hit is the sharp frame's; the second starts just behind it.
            work.rays += 2;
            Ray ray =
                makeCameraRay(camera, rasterToScreen(camera, {float(x) + 0.5f, float(y) + 0.5f}),
                              Vec2(0), 0.5f, LensModel{});
            ray.lambdaMin = std::max(ray.lambdaMin, g.depth[i] / ray.depthPerLambda);
            const VisibilityRecord behind = scene.trace(*c.meshes, ray, g.object[i], work);
            if (!behind.hit()) continue;
            ++work.revealed;
            revealed.found[i] = 1;
            revealed.color[i] = shadeFragment(c, interpolateAttributes(c, behind), 0.5f);
        }
    }
    return reconstructMotionBlur(sharp, camera.farPlane(), o.post, post, &revealed, planes.post);
}

}  // namespace patchsim
