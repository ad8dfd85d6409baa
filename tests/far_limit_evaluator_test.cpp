#include "tessellator/far_limit_evaluator.h"

#include <gtest/gtest.h>
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>

#include <random>

#include "core/obj_reader.h"
#include "core/scene_reader.h"
#include "tessellator/subdivision_mesh.h"
#include "tests/test_paths.h"

namespace patchsim {
namespace {

float diagonal(const Cage& cage) {
    Vec3 lo(1e30f), hi(-1e30f);
    for (const Vec3& p : cage.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
    return glm::length(hi - lo);
}

Vec3 limitPoint(const SubdivisionMesh& mesh, const Cage& cage, int face, float u, float v) {
    SubdivisionMesh::Stencil stencil;
    const float uv[2] = {u, v};
    mesh.evaluateStencil(face, uv, stencil);
    return mesh.applyStencil(face, stencil, stencil.position, cage.positions);
}

// Limit positions of a cage's vertices, edge midpoints and face centres: uniform refinement to
// Bfr's sharp depth, where semi-sharp creases (sharpness 5 or less) have decayed, and Far's limit
// masks there. Independent of both Bfr and the patch table.
struct ExactLimits {
    static constexpr int kLevels = 6;
    struct Point {
        Vec3 p{0};
        void Clear(void* = nullptr) { p = Vec3(0); }
        void AddWithWeight(const Point& s, float w) { p += w * s.p; }
    };
    std::vector<Point> limit;
    std::vector<int> vertexChild, edgeChild, faceChild;

    ExactLimits(const Cage& cage, const std::string& path) {
        namespace osd = OpenSubdiv::OPENSUBDIV_VERSION;
        osd::Far::TopologyDescriptor desc;
        desc.numVertices = cage.vertexCount();
        desc.numFaces = cage.faceCount();
        desc.numVertsPerFace = cage.faceSizes.data();
        desc.vertIndicesPerFace = cage.faceVertices.data();
        std::vector<int> pairs;
        std::vector<float> weights;
        for (const CageCrease& c : cage.creases) {
            pairs.insert(pairs.end(), {c.v0, c.v1});
            weights.push_back(c.sharpness);
        }
        desc.numCreases = int(weights.size());
        desc.creaseVertexIndexPairs = pairs.data();
        desc.creaseWeights = weights.data();
        osd::Sdc::Options sdc;
        sdc.SetVtxBoundaryInterpolation(cage.boundary == BoundaryInterpolation::EdgeAndCorner
                                            ? osd::Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER
                                            : osd::Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
        using Factory = osd::Far::TopologyRefinerFactory<osd::Far::TopologyDescriptor>;
        const auto scheme = schemeOf(path);
        std::unique_ptr<osd::Far::TopologyRefiner> refiner(Factory::Create(
            desc, Factory::Options(scheme == SubdivisionScheme::Loop ? osd::Sdc::SCHEME_LOOP
                                                                     : osd::Sdc::SCHEME_CATMARK,
                                   sdc)));
        osd::Far::TopologyRefiner::UniformOptions uniform(kLevels);
        uniform.fullTopologyInLastLevel = true;  // the limit masks need it
        refiner->RefineUniform(uniform);
        std::vector<Point> coarse(std::size_t(cage.vertexCount())), fine;
        for (std::size_t i = 0; i < coarse.size(); ++i) coarse[i].p = cage.positions[i];
        const osd::Far::PrimvarRefiner primvar(*refiner);
        for (int level = 1; level <= kLevels; ++level) {
            fine.assign(std::size_t(refiner->GetLevel(level).GetNumVertices()), Point{});
            Point* dst = fine.data();
            primvar.Interpolate(level, coarse.data(), dst);
            coarse.swap(fine);
        }
        limit.resize(coarse.size());
        Point* limits = limit.data();
        primvar.Limit(coarse.data(), limits);
        // A coarse point's descendant at the finest level: its child vertex, level by level.
        auto descend = [&](int vertex) {
            for (int level = 1; level < kLevels; ++level)
                vertex = refiner->GetLevel(level).GetVertexChildVertex(vertex);
            return vertex;
        };
        const auto& base = refiner->GetLevel(0);
        if (refiner->GetSchemeType() != osd::Sdc::SCHEME_LOOP)  // Loop makes no face points
            for (int f = 0; f < base.GetNumFaces(); ++f)
                faceChild.push_back(descend(base.GetFaceChildVertex(f)));
        for (int e = 0; e < base.GetNumEdges(); ++e)
            edgeChild.push_back(descend(base.GetEdgeChildVertex(e)));
        for (int v = 0; v < base.GetNumVertices(); ++v)
            vertexChild.push_back(descend(base.GetVertexChildVertex(v)));
    }
    static SubdivisionScheme schemeOf(const std::string& path) {
        return path.find("loop_") != std::string::npos ? SubdivisionScheme::Loop
                                                       : SubdivisionScheme::Catmark;
    }
};

TEST(FarLimitEvaluator, NamesOnlyTheFacesBfr350CannotBuild) {
    const std::string path = test::sourcePath("scenes/cages/catmark_val2_interior.obj");
    const Cage cage = readObjCage(path);
    const SubdivisionMesh mesh(cage, SubdivisionScheme::Catmark, path);
    // Shape 8 of the nine has the creased valence-2 face on a boundary; its neighbours too.
    EXPECT_EQ(mesh.farEvaluatedFaceCount(), 8);
    const Cage torus = readObjCage(test::sourcePath("scenes/cages/catmark_torus.obj"));
    EXPECT_EQ(SubdivisionMesh(torus, SubdivisionScheme::Catmark, "torus").farEvaluatedFaceCount(),
              0);
}

// The Far path evaluated on every face of cages Bfr handles gives Bfr's surface.
TEST(FarLimitEvaluator, AgreesWithBfrWhereBfrIsSafe) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    for (const char* name : {"catmark_torus.obj", "catmark_nonquads.obj", "catmark_pawn.obj",
                             "catmark_cube_creases1.obj", "loop_icosahedron.obj"}) {
        const std::string path = test::sourcePath(std::string("scenes/cages/") + name);
        const Cage cage = readObjCage(path);
        const SubdivisionScheme scheme = ExactLimits::schemeOf(path);
        const SubdivisionMesh bfr(cage, scheme, path);
        const SubdivisionMesh far(cage, scheme, path, SubdivisionMesh::FarFaces::All);
        ASSERT_EQ(far.farEvaluatedFaceCount(), cage.faceCount());
        ASSERT_EQ(bfr.patches().size(), far.patches().size());
        double worst = 0;
        for (const PatchInfo& patch : bfr.patches()) {
            for (int k = 0; k < 8; ++k) {
                float u = unit(rng), v = unit(rng);
                if (patch.domain == PatchDomain::Triangle && u + v > 1) u = 1 - u, v = 1 - v;
                float uv[2];
                bfr.faceCoord(patch, u, v, uv);
                const Vec3 a = limitPoint(bfr, cage, patch.face, uv[0], uv[1]);
                const Vec3 b = limitPoint(far, cage, patch.face, uv[0], uv[1]);
                worst = std::max(worst, double(glm::length(a - b)));
            }
        }
        EXPECT_LT(worst, 1e-4 * diagonal(cage)) << name;
    }
}

// On the cages that crash Bfr 3.5.0, every patch meets the exact limit at its corners (cage
// vertices, edge midpoints, face centres). Interior valence-2 vertices are left out: there
// OpenSubdiv's patch evaluation (Bfr's and Far's alike) departs from its own limit mask.
TEST(FarLimitEvaluator, Valence2InteriorCagesMatchTheExactLimit) {
    for (const char* name : {"catmark_val2_interior.obj", "loop_val2_interior.obj"}) {
        const std::string path = test::sourcePath(std::string("scenes/cages/") + name);
        const Cage cage = readObjCage(path);
        const SubdivisionScheme scheme = ExactLimits::schemeOf(path);
        const SubdivisionMesh mesh(cage, scheme, path);
        ASSERT_GT(mesh.farEvaluatedFaceCount(), 0) << name;
        const ExactLimits exact(cage, path);
        std::vector<int> valence(std::size_t(cage.vertexCount()), 0);
        for (int v : cage.faceVertices) ++valence[std::size_t(v)];
        const float tolerance = 1e-5f * diagonal(cage);
        int checkedOnFar = 0;
        for (const PatchInfo& patch : mesh.patches()) {
            for (int c = 0; c < patch.cornerCount(); ++c) {
                const PointKey key = patch.corners[c];
                int child = 0;
                if (key.kind() == PointKey::Vertex) {
                    if (valence[std::size_t(key.index())] == 2) continue;
                    child = exact.vertexChild[std::size_t(key.index())];
                } else {
                    child = (key.kind() == PointKey::FaceCentre
                                 ? exact.faceChild
                                 : exact.edgeChild)[std::size_t(key.index())];
                }
                float local[2], uv[2];
                patchCorner(patch.domain, c, local);
                mesh.faceCoord(patch, local[0], local[1], uv);
                const Vec3 got = limitPoint(mesh, cage, patch.face, uv[0], uv[1]);
                EXPECT_LT(glm::length(got - exact.limit[std::size_t(child)].p), tolerance)
                    << name << " face " << patch.face << " corner " << c;
                checkedOnFar += mesh.farEvaluated(patch.face);
            }
            // Midpoints of whole cage edges.
            for (int e = 0; e < patch.cornerCount(); ++e) {
                if (patch.edgeSources[e].kind != EdgeFactorSource::WholeCageEdge) continue;
                float local[2], uv[2];
                patchEdgePoint(patch.domain, e, 0.5f, local);
                mesh.faceCoord(patch, local[0], local[1], uv);
                const Vec3 got = limitPoint(mesh, cage, patch.face, uv[0], uv[1]);
                const int child = exact.edgeChild[std::size_t(patch.edgeSources[e].cageEdge)];
                EXPECT_LT(glm::length(got - exact.limit[std::size_t(child)].p), tolerance)
                    << name << " face " << patch.face << " edge " << e;
                checkedOnFar += mesh.farEvaluated(patch.face);
            }
        }
        EXPECT_GT(checkedOnFar, 4 * mesh.farEvaluatedFaceCount()) << name;
    }
}

}  // namespace
}  // namespace patchsim
