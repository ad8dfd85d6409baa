#include "rasterizer/patent/ray_stream.h"

#include <gtest/gtest.h>
#include <hwy/targets.h>

#include <cstring>
#include <limits>
#include <vector>

#include "core/counters.h"
#include "core/scene_reader.h"
#include "pipeline/driver/render.h"
#include "rasterizer/common/watertight_triangle.h"
#include "rasterizer/common/z_culling.h"
#include "rasterizer/patent/branch_node.h"
#include "rasterizer/patent/moving_box_ray.h"
#include "rasterizer/patent/tile_traversal.h"
#include "tests/patch_setup.h"
#include "tests/render_compare.h"
#include "tests/test_paths.h"

namespace patchsim {
namespace {

// The kernels run on whichever SIMD target the host has; each must give the same samples and the
// same counts (no fused multiply-adds, per-lane results equal to the scalar tests).
TEST(RayStream, EverySimdTargetGivesTheSameSamplesAndCounts) {
    const std::vector<std::int64_t> targets = hwy::SupportedAndGeneratedTargets();
    ASSERT_FALSE(targets.empty());
    for (const char* path : {"scenes/motion_defocus.json", "scenes/transparency.json"}) {
        SceneDesc scene = readSceneFile(test::sourcePath(path));
        scene.film.width = 48;
        scene.film.height = 36;
        scene.film.samplesPerPixel = 4;
        RenderOptions options;
        options.threads = 1;
        std::unique_ptr<RenderResult> first;
        CounterValues firstCounts;
        for (std::int64_t target : targets) {
            hwy::SetSupportedTargetsForTest(target);
            EXPECT_STREQ(rayStreamTarget(), hwy::TargetName(target));
            CounterRegistry::instance().reset();
            auto result = std::make_unique<RenderResult>(renderScene(scene, options));
            const CounterValues counts = CounterRegistry::instance().snapshot();
            if (!first) {
                first = std::move(result);
                firstCounts = counts;
                continue;
            }
            EXPECT_EQ(test::compare(*first, *result).mismatches, 0u)
                << path << " on " << hwy::TargetName(target);
            EXPECT_EQ(first->frame.color.rgb, result->frame.color.rgb) << path;
            EXPECT_EQ(firstCounts.raw(), counts.raw())
                << path << ": counts on " << hwy::TargetName(target);
        }
        hwy::SetSupportedTargetsForTest(0);
    }
    std::printf("SIMD targets compared: %zu\n", targets.size());
}

// A small frame of a shipped scene made ready for passes: its patches' meshes and groups (one
// group per patch), a visibility buffer and the tile rays' frame.
struct GroupedFrame {
    SceneDesc scene;
    test::PatchSetup setup;
    std::vector<MovingMesh> meshes;
    std::vector<PatchRasterizer::Group> groups;
    VisibilityBuffer buffer;
    TileRayFrame frame;
    RasterWork work;

    GroupedFrame(const char* path, FilmDesc film, const RasterizerOptions& options = {})
        : GroupedFrame(readSceneFile(test::sourcePath(path)), film, options) {}
    GroupedFrame(const SceneDesc& desc, FilmDesc film, const RasterizerOptions& options = {})
        : scene(withFilm(desc, film)),
          setup(scene, options),
          groups(setup.fe.patchCount()),
          buffer(film.width, film.height, film.samplesPerPixel, setup.fe.camera().farPlane()),
          frame{&setup.fe.camera(),
                setup.lens,
                {&setup.samples, nullptr},
                film.samplesPerPixel,
                setup.effects.timeSamples(),
                setup.rasterizer.tileGrid().tileSize,
                false,
                false} {
        FrontEndWorkspace ws = setup.fe.makeWorkspace();
        const int leafSize = setup.rasterizer.options().leafSize;
        for (std::size_t i = 0; i < setup.fe.patchCount(); ++i) {
            meshes.push_back(setup.mesh(i, ws));
            // Opaque or not as the frame driver decides (runFrontEnd).
            const MaterialDesc& m =
                setup.fe.objects()[std::size_t(meshes[i].objectId)].desc.material;
            meshes[i].opaque =
                !setup.effects.transparency || (m.opacity >= 1.0f && m.closeOpacity >= 1.0f);
            const HierarchyOrder all =
                hierarchyOrder(meshes[i], int(meshes[i].triangleCount()), leafSize);
            setup.rasterizer.prepareGroup(meshes[i], all.triangles.data(), all.triangles.size(),
                                          groups[i], work);
        }
    }

    static SceneDesc withFilm(SceneDesc desc, FilmDesc film) {
        desc.film = film;
        return desc;
    }

    // Group g's walk over tile (tx, ty), as rasterizeTile makes it (with z culling, out to the
    // tile's farthest depth bound), and the pass that follows it.
    TileTraversal walk(TileRays& rays, int tx, int ty, std::size_t g) {
        const PatchRasterizer& r = setup.rasterizer;
        const Camera& camera = setup.fe.camera();
        const float farDepth = r.options().zCulling ? rays.farthestDepthBound() : camera.farPlane();
        RasterWork walkWork;
        return traverseTile(groups[g].hierarchy, groups[g].nodes,
                            {&camera, setup.lens, r.tileGrid().rect(tx, ty), farDepth},
                            setup.effects.motion, timeRefinementOf(r.options()), walkWork);
    }
    // A transparent group's pass offers its hits to `layers`, pool 0, as rasterizeTile does.
    StreamPass passAfter(const TileTraversal& traversal, std::size_t g,
                         TransparentLayers* layers = nullptr) const {
        const RasterizerOptions& options = setup.rasterizer.options();
        const PatchHierarchy& h = groups[g].hierarchy;
        StreamPass pass{&meshes[g], &h, &traversal,
                        branchNode(options.branchMethod, traversal, h.depth()), options.zCulling};
        if (!meshes[g].opaque) pass.transparent = layers;
        return pass;
    }

    // `visit(tx, ty, g)` for every group g whose bounds cover tile (tx, ty), the tile's rays
    // loaded into `rays` from the buffer (`loaded()` is called then, before any group), and
    // written back after the tile's last group.
    template <class Visit, class Loaded>
    void forEachCoveredTile(TileRays& rays, const Visit& visit, const Loaded& loaded) {
        const TileGrid& grid = setup.rasterizer.tileGrid();
        for (int ty = 0; ty < grid.tilesY(); ++ty)
            for (int tx = 0; tx < grid.tilesX(); ++tx) {
                rays.load(grid.rect(tx, ty), buffer);
                loaded();
                for (std::size_t g = 0; g < groups.size(); ++g) {
                    const TileRange& covered = groups[g].tiles;
                    if (tx >= covered.x0 && tx < covered.x1 && ty >= covered.y0 && ty < covered.y1)
                        visit(tx, ty, g);
                }
                rays.store(buffer, nullptr);
            }
    }
    template <class Visit>
    void forEachCoveredTile(TileRays& rays, const Visit& visit) {
        forEachCoveredTile(rays, visit, [] {});
    }
};

// With z culling a pass starts from the ray ends as the tile holds them (TileRays::rayEnd), so
// after every pass each ray must still end at its sample's depth bound: where the pass found a
// nearer hit, at that hit's.
TEST(RayStream, WithZCullingEveryRayEndsAtItsDepthBoundAfterEachPass) {
    GroupedFrame f("scenes/motion_defocus.json", {64, 48, 4, 1});
    const PatchRasterizer& rasterizer = f.setup.rasterizer;
    ASSERT_TRUE(rasterizer.options().zCulling);
    TileRays rays(f.frame);
    const VisibilityTargets targets{&f.buffer, nullptr, nullptr, 0};
    const auto endsAtDepthBound = [&rays](int i) {
        const float depth = rays.bestDepth[i];
        const float bound = depth < rays.farDepth() ? depth : rays.farDepth();
        const float end = rayEndAtDepth(bound, rays.depthPerLambda());
        return std::memcmp(&end, &rays.rayEnd[i], sizeof end) == 0;
    };
    std::size_t passes = 0, shortened = 0, wrong = 0;
    f.forEachCoveredTile(
        rays,
        [&](int tx, int ty, std::size_t g) {
            rasterizer.rasterizeTile(f.meshes[g], f.groups[g], tx, ty, rays, targets, f.work);
            ++passes;
            for (int i = 0; i < rays.count(); ++i) {
                wrong += !endsAtDepthBound(i);
                shortened += rays.bestDepth[i] < rays.farDepth();
            }
        },
        [&] {  // every tile as loaded, before its first pass
            for (int i = 0; i < rays.count(); ++i) wrong += !endsAtDepthBound(i);
        });
    EXPECT_EQ(wrong, 0u);
    EXPECT_GT(passes, 100u);
    EXPECT_GT(shortened, 1000u) << "the passes should find hits";
}

// What a pass counts at its start: it tests exactly the tile's samples whose time lies in the
// union of the overlapping leaves' intervals (the branch node's range), casts one ray for each,
// tests each against the branch node's box, and rejects the tile's other samples by time.
TEST(RayStream, APassTestsTheSamplesInItsLeavesTimesAndCastsARayForEach) {
    for (const char* path : {"scenes/motion_defocus.json", "scenes/static.json"}) {
        GroupedFrame f(path, {64, 48, 4, 1});
        TileRays rays(f.frame);
        std::size_t passes = 0, narrowed = 0;
        f.forEachCoveredTile(rays, [&](int tx, int ty, std::size_t g) {
            const PatchHierarchy& h = f.groups[g].hierarchy;
            const TileTraversal traversal = f.walk(rays, tx, ty, g);
            if (!traversal.overlaps) return;
            TimeRange hull = TimeRange::empty();
            for (int j = 0; j < h.leafCount(); ++j)
                if (traversal.leafMask >> j & 1u) hull.extend(traversal.leafTimes[std::size_t(j)]);
            std::int64_t inHull = 0;
            for (int i = 0; i < rays.count(); ++i)
                inHull += rays.time[i] >= hull.lower && rays.time[i] <= hull.upper;
            const StreamPass stream = f.passAfter(traversal, g);
            RasterWork pass;
            traceRayStream(rays, stream, pass);
            ++passes;
            narrowed += inHull < rays.count();
            ASSERT_EQ(pass.samplesTested, inHull) << path << " tile " << tx << "," << ty;
            ASSERT_EQ(pass.raysCast, inHull);
            ASSERT_EQ(pass.samplesRejectedTime, rays.count() - inHull);
            ASSERT_GE(pass.rayBoxTests, inHull);
            ASSERT_EQ(pass.branchDepthSum, h.levelOf(stream.branchNode));
        });
        EXPECT_GT(passes, 50u) << path;
        if (f.setup.effects.motion) {
            EXPECT_GT(narrowed, passes / 10) << path << ": time should narrow many passes";
        }
    }
}

// A pass replayed one ray at a time with the scalar tests, as an independent model of what the
// vector pass computes and counts. Each ray's work depends only on its own state (its end and its
// nearest hit so far), and the vector pass takes each ray through the hierarchy depth first,
// nearer child first, testing both children with the end the ray had when they were tested: so
// one ray's walk, replayed alone in that order, meets the same boxes and triangles. A pass that
// keeps every hit (`layers` set: a transparent mesh) offers each to the layers instead, in the
// order the vector pass offers a sample's hits: leaf by leaf in that order, triangle by triangle.
class ScalarPass {
  public:
    ScalarPass(const TileRays& rays, const MovingMesh& mesh, const PatchHierarchy& h,
               const TileTraversal& traversal, TransparentLayers* layers = nullptr)
        : rays_(rays),
          mesh_(mesh),
          h_(h),
          layers_(layers),
          times_(std::size_t(2 * h.leafCount() - 1)) {
        const int firstLeaf = PatchHierarchy::firstLeaf(h.depth());
        for (int j = 0; j < h.leafCount(); ++j)
            times_[std::size_t(firstLeaf + j)] = (traversal.leafMask >> j & 1u)
                                                     ? traversal.leafTimes[std::size_t(j)]
                                                     : TimeRange::empty();
        for (int i = firstLeaf - 1; i >= 0; --i) {
            times_[std::size_t(i)] = times_[std::size_t(2 * i + 1)];
            times_[std::size_t(i)].extend(times_[std::size_t(2 * i + 2)]);
        }
        for (int i = 0; i < rays.padded(); ++i)
            samples.push_back({rays.rayEnd[i], rays.bestDepth[i], rays.bestPatch[i],
                               rays.bestTriangle[i], rays.bestB1[i], rays.bestB2[i], false});
    }

    struct SampleState {
        float end, depth;
        std::int32_t patch;
        std::uint32_t triangle;
        float b1, b2;
        bool improved;
    };

    // `zCulling` false: the pass first sets the ends of the samples in its index range to the far
    // plane's, or, keeping every hit, to their depth bound's (hits behind an opaque one are
    // hidden).
    void run(int start, bool zCulling) {
        if (!zCulling) {
            int first, last;
            rays_.indexRange(times_[std::size_t(start)], first, last);
            for (int i = first; i < last; ++i) {
                SampleState& s = samples[std::size_t(i)];
                const float bound =
                    layers_ && s.depth < rays_.farDepth() ? s.depth : rays_.farDepth();
                s.end = rayEndAtDepth(bound, rays_.depthPerLambda());
            }
        }
        for (int i = 0; i < rays_.count(); ++i) {
            if (!times_[std::size_t(start)].contains(rays_.time[i])) continue;
            ++work.samplesTested;
            ++work.raysCast;
            ++work.rayBoxTests;
            if (hits(start, i)) visit(start, i);
        }
        for (const SampleState& s : samples) work.visibilitySamples += s.improved;
    }

    RasterWork work;
    std::vector<SampleState> samples;  // per sample of the tile
    std::int64_t hiddenHits = 0;       // transparent hits beyond their ray's end (not offered)

  private:
    bool hits(int node, int i) const {
        Ray ray = rays_.ray(i);
        ray.lambdaMax = samples[std::size_t(i)].end;
        return hitsMovingBox(makeSlabRay(ray), h_.node(node));
    }

    void visit(int node, int i) {
        if (h_.isLeaf(node)) return leaf(node, i);
        int first = 2 * node + 1, second = 2 * node + 2;
        const LBBox &a = h_.node(first), &b = h_.node(second);
        if (b.bounds0.upper.z + b.bounds1.upper.z > a.bounds0.upper.z + a.bounds1.upper.z)
            std::swap(first, second);
        bool met[2] = {false, false};
        const int children[2] = {first, second};
        for (int c = 0; c < 2; ++c) {
            if (!times_[std::size_t(children[c])].contains(rays_.time[i])) continue;
            ++work.rayBoxTests;
            met[c] = hits(children[c], i);
        }
        for (int c = 0; c < 2; ++c)
            if (met[c]) visit(children[c], i);
    }

    void leaf(int node, int i) {
        std::size_t count;
        const std::uint32_t* triangles =
            h_.leafTriangles(node - PatchHierarchy::firstLeaf(h_.depth()), count);
        if (layers_) return offerEveryHit(triangles, count, i);
        SampleState& s = samples[std::size_t(i)];
        const Ray ray = rays_.ray(i);
        const ShearedRay sheared = shearRay(ray);
        float end = s.end;
        SampleState best{end, std::numeric_limits<float>::infinity(), -1, 0, 0, 0, false};
        bool found = false;
        for (std::size_t k = 0; k < count; ++k) {
            ++work.rayTriangleTests;
            TriangleHit hit;
            if (!intersects(sheared, ray, triangles[k], end, hit)) continue;
            const SampleState candidate{0,
                                        hit.lambda * rays_.depthPerLambda(),
                                        mesh_.patchOf(triangles[k]),
                                        mesh_.triangleInPatchOf(triangles[k]),
                                        hit.b1,
                                        hit.b2,
                                        false};
            if (!nearer(candidate, best)) continue;
            best = candidate;
            end = std::min(end, rayEndAtDepth(candidate.depth, rays_.depthPerLambda()));
            found = true;
        }
        if (!found || !nearer(best, s)) return;
        s = {end, best.depth, best.patch, best.triangle, best.b1, best.b2, true};
    }

    void offerEveryHit(const std::uint32_t* triangles, std::size_t count, int i) {
        const Ray ray = rays_.ray(i);
        const ShearedRay sheared = shearRay(ray);
        for (std::size_t k = 0; k < count; ++k) {
            ++work.rayTriangleTests;
            TriangleHit hit;
            if (!intersects(sheared, ray, triangles[k], samples[std::size_t(i)].end, hit)) {
                hiddenHits += intersects(sheared, ray, triangles[k],
                                         std::numeric_limits<float>::infinity(), hit);
                continue;
            }
            VisibilityRecord record;
            record.depth = hit.lambda * rays_.depthPerLambda();
            record.patch = mesh_.patchOf(triangles[k]);
            record.triangle = mesh_.triangleInPatchOf(triangles[k]);
            record.b1 = hit.b1;
            record.b2 = hit.b2;
            record.time = rays_.time[i];
            record.lens = {rays_.lensU[i], rays_.lensV[i]};
            ++work.transparentFragments;
            if (!layers_->offer(rays_.record[i], 0, LayerFragment{record, mesh_.objectId}))
                ++work.transparentOverflow;
        }
    }

    // The watertight test of the mesh's `triangle`, blended to the ray's time, out to `end`.
    bool intersects(const ShearedRay& sheared, const Ray& ray, std::uint32_t triangle, float end,
                    TriangleHit& hit) const {
        const std::uint32_t* v = &mesh_.indices[3 * std::size_t(triangle)];
        return intersectTriangle(sheared, mesh_.vertexAt(v[0], ray.time),
                                 mesh_.vertexAt(v[1], ray.time), mesh_.vertexAt(v[2], ray.time),
                                 rays_.lambdaMin(), end, hit);
    }

    // VisibilityRecord::nearerThan.
    static bool nearer(const SampleState& a, const SampleState& b) {
        if (a.depth != b.depth) return a.depth < b.depth;
        if (a.patch != b.patch) return std::uint32_t(a.patch) < std::uint32_t(b.patch);
        return a.triangle < b.triangle;
    }

    const TileRays& rays_;
    const MovingMesh& mesh_;
    const PatchHierarchy& h_;
    TransparentLayers* layers_;
    std::vector<TimeRange> times_;
};

bool sameBits(float a, float b) {
    return std::memcmp(&a, &b, sizeof a) == 0;
}

bool sameFragment(const LayerFragment& a, const LayerFragment& b) {
    const VisibilityRecord &x = a.record, &y = b.record;
    return sameBits(x.depth, y.depth) && x.patch == y.patch && x.triangle == y.triangle &&
           sameBits(x.b1, y.b1) && sameBits(x.b2, y.b2) && sameBits(x.time, y.time) &&
           sameBits(x.lens.x, y.lens.x) && sameBits(x.lens.y, y.lens.y) && a.object == b.object;
}

// Sample i's transparent layers, the pass's against the replay's: the same fragments, bit for bit,
// in the same slots.
::testing::AssertionResult sameLayers(const TransparentLayers& pass,
                                      const TransparentLayers& replay, std::size_t sample) {
    if (pass.count(sample) != replay.count(sample))
        return ::testing::AssertionFailure() << "sample " << sample << ": " << pass.count(sample)
                                             << " layers against " << replay.count(sample);
    for (int k = 0; k < pass.count(sample); ++k)
        if (!sameFragment(pass.layers(sample)[k], replay.layers(sample)[k]))
            return ::testing::AssertionFailure() << "sample " << sample << ", layer " << k;
    return ::testing::AssertionSuccess();
}

// transparency.json with its glass cube larger and set back, so that it sweeps through and behind
// the torus, seen through a lens: the cube's hits behind the torus are culled by the rays' ends,
// the others are kept.
SceneDesc glassBehindTorus() {
    SceneDesc scene = readSceneFile(test::sourcePath("scenes/transparency.json"));
    ObjectDesc& cube = scene.objects.at(1);
    cube.open.translate.z = cube.close.translate.z = -1.5f;
    cube.open.scale = cube.close.scale = Vec3(1.5f);
    scene.lens.apertureRadius = 0.12f;
    scene.lens.focusDistance = 6.0f;
    return scene;
}

// Every pass of a frame against its scalar replay: the same counts (samples tested, rays, box and
// triangle tests, visibility samples, transparent fragments) and, per sample, the same nearest hit
// and ray end, bit for bit, and the same transparent layers. With and without a lens, moving and
// static, opaque and transparent, with and without z culling.
TEST(RayStream, EveryPassCountsWhatItsScalarReplayCounts) {
    struct ReplayedScene {
        const char* name;
        SceneDesc scene;
        std::int64_t minHiddenHits;  // transparent hits its ray ends must cull
    };
    const auto shipped = [](const char* path) { return readSceneFile(test::sourcePath(path)); };
    const ReplayedScene scenes[] = {
        {"scenes/motion_defocus.json", shipped("scenes/motion_defocus.json"), 0},
        {"scenes/static.json", shipped("scenes/static.json"), 0},
        {"scenes/transparency.json", shipped("scenes/transparency.json"), 0},
        {"glass behind the torus", glassBehindTorus(), 100}};
    for (const auto& [path, scene, minHiddenHits] : scenes)
        for (bool zCulling : {true, false}) {
            RasterizerOptions options;
            options.zCulling = zCulling;
            const FilmDesc film{64, 48, 4, 1};
            GroupedFrame f(scene, film, options);
            TileRays rays(f.frame);
            const std::size_t filmSamples =
                std::size_t(film.width * film.height * film.samplesPerPixel);
            TransparentLayers passLayers(filmSamples, 16), replayLayers(filmSamples, 16);
            std::size_t passes = 0, transparentPasses = 0;
            std::int64_t boxTests = 0, triangleTests = 0, visible = 0, fragments = 0, hidden = 0;
            f.forEachCoveredTile(rays, [&](int tx, int ty, std::size_t g) {
                const TileTraversal traversal = f.walk(rays, tx, ty, g);
                if (!traversal.overlaps) return;
                const StreamPass stream = f.passAfter(traversal, g, &passLayers);
                ScalarPass replay(rays, f.meshes[g], f.groups[g].hierarchy, traversal,
                                  stream.transparent ? &replayLayers : nullptr);
                replay.run(stream.branchNode, stream.zCulling);
                RasterWork pass;
                traceRayStream(rays, stream, pass);
                ++passes;
                transparentPasses += stream.transparent != nullptr;
                ASSERT_EQ(pass.samplesTested, replay.work.samplesTested)
                    << path << " " << tx << "," << ty;
                ASSERT_EQ(pass.raysCast, replay.work.raysCast);
                ASSERT_EQ(pass.rayBoxTests, replay.work.rayBoxTests)
                    << path << " " << tx << "," << ty;
                ASSERT_EQ(pass.rayTriangleTests, replay.work.rayTriangleTests);
                ASSERT_EQ(pass.visibilitySamples, replay.work.visibilitySamples);
                ASSERT_EQ(pass.transparentFragments, replay.work.transparentFragments);
                ASSERT_EQ(pass.transparentOverflow, replay.work.transparentOverflow);
                for (int i = 0; i < rays.count(); ++i) {
                    const ScalarPass::SampleState& s = replay.samples[std::size_t(i)];
                    ASSERT_TRUE(sameBits(rays.bestDepth[i], s.depth)) << i;
                    ASSERT_EQ(rays.bestPatch[i], s.patch);
                    ASSERT_EQ(rays.bestTriangle[i], s.triangle);
                    ASSERT_TRUE(sameBits(rays.bestB1[i], s.b1) && sameBits(rays.bestB2[i], s.b2));
                    ASSERT_TRUE(sameBits(rays.rayEnd[i], s.end)) << i;
                    if (stream.transparent) {
                        ASSERT_TRUE(sameLayers(passLayers, replayLayers, rays.record[i]))
                            << path << " " << tx << "," << ty;
                    }
                }
                boxTests += pass.rayBoxTests;
                triangleTests += pass.rayTriangleTests;
                visible += pass.visibilitySamples;
                fragments += pass.transparentFragments;
                hidden += replay.hiddenHits;
            });
            EXPECT_GT(passes, 50u) << path;
            EXPECT_GT(boxTests, 10000) << path;
            EXPECT_GT(triangleTests, 5000) << path;
            EXPECT_GT(visible, 1000) << path;
            if (f.setup.effects.transparency) {
                EXPECT_GT(transparentPasses, 20u) << path;
                EXPECT_GT(fragments, 1000) << path;
            }
            EXPECT_GE(hidden, minHiddenHits) << path;
        }
}

}  // namespace
}  // namespace patchsim
