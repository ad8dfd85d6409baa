#include "tessellator/subdivision_mesh.h"

#include <gtest/gtest.h>
#include <opensubdiv/far/patchMap.h>
#include <opensubdiv/far/patchTableFactory.h>
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>

#include <algorithm>
#include <map>
#include <random>

#include "core/error.h"
#include "tessellator/front_end.h"
#include "tests/test_paths.h"

namespace patchsim {
namespace {

namespace osd = OpenSubdiv::OPENSUBDIV_VERSION;

// Limit position and derivatives straight from a face's Bfr stencil.
Vec3 evaluateLimit(const SubdivisionMesh& mesh, const std::vector<Vec3>& points, int face, float u,
                   float v) {
    SubdivisionMesh::Stencil stencil;
    const float uv[2] = {u, v};
    mesh.evaluateStencil(face, uv, stencil);
    return mesh.applyStencil(face, stencil, stencil.position, points);
}

// An independent evaluator: Far's feature-adaptive patch table and PatchMap.
struct FarPoint {
    Vec3 p{0};
    void Clear(void* = nullptr) { p = Vec3(0); }
    void AddWithWeight(const FarPoint& src, float w) { p += w * src.p; }
};

class FarEvaluator {
  public:
    explicit FarEvaluator(const Cage& cage) {
        osd::Far::TopologyDescriptor desc;
        desc.numVertices = cage.vertexCount();
        desc.numFaces = cage.faceCount();
        desc.numVertsPerFace = cage.faceSizes.data();
        desc.vertIndicesPerFace = cage.faceVertices.data();
        osd::Sdc::Options sdc;
        sdc.SetVtxBoundaryInterpolation(osd::Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
        using Factory = osd::Far::TopologyRefinerFactory<osd::Far::TopologyDescriptor>;
        refiner_.reset(Factory::Create(desc, Factory::Options(osd::Sdc::SCHEME_CATMARK, sdc)));
        refiner_->RefineAdaptive(osd::Far::TopologyRefiner::AdaptiveOptions(3));
        osd::Far::PatchTableFactory::Options options;
        options.endCapType = osd::Far::PatchTableFactory::Options::ENDCAP_GREGORY_BASIS;
        table_.reset(osd::Far::PatchTableFactory::Create(*refiner_, options));
        const int refined = refiner_->GetNumVerticesTotal();
        points_.resize(std::size_t(refined + table_->GetNumLocalPoints()));
        for (int i = 0; i < cage.vertexCount(); ++i)
            points_[std::size_t(i)].p = cage.positions[std::size_t(i)];
        osd::Far::PrimvarRefiner primvar(*refiner_);
        FarPoint* src = points_.data();
        for (int level = 1; level <= refiner_->GetMaxLevel(); ++level) {
            FarPoint* dst = src + refiner_->GetLevel(level - 1).GetNumVertices();
            primvar.Interpolate(level, src, dst);
            src = dst;
        }
        if (table_->GetNumLocalPoints() > 0)
            table_->ComputeLocalPointValues(points_.data(), points_.data() + refined);
        map_ = std::make_unique<osd::Far::PatchMap>(*table_);
    }

    Vec3 evaluate(int face, float u, float v) const {
        const auto* handle = map_->FindPatch(face, u, v);
        EXPECT_NE(handle, nullptr);
        float w[20], wu[20], wv[20];
        table_->EvaluateBasis(*handle, u, v, w, wu, wv);
        const auto cvs = table_->GetPatchVertices(*handle);
        Vec3 p(0);
        for (int i = 0; i < cvs.size(); ++i) p += w[i] * points_[std::size_t(cvs[i])].p;
        return p;
    }

  private:
    std::unique_ptr<osd::Far::TopologyRefiner> refiner_;
    std::unique_ptr<osd::Far::PatchTable> table_;
    std::unique_ptr<osd::Far::PatchMap> map_;
    std::vector<FarPoint> points_;
};

TEST(SubdivisionMesh, BfrStencilsAgreeWithFarPatchTableOnARegularSurface) {
    const Cage cage = readObjCage(test::sourcePath("scenes/cages/catmark_torus.obj"));
    const SubdivisionMesh mesh(cage, SubdivisionScheme::Catmark, "torus");
    const FarEvaluator far(cage);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> uv(0.0f, 1.0f);
    double worst = 0;
    for (int face = 0; face < cage.faceCount(); ++face) {
        for (int k = 0; k < 20; ++k) {
            const float u = uv(rng), v = uv(rng);
            const Vec3 a = evaluateLimit(mesh, cage.positions, face, u, v);
            const Vec3 b = far.evaluate(face, u, v);
            worst = std::max(worst, double(glm::length(a - b)));
        }
    }
    EXPECT_LT(worst, 1e-5);
}

// The faces' surfaces are built on several threads through one locked cache: every face's
// stencils are the same, bit for bit, on any thread count. Creased and N-gon cages, where Bfr
// builds irregular surfaces and faces share cached patch trees.
TEST(SubdivisionMesh, SurfacesBuiltOnSeveralThreadsGiveOneThreadsStencils) {
    const std::vector<std::pair<std::string, SubdivisionScheme>> cages = {
        {test::sourcePath("scenes/cages/catmark_cube_creases1.obj"), SubdivisionScheme::Catmark},
        {test::sourcePath("scenes/cages/catmark_nonquads.obj"), SubdivisionScheme::Catmark},
        {test::sourcePath("scenes/cages/loop_icosahedron.obj"), SubdivisionScheme::Loop},
        {test::sourcePath("scenes/cages/catmark_rook.obj"), SubdivisionScheme::Catmark}};
    for (const auto& [path, scheme] : cages) {
        const Cage cage = readObjCage(path);
        const SubdivisionMesh one(cage, scheme, path, SubdivisionMesh::FarFaces::OnlyUnsafeForBfr,
                                  1);
        for (int threads : {2, 3}) {
            const SubdivisionMesh many(cage, scheme, path,
                                       SubdivisionMesh::FarFaces::OnlyUnsafeForBfr, threads);
            ASSERT_EQ(many.patches().size(), one.patches().size()) << path;
            for (int face = 0; face < cage.faceCount(); ++face) {
                ASSERT_EQ(many.controlPointCount(face), one.controlPointCount(face)) << path;
                for (const float uv : {0.0f, 0.37f, 1.0f}) {
                    const float faceUV[2] = {uv, 0.61f};
                    SubdivisionMesh::Stencil a, b;
                    one.evaluateStencil(face, faceUV, a);
                    many.evaluateStencil(face, faceUV, b);
                    ASSERT_EQ(a.controlPoints, b.controlPoints) << path << " face " << face;
                    ASSERT_EQ(a.position, b.position) << path << " face " << face;
                    ASSERT_EQ(a.du, b.du) << path << " face " << face;
                    ASSERT_EQ(a.dv, b.dv) << path << " face " << face;
                }
            }
        }
    }
}

TEST(SubdivisionMesh, BilinearSchemeIsBilinearInterpolation) {
    const std::string path = test::regressionCagesDir() + "/bilinear_cube.obj";
    const Cage cage = readObjCage(path);
    const SubdivisionMesh mesh(cage, SubdivisionScheme::Bilinear, path);
    for (int face = 0; face < cage.faceCount(); ++face) {
        const auto& fv = mesh.faceVertices(face);
        ASSERT_EQ(fv.size(), 4u);
        const Vec3 c[4] = {cage.positions[std::size_t(fv[0])], cage.positions[std::size_t(fv[1])],
                           cage.positions[std::size_t(fv[2])], cage.positions[std::size_t(fv[3])]};
        for (float u : {0.0f, 0.3f, 1.0f}) {
            for (float v : {0.0f, 0.7f, 1.0f}) {
                const Vec3 expected = (1 - u) * (1 - v) * c[0] + u * (1 - v) * c[1] + u * v * c[2] +
                                      (1 - u) * v * c[3];
                EXPECT_LT(glm::length(evaluateLimit(mesh, cage.positions, face, u, v) - expected),
                          1e-5f);
            }
        }
    }
}

TEST(SubdivisionMesh, CatmarkLimitOfARegularVertexMatchesTheLimitMask) {
    // A regular interior vertex's limit position is (16 v + 4 sum(edge neighbours) +
    // sum(diagonal neighbours)) / 36. Check it at the (0,0) corner of every torus face.
    const Cage cage = readObjCage(test::sourcePath("scenes/cages/catmark_torus.obj"));
    const SubdivisionMesh mesh(cage, SubdivisionScheme::Catmark, "torus");
    const int faces = cage.faceCount();
    for (int face = 0; face < faces; ++face) {
        const int v = mesh.faceVertices(face)[0];
        Vec3 edgeSum(0), diagonalSum(0);
        int edgeCount = 0, diagonalCount = 0;
        for (int f = 0; f < faces; ++f) {
            const auto& fv = mesh.faceVertices(f);
            const auto it = std::find(fv.begin(), fv.end(), v);
            if (it == fv.end()) continue;
            const std::size_t i = std::size_t(it - fv.begin());
            edgeSum += cage.positions[std::size_t(fv[(i + 1) % 4])];  // each edge seen once
            diagonalSum += cage.positions[std::size_t(fv[(i + 2) % 4])];
            ++edgeCount;
            ++diagonalCount;
        }
        ASSERT_EQ(edgeCount, 4);
        const Vec3 expected =
            (16.0f * cage.positions[std::size_t(v)] + 4.0f * edgeSum + diagonalSum) / 36.0f;
        EXPECT_LT(glm::length(evaluateLimit(mesh, cage.positions, face, 0, 0) - expected), 1e-5f);
    }
}

TEST(SubdivisionMesh, NGonsBecomeOneQuadSubPatchPerCorner) {
    const Cage cage = readObjCage(test::sourcePath("scenes/cages/catmark_nonquads.obj"));
    const SubdivisionMesh mesh(cage, SubdivisionScheme::Catmark, "nonquads");
    std::size_t expected = 0;
    for (int n : cage.faceSizes) expected += n == 4 ? 1 : std::size_t(n);
    EXPECT_EQ(mesh.patches().size(), expected);
    for (const PatchInfo& p : mesh.patches()) EXPECT_EQ(p.domain, PatchDomain::Quad);
    // Sub-patch corners are where Bfr puts them: (1,1) is the face centre, the mean limit
    // position of the sub-patches' (1,1) corners equals each of them.
    for (const PatchInfo& p : mesh.patches()) {
        if (p.subface < 0) continue;
        float centre[2], first[2];
        mesh.faceCoord(p, 1, 1, centre);
        const PatchInfo* sibling = &p;
        for (const PatchInfo& q : mesh.patches())
            if (q.face == p.face && q.subface == 0) sibling = &q;
        mesh.faceCoord(*sibling, 1, 1, first);
        EXPECT_LT(glm::length(evaluateLimit(mesh, cage.positions, p.face, centre[0], centre[1]) -
                              evaluateLimit(mesh, cage.positions, p.face, first[0], first[1])),
                  1e-5f);
    }
}

// A face that uses one pair of vertices twice makes Far add a second edge with those vertices;
// every such edge names its points by the lowest-numbered one, so all see the same spans.
TEST(SubdivisionMesh, EdgesWithTheSameVerticesShareTheirSpans) {
    const Cage cage = readObjCage(test::sourcePath("scenes/cages/catmark_nonman_edges.obj"));
    const SubdivisionMesh mesh(cage, SubdivisionScheme::Catmark, "nonman_edges");
    std::map<std::pair<int, int>, int> first;
    int copies = 0;
    for (int e = 0; e < mesh.cageEdgeCount(); ++e) {
        const int a = mesh.cageEdgeVertex(e, 0), b = mesh.cageEdgeVertex(e, 1);
        const std::pair ends{std::min(a, b), std::max(a, b)};
        if (ends.first == ends.second) {  // degenerate: its own
            EXPECT_EQ(mesh.sharedEdge(e), e);
            continue;
        }
        const int expected = first.emplace(ends, e).first->second;
        EXPECT_EQ(mesh.sharedEdge(e), expected) << "edge " << e;
        EXPECT_EQ(&mesh.spansOnCageEdge(e), &mesh.spansOnCageEdge(expected));
        copies += expected != e;
    }
    EXPECT_EQ(copies, 4);  // four pairs, each used twice by one face (three faces)
}

TEST(SubdivisionMesh, LoopNeedsTriangles) {
    const Cage cage = readObjCage(test::sourcePath("scenes/cages/catmark_torus.obj"));
    EXPECT_THROW(SubdivisionMesh(cage, SubdivisionScheme::Loop, "torus"), InputError);
}

}  // namespace
}  // namespace patchsim
