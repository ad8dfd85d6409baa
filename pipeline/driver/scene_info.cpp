#include "pipeline/driver/scene_info.h"

#include <atomic>

#include "pipeline/core/parallel.h"

namespace patchsim {

SceneInfo gatherSceneInfo(const FrontEnd& frontEnd, const EffectOverrides& overrides, int threads) {
    SceneInfo info;
    info.objects = frontEnd.objects().size();
    for (const SceneObject& o : frontEnd.objects())
        info.cageFaces += std::size_t(o.cage.faceCount());
    info.patches = frontEnd.patchCount();
    std::vector<std::uint64_t> points(info.patches), triangles(info.patches);
    std::vector<char> culled(info.patches);
    const int workers = resolveThreadCount(threads);
    std::vector<FrontEndWorkspace> workspaces;
    for (int w = 0; w < workers; ++w) workspaces.push_back(frontEnd.makeWorkspace());
    std::vector<TessellatedPatch> scratch(static_cast<std::size_t>(workers));
    parallelFor(info.patches, workers, [&](int worker, std::size_t i) {
        TessellatedPatch& patch = scratch[std::size_t(worker)];
        frontEnd.tessellate(i, patch, workspaces[std::size_t(worker)], /*evaluate=*/false);
        points[i] = patch.tessellation.points.size();
        triangles[i] = patch.triangleCount();
        culled[i] = patch.culled();
    });
    for (std::size_t i = 0; i < info.patches; ++i) {
        info.domainPoints += points[i];
        info.triangles += triangles[i];
        info.culledPatches += culled[i] ? 1 : 0;
    }
    info.called =
        detectEffects(frontEnd.scene(), frontEnd.geometryMoves(), frontEnd.camera().moves());
    info.simulated = applyOverrides(info.called, overrides);
    return info;
}

void printSceneInfo(std::ostream& out, const FrontEnd& frontEnd, const SceneInfo& info) {
    const SceneDesc& scene = frontEnd.scene();
    const auto yesNo = [](bool b) { return b ? "yes" : "no"; };
    out << "scene:         " << scene.path << "\n"
        << "objects:       " << info.objects << "\n";
    for (const SceneObject& o : frontEnd.objects()) {
        out << "  " << o.desc.name << ": " << o.desc.cagePath << " (" << schemeName(o.desc.scheme)
            << ", " << o.cage.vertexCount() << " vertices, " << o.cage.faceCount() << " faces, "
            << o.mesh->patches().size() << " patches)\n";
        for (const std::string& w : o.cage.warnings) out << "    warning: " << w << "\n";
        if (const int far = o.mesh->farEvaluatedFaceCount())
            out << "    note: " << far
                << " faces evaluated on Far's patch table (OpenSubdiv 3.5.0's Bfr cannot build "
                   "them safely)\n";
    }
    out << "film:          " << scene.film.width << "x" << scene.film.height << ", "
        << scene.film.samplesPerPixel << " spp, seed " << scene.film.seed << "\n"
        << "tessellation:  " << partitioningName(scene.tessellation.partitioning) << ", ";
    if (scene.tessellation.targetEdgePixels > 0)
        out << "adaptive (" << scene.tessellation.targetEdgePixels << " px per edge, max "
            << scene.tessellation.maxFactor << ")";
    else
        out << "fixed factor " << scene.tessellation.factor;
    out << ", inside " << insideReductionName(scene.tessellation.insideReduction) << "\n"
        << "cage faces:    " << info.cageFaces << "\n"
        << "patches:       " << info.patches << " (" << info.culledPatches << " culled)\n"
        << "domain points: " << info.domainPoints << "\n"
        << "triangles:     " << info.triangles << "\n"
        << "motion:        " << yesNo(info.called.motion)
        << (info.called.motion && !info.simulated.motion ? " (switched off)" : "") << "\n"
        << "defocus:       " << yesNo(info.called.defocus)
        << (info.called.defocus && !info.simulated.defocus ? " (switched off)" : "") << "\n"
        << "transparency:  " << yesNo(info.called.transparency)
        << (info.called.transparency && !info.simulated.transparency ? " (switched off)" : "")
        << "\n"
        << "mode:          " << describeMode(info.simulated) << "\n";
}

}  // namespace patchsim
