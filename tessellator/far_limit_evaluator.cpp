#include "tessellator/far_limit_evaluator.h"

#include <opensubdiv/bfr/parameterization.h>
#include <opensubdiv/far/patchMap.h>
#include <opensubdiv/far/patchTableFactory.h>
#include <opensubdiv/far/ptexIndices.h>
#include <opensubdiv/far/stencilTableFactory.h>

#include <stdexcept>
#include <unordered_map>

namespace patchsim {

namespace {

// Bfr's default approximation depth for sharp features (Bfr::SurfaceFactory::Options), and for
// smooth irregular ones.
constexpr int kSharpIsolationLevel = 6;
constexpr int kSmoothIsolationLevel = 2;
constexpr int kMaxPatchPoints = 20;  // Gregory basis

}  // namespace

bool bfrBuilderIsUnsafe(const osd::Far::TopologyLevel& level, int face) {
    bool valence2Interior = false, boundary = false, sharp = false;
    for (const int v : level.GetFaceVertices(face)) {
        const bool manifoldInterior = !level.IsVertexBoundary(v) && !level.IsVertexNonManifold(v);
        valence2Interior =
            valence2Interior || (manifoldInterior && level.GetVertexFaces(v).size() == 2);
        boundary = boundary || !manifoldInterior;
        for (const int e : level.GetVertexEdges(v)) sharp = sharp || level.GetEdgeSharpness(e) > 0;
    }
    return valence2Interior && boundary && sharp;
}

struct FarLimitEvaluator::Impl {
    std::unique_ptr<osd::Far::TopologyRefiner> refiner;
    std::unique_ptr<const osd::Far::PatchTable> patches;
    std::unique_ptr<const osd::Far::PatchMap> map;
    // Refined vertices (past the cage's) in cage vertices; end-cap points in refined vertices.
    // The template types, not Far::StencilTable: OpenSubdiv's wrappers downcast a
    // StencilTableReal<float> to StencilTable, which is undefined behaviour (UBSan stops on it).
    std::unique_ptr<const osd::Far::StencilTableReal<float>> refined;
    const osd::Far::StencilTableReal<float>* local = nullptr;  // owned by `patches`
    int refinedVertices = 0;                                   // cage and refined vertices
    std::unique_ptr<osd::Far::PtexIndices> ptex;
    osd::Sdc::SchemeType scheme = osd::Sdc::SCHEME_CATMARK;
    int baseVertices = 0;
    std::unordered_map<int, std::vector<int>> controlPoints;  // by face

    const osd::Far::PatchTable::PatchHandle* find(int face, const float faceUV[2],
                                                  float subUV[2]) const {
        const int size = refiner->GetLevel(0).GetFaceVertices(face).size();
        const osd::Bfr::Parameterization param(scheme, size);
        int ptexFace = ptex->GetFaceId(face);
        if (param.HasSubFaces())
            ptexFace += param.ConvertCoordToNormalizedSubFace(faceUV, subUV);
        else
            subUV[0] = faceUV[0], subUV[1] = faceUV[1];
        return map->FindPatch(ptexFace, double(subUV[0]), double(subUV[1]));
    }
};

FarLimitEvaluator::FarLimitEvaluator(
    const osd::Far::TopologyDescriptor& descriptor,
    const osd::Far::TopologyRefinerFactory<osd::Far::TopologyDescriptor>::Options& options,
    const std::vector<int>& faces)
    : impl_(std::make_unique<Impl>()) {
    using Factory = osd::Far::TopologyRefinerFactory<osd::Far::TopologyDescriptor>;
    impl_->refiner.reset(Factory::Create(descriptor, options));
    if (!impl_->refiner) throw std::runtime_error("Far rejected a topology Bfr accepted");
    impl_->scheme = options.schemeType;
    impl_->baseVertices = impl_->refiner->GetLevel(0).GetNumVertices();
    osd::Far::TopologyRefiner::AdaptiveOptions adaptive(kSharpIsolationLevel);
    adaptive.SetSecondaryLevel(kSmoothIsolationLevel);
    impl_->refiner->RefineAdaptive(adaptive,
                                   osd::Far::ConstIndexArray(faces.data(), int(faces.size())));
    osd::Far::PatchTableFactory::Options patchOptions(kSharpIsolationLevel);
    patchOptions.endCapType = osd::Far::PatchTableFactory::Options::ENDCAP_GREGORY_BASIS;
    impl_->patches.reset(osd::Far::PatchTableFactory::Create(*impl_->refiner, patchOptions));
    osd::Far::StencilTableFactoryReal<float>::Options stencilOptions;
    stencilOptions.generateIntermediateLevels = true;
    stencilOptions.generateOffsets = true;
    impl_->refined.reset(
        osd::Far::StencilTableFactoryReal<float>::Create(*impl_->refiner, stencilOptions));
    impl_->local = impl_->patches->GetLocalPointStencilTable<float>();
    impl_->refinedVertices = impl_->refiner->GetNumVerticesTotal();
    impl_->map = std::make_unique<osd::Far::PatchMap>(*impl_->patches);
    impl_->ptex = std::make_unique<osd::Far::PtexIndices>(*impl_->refiner);
    LimitStencil scratch;
    for (const int face : faces) {
        if (!hasSurface(face)) continue;
        const float centre[2] = {0.5f, 0.5f};
        const osd::Bfr::Parameterization param(
            impl_->scheme, impl_->refiner->GetLevel(0).GetFaceVertices(face).size());
        float uv[2] = {centre[0], centre[1]};
        if (param.GetType() == osd::Bfr::Parameterization::TRI) uv[0] = uv[1] = 1.0f / 3.0f;
        if (param.HasSubFaces()) param.ConvertNormalizedSubFaceToCoord(0, centre, uv);
        evaluate(face, uv, scratch);
        impl_->controlPoints[face] = scratch.controlPoints;
    }
}

FarLimitEvaluator::~FarLimitEvaluator() = default;

bool FarLimitEvaluator::hasSurface(int face) const {
    if (impl_->refiner->GetLevel(0).IsFaceHole(face)) return false;
    const float centre[2] = {0.25f, 0.25f};
    float sub[2];
    return impl_->find(face, centre, sub) != nullptr;
}

const std::vector<int>& FarLimitEvaluator::controlPoints(int face) const {
    static const std::vector<int> kNone;
    const auto it = impl_->controlPoints.find(face);
    return it == impl_->controlPoints.end() ? kNone : it->second;
}

void FarLimitEvaluator::evaluate(int face, const float faceUV[2], LimitStencil& out) const {
    out.controlPoints.clear();
    out.position.clear();
    out.du.clear();
    out.dv.clear();
    float sub[2];
    const auto* handle = impl_->find(face, faceUV, sub);
    if (!handle) throw std::logic_error("no Far patch at a point of a face with a surface");
    float w[kMaxPatchPoints], wu[kMaxPatchPoints], wv[kMaxPatchPoints];
    impl_->patches->EvaluateBasis(*handle, sub[0], sub[1], w, wu, wv);
    const osd::Far::ConstIndexArray points = impl_->patches->GetPatchVertices(*handle);
    auto add = [&](int vertex, float a, float b, float c) {
        for (std::size_t k = 0; k < out.controlPoints.size(); ++k) {
            if (out.controlPoints[k] != vertex) continue;
            out.position[k] += a;
            out.du[k] += b;
            out.dv[k] += c;
            return;
        }
        out.controlPoints.push_back(vertex);
        out.position.push_back(a);
        out.du.push_back(b);
        out.dv.push_back(c);
    };
    // A patch point is a cage vertex, a refined vertex (a stencil on cage vertices) or an end-cap
    // point (a stencil on cage and refined vertices).
    auto addPoint = [&](int point, float a, float b, float c, auto& self) -> void {
        if (point < impl_->baseVertices) {
            add(point, a, b, c);
            return;
        }
        const bool isLocal = point >= impl_->refinedVertices;
        const osd::Far::StencilReal<float> s =
            isLocal ? impl_->local->GetStencil(point - impl_->refinedVertices)
                    : impl_->refined->GetStencil(point - impl_->baseVertices);
        const int* vertices = s.GetVertexIndices();
        const float* weights = s.GetWeights();
        for (int k = 0; k < s.GetSize(); ++k) {
            if (isLocal)
                self(vertices[k], a * weights[k], b * weights[k], c * weights[k], self);
            else
                add(vertices[k], a * weights[k], b * weights[k], c * weights[k]);
        }
    };
    for (int i = 0; i < points.size(); ++i) addPoint(points[i], w[i], wu[i], wv[i], addPoint);
}

}  // namespace patchsim
