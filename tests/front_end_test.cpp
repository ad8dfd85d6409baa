#include "tessellator/front_end.h"

#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include "core/effects.h"
#include "core/error.h"
#include "core/scene_reader.h"
#include "pipeline/driver/tessellation_export.h"
#include "tests/test_paths.h"

namespace patchsim {
namespace {

SceneDesc sceneWithCage(const std::string& cage, Partitioning mode, float factor) {
    SceneDesc scene;
    scene.path = "test";
    scene.tessellation.partitioning = mode;
    scene.tessellation.factor = factor;
    ObjectDesc object;
    object.cagePath = cage;
    const std::string name = std::filesystem::path(cage).filename().string();
    object.scheme = name.starts_with("loop_")       ? SubdivisionScheme::Loop
                    : name.starts_with("bilinear_") ? SubdivisionScheme::Bilinear
                                                    : SubdivisionScheme::Catmark;
    scene.objects.push_back(object);
    return scene;
}

std::vector<TessellatedPatch> tessellateAll(const FrontEnd& fe) {
    std::vector<TessellatedPatch> patches(fe.patchCount());
    FrontEndWorkspace ws = fe.makeWorkspace();
    for (std::size_t i = 0; i < patches.size(); ++i) fe.tessellate(i, patches[i], ws);
    return patches;
}

using PointBits = std::array<std::uint32_t, 6>;
PointBits bits(const Vec3& a, const Vec3& b) {
    return {std::bit_cast<std::uint32_t>(a.x), std::bit_cast<std::uint32_t>(a.y),
            std::bit_cast<std::uint32_t>(a.z), std::bit_cast<std::uint32_t>(b.x),
            std::bit_cast<std::uint32_t>(b.y), std::bit_cast<std::uint32_t>(b.z)};
}

struct WeldedMesh {
    std::size_t boundaryEdges = 0;
    std::size_t overusedEdges = 0;  // used by more than two triangles
    std::size_t triangles = 0;
};

// Welds points by their exact bits and counts how often each edge is used.
WeldedMesh weld(const std::vector<TessellatedPatch>& patches) {
    std::map<PointBits, std::size_t> ids;
    std::map<std::pair<std::size_t, std::size_t>, int> edgeUse;
    WeldedMesh mesh;
    for (const TessellatedPatch& p : patches) {
        std::vector<std::size_t> id(p.tessellation.points.size());
        for (std::size_t k = 0; k < id.size(); ++k)
            id[k] = ids.emplace(bits(p.position[0][k], p.position[1][k]), ids.size()).first->second;
        const auto& idx = p.tessellation.indices;
        for (std::size_t t = 0; t + 2 < idx.size(); t += 3) {
            ++mesh.triangles;
            for (int e = 0; e < 3; ++e) {
                const std::size_t a = id[idx[t + std::size_t(e)]],
                                  b = id[idx[t + std::size_t((e + 1) % 3)]];
                ++edgeUse[{std::min(a, b), std::max(a, b)}];
            }
        }
    }
    for (const auto& [edge, uses] : edgeUse) {
        mesh.boundaryEdges += uses == 1;
        mesh.overusedEdges += uses > 2;
    }
    return mesh;
}

// Cage edges used by one face only (on faces that are not holes).
std::size_t cageBoundaryEdges(const Cage& cage) {
    std::map<std::pair<int, int>, int> use;
    std::size_t offset = 0;
    for (int f = 0; f < cage.faceCount(); ++f) {
        const int n = cage.faceSizes[std::size_t(f)];
        for (int i = 0; i < n; ++i) {
            const int a = cage.faceVertices[offset + std::size_t(i)];
            const int b = cage.faceVertices[offset + std::size_t((i + 1) % n)];
            ++use[{std::min(a, b), std::max(a, b)}];
        }
        offset += std::size_t(n);
    }
    std::size_t boundary = 0;
    for (const auto& [e, u] : use) boundary += u == 1;
    return boundary;
}

// Vertices where other than two boundary edges meet (a crack loop that touches a boundary loop).
std::size_t oddBoundaryVertices(const std::vector<std::pair<std::size_t, std::size_t>>& edges) {
    std::map<std::size_t, int> degree;
    for (auto [a, b] : edges) ++degree[a], ++degree[b];
    std::size_t odd = 0;
    for (const auto& [v, d] : degree) odd += d != 2;
    return odd;
}

// Connected components of a set of undirected edges (by their vertices).
std::size_t components(const std::vector<std::pair<std::size_t, std::size_t>>& edges) {
    std::map<std::size_t, std::size_t> parent;
    std::function<std::size_t(std::size_t)> root = [&](std::size_t v) {
        auto it = parent.try_emplace(v, v).first;
        return it->second == v ? v : it->second = root(it->second);
    };
    for (auto [a, b] : edges) parent[root(a)] = root(b);
    std::size_t count = 0;
    for (const auto& [v, p] : parent) count += root(v) == v;
    return count;
}

struct BoundaryShape {
    std::size_t loops = 0, oddVertices = 0;
    bool operator==(const BoundaryShape&) const = default;
};
std::ostream& operator<<(std::ostream& out, const BoundaryShape& b) {
    return out << b.loops << " loops, " << b.oddVertices << " vertices not on exactly two";
}

// Boundary loops of the cage faces that became patches: edges such faces use once.
BoundaryShape cageBoundary(const FrontEnd& fe) {
    const Cage& cage = fe.objects()[0].cage;
    std::set<int> faces;
    for (const PatchInfo& p : fe.objects()[0].mesh->patches()) faces.insert(p.face);
    std::map<std::pair<std::size_t, std::size_t>, int> use;
    std::size_t offset = 0;
    for (int f = 0; f < cage.faceCount(); ++f) {
        const int n = cage.faceSizes[std::size_t(f)];
        for (int i = 0; i < n && faces.count(f); ++i) {
            const auto a = std::size_t(cage.faceVertices[offset + std::size_t(i)]);
            const auto b = std::size_t(cage.faceVertices[offset + std::size_t((i + 1) % n)]);
            if (a != b) ++use[{std::min(a, b), std::max(a, b)}];
        }
        offset += std::size_t(n);
    }
    std::vector<std::pair<std::size_t, std::size_t>> boundary;
    for (const auto& [e, u] : use)
        if (u == 1) boundary.push_back(e);
    return {components(boundary), oddBoundaryVertices(boundary)};
}

struct ExportedMesh {
    BoundaryShape boundary;
    std::size_t overusedEdges = 0;  // used by more than two triangles
};

// The OBJ `patchsim tessellate` writes (welded by exact position at both shutter ends), read back.
ExportedMesh exportAndRead(const FrontEnd& fe) {
    std::ostringstream obj;
    writeTessellationObj(fe, {0.0f, 1}, obj);
    std::istringstream in(obj.str());
    std::map<std::pair<std::size_t, std::size_t>, int> use;
    std::string line;
    while (std::getline(in, line)) {
        if (!line.starts_with("f ")) continue;
        std::istringstream face(line.substr(2));
        std::size_t v[3];
        std::string token;
        for (std::size_t& index : v) {
            face >> token;
            index = std::stoul(token.substr(0, token.find('/')));
        }
        for (int e = 0; e < 3; ++e) {
            const std::size_t a = v[e], b = v[(e + 1) % 3];
            if (a != b) ++use[{std::min(a, b), std::max(a, b)}];
        }
    }
    ExportedMesh mesh;
    std::vector<std::pair<std::size_t, std::size_t>> boundary;
    for (const auto& [e, u] : use) {
        if (u == 1) boundary.push_back(e);
        mesh.overusedEdges += u > 2;
    }
    mesh.boundary = {components(boundary), oddBoundaryVertices(boundary)};
    return mesh;
}

// Every scheme and every partitioning is watertight: the two sides of a shared edge use the same
// points, bit for bit, so the exported mesh welded by exact position has exactly the cage's
// boundary loops (a crack or T-junction would add a loop). The `nonman_edges` cages have faces
// that use one pair of vertices twice, which Far makes two edges.
TEST(FrontEnd, WatertightOnEveryCageUnderEveryPartitioning) {
    std::vector<std::string> files = test::regressionCageFiles();
    for (const char* own :
         {"catmark_val2_interior.obj", "loop_val2_interior.obj", "catmark_nonman_quadpole8.obj",
          "catmark_nonman_edges.obj", "loop_nonman_edges.obj"})
        files.push_back(test::sourcePath(std::string("scenes/cages/") + own));
    // More cages (e.g. all of OpenSubdiv's regression shapes written out as OBJ) from a folder.
    if (const char* extra = std::getenv("PATCHSIM_EXTRA_CAGES"))
        for (const auto& entry : std::filesystem::directory_iterator(extra))
            if (entry.path().extension() == ".obj") files.push_back(entry.path().string());
    for (const std::string& path : files) {
        for (auto [mode, factor] :
             {std::pair{Partitioning::Integer, 5.0f}, std::pair{Partitioning::Pow2, 3.0f},
              std::pair{Partitioning::FractionalOdd, 4.3f},
              std::pair{Partitioning::FractionalEven, 5.7f}}) {
            const FrontEnd fe(sceneWithCage(path, mode, factor));
            const ExportedMesh mesh = exportAndRead(fe);
            const std::string what = path + " " + partitioningName(mode);
            if (fe.objects()[0].cage.warnings.empty()) {  // manifold cage
                EXPECT_EQ(mesh.overusedEdges, 0u) << what;
            }
            EXPECT_EQ(mesh.boundary, cageBoundary(fe)) << what;
        }
    }
}

TEST(FrontEnd, NGonHalfEdgesMeetTheirNeighboursExactly) {
    const FrontEnd fe(sceneWithCage(test::sourcePath("scenes/cages/catmark_nonquads.obj"),
                                    Partitioning::Integer, 6));
    const WeldedMesh mesh = weld(tessellateAll(fe));
    EXPECT_EQ(mesh.overusedEdges, 0u);
    // Only the cage's own boundary stays open: 6 segments on each of its boundary edges.
    EXPECT_EQ(mesh.boundaryEdges, 6 * cageBoundaryEdges(fe.objects()[0].cage));
}

TEST(FrontEnd, AdaptiveFactorsAgreeOnSharedEdgesOfMovingObjects) {
    for (const char* scene : {"scenes/motion.json", "scenes/motion_defocus.json"}) {
        const FrontEnd fe(readSceneFile(test::sourcePath(scene)));
        const auto patches = tessellateAll(fe);
        for (std::size_t object = 0; object < fe.objects().size(); ++object) {
            std::vector<TessellatedPatch> mine;
            for (const auto& p : patches)
                if (p.object == int(object)) mine.push_back(p);
            const WeldedMesh mesh = weld(mine);
            EXPECT_EQ(mesh.overusedEdges, 0u) << scene << " object " << object;
            EXPECT_EQ(mesh.boundaryEdges, 0u) << scene << " object " << object;
        }
    }
}

TEST(FrontEnd, TriangleWindingFollowsTheSurfaceNormal) {
    const FrontEnd fe(readSceneFile(test::sourcePath("scenes/static.json")));
    std::size_t agree = 0, total = 0;
    for (const TessellatedPatch& p : tessellateAll(fe)) {
        const auto& idx = p.tessellation.indices;
        for (std::size_t t = 0; t + 2 < idx.size(); t += 3) {
            const Vec3 a = p.position[0][idx[t]], b = p.position[0][idx[t + 1]],
                       c = p.position[0][idx[t + 2]];
            const Vec3 n = p.normal[0][idx[t]] + p.normal[0][idx[t + 1]] + p.normal[0][idx[t + 2]];
            agree += glm::dot(glm::cross(b - a, c - a), n) > 0;
            ++total;
        }
    }
    EXPECT_GT(double(agree), 0.999 * double(total)) << agree << " of " << total;
}

TEST(FrontEnd, StaticSceneIsBitwiseStaticAndMovingSceneMoves) {
    const FrontEnd still(readSceneFile(test::sourcePath("scenes/static.json")));
    EXPECT_FALSE(still.geometryMoves());
    for (const TessellatedPatch& p : tessellateAll(still)) {
        ASSERT_EQ(p.position[0], p.position[1]);
        ASSERT_EQ(p.normal[0], p.normal[1]);
    }
    const FrontEnd moving(readSceneFile(test::sourcePath("scenes/motion.json")));
    EXPECT_TRUE(moving.geometryMoves());
}

TEST(FrontEnd, EffectsOfEveryShippedScene) {
    const std::map<std::string, std::array<bool, 3>> expected = {
        {"default.json", {true, true, false}},      {"motion_defocus.json", {true, true, false}},
        {"static.json", {false, false, false}},     {"motion.json", {true, false, false}},
        {"defocus.json", {false, true, false}},     {"transparency.json", {true, false, true}},
        {"ngons_loop.json", {false, false, false}}, {"hybrid.json", {true, false, false}},
        {"camera_pan.json", {true, false, false}}};
    for (const std::string& path : test::sceneFiles()) {
        const std::string name = std::filesystem::path(path).filename().string();
        const FrontEnd fe(readSceneFile(path));
        const Effects e = detectEffects(fe.scene(), fe.geometryMoves(), fe.camera().moves());
        ASSERT_TRUE(expected.count(name)) << "add " << name << " to this test";
        EXPECT_EQ(e.motion, expected.at(name)[0]) << name;
        EXPECT_EQ(e.defocus, expected.at(name)[1]) << name;
        EXPECT_EQ(e.transparency, expected.at(name)[2]) << name;
    }
}

// A full turn puts every control point back: with straight-line motion that is no motion, and the
// simulator says so instead of blurring by rounding noise.
TEST(FrontEnd, AFullTurnIsNoMotionAndIsReported) {
    SceneDesc scene = readSceneFile(test::sourcePath("scenes/static.json"));
    scene.objects[0].close.rotateDegrees = scene.objects[0].open.rotateDegrees + Vec3(0, 360, 0);
    const FrontEnd fe(scene);
    EXPECT_TRUE(fe.objects()[0].points.keyframesReturnToStart);
    EXPECT_FALSE(fe.geometryMoves());
    scene.objects[0].close.rotateDegrees = scene.objects[0].open.rotateDegrees + Vec3(0, 90, 0);
    const FrontEnd turning(scene);
    EXPECT_FALSE(turning.objects()[0].points.keyframesReturnToStart);
    EXPECT_TRUE(turning.geometryMoves());
}

TEST(FrontEnd, ClosedShutterMeansNoMotion) {
    SceneDesc scene = readSceneFile(test::sourcePath("scenes/motion.json"));
    scene.shutter = {0.5f, 0.5f};
    const FrontEnd fe(scene);
    EXPECT_FALSE(fe.geometryMoves());
    EXPECT_FALSE(detectEffects(fe.scene(), fe.geometryMoves(), fe.camera().moves()).motion);
}

TEST(FrontEnd, HardCaseFactorsCullOrClampAndNeverProduceNaN) {
    const float inf = std::numeric_limits<float>::infinity();
    const std::string torus = test::sourcePath("scenes/cages/catmark_torus.obj");
    struct Case {
        float factor;
        bool culled;
        std::size_t pointsPerPatch;
    };
    for (const Case& c : {Case{1, false, 4}, Case{63, false, 64 * 64}, Case{64, false, 65 * 65},
                          Case{1e-7f, false, 4}, Case{inf, false, 65 * 65},
                          Case{std::numeric_limits<float>::quiet_NaN(), true, 0},
                          Case{-inf, true, 0}, Case{-2, true, 0}, Case{0, true, 0}}) {
        const FrontEnd fe(sceneWithCage(torus, Partitioning::Integer, c.factor));
        for (const TessellatedPatch& p : tessellateAll(fe)) {
            EXPECT_EQ(p.culled(), c.culled) << c.factor;
            EXPECT_EQ(p.tessellation.points.size(), c.pointsPerPatch) << c.factor;
            for (int end = 0; end < 2; ++end)
                for (const Vec3& v : p.position[end])
                    ASSERT_TRUE(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z));
        }
    }
}

TEST(FrontEnd, TessellationIsDeterministicAcrossWorkspaces) {
    const FrontEnd fe(readSceneFile(test::sourcePath("scenes/motion_defocus.json")));
    const auto a = tessellateAll(fe);
    FrontEndWorkspace other = fe.makeWorkspace();
    for (std::size_t i = a.size(); i-- > 0;) {  // reverse order, fresh workspace
        TessellatedPatch b;
        fe.tessellate(i, b, other);
        ASSERT_EQ(a[i].tessellation.indices, b.tessellation.indices);
        ASSERT_EQ(a[i].position[0], b.position[0]);
        ASSERT_EQ(a[i].position[1], b.position[1]);
    }
}

TEST(FrontEnd, MissingCageNamesTheSceneField) {
    SceneDesc scene = sceneWithCage("/nonexistent/cage.obj", Partitioning::Integer, 4);
    scene.path = "scene.json";
    try {
        FrontEnd fe(scene);
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(
                      "scene.json: objects[0].cage: cannot open '/nonexistent/cage.obj'"),
                  std::string::npos)
            << e.what();
    }
}

// Each number is within the readers' cap of 1e30, but a cage coordinate of 1e30 scaled by 1e30 is
// infinite: the object is refused by name instead of tessellating into NaN vertices.
TEST(FrontEnd, ControlPointsBeyondTheFloatRangeNameTheObject) {
    const std::string cage = test::temporaryDirectory() + "/far_quad.obj";
    std::ofstream(cage) << "v 1e30 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 4 3\n";
    SceneDesc scene = sceneWithCage(cage, Partitioning::Integer, 4);
    scene.path = "scene.json";
    const ObjectDesc good = scene.objects[0];
    scene.objects.insert(scene.objects.begin(), good);
    scene.objects[1].close.scale = Vec3(1e30f);  // finite at shutter open, infinite at close
    try {
        FrontEnd fe(scene);
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_EQ(e.field(), "objects[1]");
        EXPECT_NE(std::string(e.what()).find("scene.json: objects[1]: vertex 1 of '" + cage +
                                             "' is not finite at shutter close"),
                  std::string::npos)
            << e.what();
    }
    // 1e38: still a float, and a motion (the cage's float length overflowed, and its tolerance
    // for "back where it started" with it).
    scene.objects[1].close.scale = Vec3(1e8f);
    const FrontEnd fe(scene);
    EXPECT_TRUE(fe.objects()[1].points.moves());
    EXPECT_FALSE(fe.objects()[1].points.keyframesReturnToStart);
    for (const TessellatedPatch& p : tessellateAll(fe))
        for (int end = 0; end < 2; ++end)
            for (const Vec3& v : p.position[end])
                ASSERT_TRUE(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z));
}

// Objects are built on several threads; the scene's objects come out in their order, each the
// same as on one thread, and of two bad objects the first in the scene is the one reported.
TEST(FrontEnd, ObjectsBuiltOnThreadsAreThoseOfOneThread) {
    const SceneDesc scene = readSceneFile(test::sourcePath("scenes/motion_defocus.json"));
    ASSERT_GE(scene.objects.size(), 2u);
    const FrontEnd one(scene, 1), two(scene, 2);
    ASSERT_EQ(one.patchCount(), two.patchCount());
    for (std::size_t k = 0; k < scene.objects.size(); ++k)
        EXPECT_EQ(one.objects()[k].cage.positions, two.objects()[k].cage.positions);
    const auto a = tessellateAll(one), b = tessellateAll(two);
    for (std::size_t i = 0; i < a.size(); ++i) {
        ASSERT_EQ(a[i].tessellation.indices, b[i].tessellation.indices);
        ASSERT_EQ(a[i].position[0], b[i].position[0]);
        ASSERT_EQ(a[i].position[1], b[i].position[1]);
    }
    SceneDesc bad = scene;
    bad.path = "scene.json";
    bad.objects[0].cagePath = "/nonexistent/first.obj";
    bad.objects[1].cagePath = "/nonexistent/second.obj";
    for (int run = 0; run < 8; ++run) {
        try {
            FrontEnd fe(bad, 2);
            FAIL() << "no error";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find("scene.json: objects[0].cage: cannot open "
                                                 "'/nonexistent/first.obj'"),
                      std::string::npos)
                << e.what();
        }
    }
}

}  // namespace
}  // namespace patchsim
