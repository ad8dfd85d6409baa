#pragma once
// `patchsim sweep`: what accuracy costs in time (DESIGN.md section 9). Every scene, at every blur
// level, is rendered by every method at every sample count; each run's error against the
// converged image (converged_image.h), its wall time (median of repeats), its modelled cycles
// and its work go into one CSV row. Images of every run are kept, and plots are drawn by
// scripts/plot_results.py (matplotlib, plots.h) when Python has it.
//
// Everything but the wall time is a pure function of the scene and the settings: the CSV is the
// same for any thread count apart from that column.

#include <optional>
#include <string>
#include <vector>

#include "core/scene.h"
#include "core/scene_reader.h"
#include "pipeline/driver/render.h"
#include "pipeline/methods/visibility_method.h"
#include "pipeline/timing/hardware_config.h"

namespace patchsim {

struct SweepScene {
    std::string label;  // file stem, and "-blur<scale>" when the blur is scaled
    SceneDesc scene;
};

// The scene with its motion (object and camera keyframe differences) and its aperture scaled.
SceneDesc scaleBlur(const SceneDesc& scene, float scale);

// The labels of every scene at every blur (scene-major), as file names and CSV rows use them:
// the file's stem ("default" for the built-in scene, path ""), with as many parent folders as it
// takes to tell it from the other paths ("a-motion", "b-motion"), and "-blur<scale>" when the blur
// is scaled; characters other than letters, digits, '.', '_' and '-' become '_'; labels still
// equal get "-2", "-3" in order. Throws InputError when `paths` names one file twice.
std::vector<std::string> sweepSceneLabels(const std::vector<std::string>& paths,
                                          const std::vector<float>& blurs);

// One method at one setting of its own parameters (sweep --vary): what it renders with.
struct SweepVariant {
    const VisibilityMethod* method = nullptr;
    // "" when nothing varies; else "name=value" per varied parameter, joined by ';'
    // ("time-strata=16", "leaf-size=2;tile-size=16").
    std::string setting;
    RenderOptions render;  // the method's parameters at this setting (the method is `method`)
    // Rasterizer options of this setting, (key, value text), set on each scene's before a run.
    std::vector<std::pair<std::string, std::string>> rasterizer;

    // As file names use it: the method, then the setting with '=' and ';' as '_'.
    std::string label() const;
};

struct SweepOptions {
    std::vector<SweepVariant> variants;  // method-major, as --methods lists them
    std::vector<int> samplesPerPixel;
    int repeats = 3;
    int convergedSamplesPerPixel = 0;  // 0: 16 x the largest of `samplesPerPixel`
    RenderOptions render;  // the converged image's: threads, filter (method and spp the sweep's)
    HardwareConfig hardware;
    SceneLimits limits;
    std::string outputDir;
    bool progress = true;
    // The files the sweep reads, (path, option): no output may overwrite one.
    std::vector<std::pair<std::string, std::string>> inputs;
};

struct SweepRow {
    std::string scene, method, setting;
    int spp = 0;
    double wallSeconds = 0, modelledCycles = 0;
    // With the memory system modelled: bytes to and from DRAM (the CSV leaves it empty without).
    std::optional<std::uint64_t> dramBytes;
    std::optional<double> dramRowHitRate;  // with DRAM banks modelled
    // The modelled energy (energy_model.h): arithmetic, and the memory system's when modelled.
    double energyNanojoules = 0;
    VisibilityTotals visibility;
    std::int64_t shadingInvocations = 0;
    double rmse = 0, psnr = 0, ssim = 1, coverageError = 0;
    // On its method's Pareto front for this scene and spp: no other setting of the method has
    // fewer or equal modelled cycles and error (RMSE), one of them fewer.
    bool front = true;
};

// Sets every row's `front` among the rows of its scene, spp and method.
void markParetoFronts(std::vector<SweepRow>& rows);

std::string sweepCsvHeader();
std::string sweepCsvRow(const SweepRow& row);

// Runs the sweep; writes OUT/results.csv, OUT/best.csv (the rows on their method's Pareto front),
// OUT/images, OUT/converged (the cache) and, with matplotlib, OUT/plots. Returns the rows. `log`
// receives one line per step worth telling.
std::vector<SweepRow> runSweep(const std::vector<SweepScene>& scenes, const SweepOptions& options,
                               std::ostream& log);

}  // namespace patchsim
