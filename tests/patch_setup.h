#pragma once
// A scene's front end and patch rasterizer, built the way the frame driver builds them, for tests
// that drive the rasterizer's steps one tile or one group at a time.

#include "core/scene.h"
#include "rasterizer/patent/patch_rasterizer.h"
#include "tessellator/front_end.h"

namespace patchsim::test {

struct PatchSetup {
    explicit PatchSetup(const SceneDesc& scene, const RasterizerOptions& options = {})
        : fe(scene),
          effects(detectEffects(scene, fe.geometryMoves(), fe.camera().moves())),
          samples(scene.film.seed, scene.film.samplesPerPixel, effects),
          lens{scene.lens.apertureRadius, scene.lens.focusDistance},
          rasterizer(fe.camera(), lens, samples, effects, options) {}
    // The rasterizer holds references to the camera and the samples.
    PatchSetup(const PatchSetup&) = delete;
    PatchSetup& operator=(const PatchSetup&) = delete;

    // Patch i tessellated, as the rasterizer takes it (in camera space, opaque).
    MovingMesh mesh(std::size_t i, FrontEndWorkspace& workspace) const {
        TessellatedPatch patch;
        fe.tessellate(i, patch, workspace);
        MovingMesh m;
        toMovingMesh(patch, fe.camera(), effects.motion, int(i), true, m);
        return m;
    }

    const FrontEnd fe;
    const Effects effects;
    const SampleGenerator samples;
    const LensModel lens;
    const PatchRasterizer rasterizer;
};

}  // namespace patchsim::test
