#include "pipeline/driver/scene_info.h"

#include <atomic>

#include "core/parallel.h"

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

std::vector<std::string> objectNotes(const SceneObject& o) {
    std::vector<std::string> notes;
    for (const std::string& w : o.cage.warnings) notes.push_back("warning: " + w);
    if (const int far = o.mesh->farEvaluatedFaceCount())
        notes.push_back("note: " + std::to_string(far) +
                        " faces evaluated on Far's patch table (OpenSubdiv 3.5.0's Bfr cannot "
                        "build them safely)");
    if (o.points.keyframesReturnToStart)
        notes.push_back(
            "note: " + o.desc.name +
            "'s keyframes put every control point back where it started (e.g. a 360-degree "
            "turn); control points move in straight lines between shutter open and close, so it "
            "does not move");
    return notes;
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
        for (const std::string& note : objectNotes(o)) out << "    " << note << "\n";
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
        << "triangles:     " << info.triangles << "\n";
    const auto effect = [&](const char* label, bool called, bool simulated) {
        out << label << yesNo(called) << (called && !simulated ? " (switched off)" : "") << "\n";
    };
    effect("motion:        ", info.called.motion, info.simulated.motion);
    effect("shading time:  ", info.called.shadingVaries, info.simulated.shadingVaries);
    effect("defocus:       ", info.called.defocus, info.simulated.defocus);
    effect("transparency:  ", info.called.transparency, info.simulated.transparency);
    out << "mode:          " << describeMode(info.simulated) << "\n";
}

}  // namespace patchsim
