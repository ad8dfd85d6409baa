#pragma once
// The patch rasterizer of US 8,791,945 as a visibility method, and the pieces of it the methods
// that start from its sharp frames share (pipeline/methods/sharp_frame_method.h).

#include <vector>

#include "pipeline/methods/visibility_method.h"

namespace patchsim {

// Every patch through the patch rasterizer (rasterizer/patent/frame_rasterizer.h) into `targets`,
// the tile rows `partition` owns; its counts flushed and its work added to `ops`, per patch. The
// hierarchies, which every process builds, are counted by the first process only. `progress`
// draws a bar (shared between processes when the frame is split).
struct PatchPass {
    const SampleGenerator* samples;
    Effects rasterized;  // the effects the rasterizer simulates
    VisibilityTargets targets;
    FramePartition partition;
    bool progress;
    MemoryTrace* memoryTrace = nullptr;  // the frame's surface traffic, when it is recorded
};
void rasterizePatches(const FrameInputs& in, const PatchPass& pass, std::vector<PatchOps>& ops);

// The patch rasterizer's memory beside the film: one tile's rays per worker. Throws InputError
// (the scene, "rasterizer.tile_size") when they do not fit the memory budget.
void checkTileScratch(const SceneDesc& scene, const RenderOptions& options, int workers);

// A frame rasterized in tiles: its rows belong to a process by the tile row they lie in.
class TiledFrame : public MethodFrame {
  public:
    using MethodFrame::MethodFrame;
    bool ownsPixelRow(int y) const override {
        return in_.partition.ownsTiledPixelRow(y, in_.scene->rasterizer.tileSize);
    }
};

}  // namespace patchsim
