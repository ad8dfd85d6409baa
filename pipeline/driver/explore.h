#pragma once
// `patchsim explore`: design-space exploration. A grid file lists values for rasterizer options
// and hardware parameters; every point of their cross product, for every scene, becomes one CSV
// row with the options, the modelled cycles, the bottleneck and every counter. A scene is rendered
// once per rasterizer combination (its counted work does not depend on the hardware), and the
// timing model is then run for each hardware combination.
//
// Jobs (one render each) are numbered in a fixed order; rows come out in that order whether the
// jobs ran on one process or were spread over MPI ranks (docs/EXPLORE.md).

#include <functional>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "core/scene.h"
#include "core/scene_reader.h"
#include "pipeline/timing/hardware_config.h"

namespace patchsim {

struct GridAxis {
    std::string name;  // "tile_size", "RS.units", ...
    bool hardware = false;
    std::vector<std::string> values;   // as written in the CSV (numbers or names)
    std::vector<nlohmann::json> json;  // as given in the grid file
};

struct ExploreGrid {
    std::string path;  // the grid file, for messages
    std::vector<GridAxis> rasterAxes, hardwareAxes;
    // Optional film overrides so sweeps run at a chosen cost.
    int width = 0, height = 0, samplesPerPixel = 0;
};

// Throws InputError naming the file and field. Every value is checked here, by the rules the scene
// and hardware readers apply, so a bad value fails before any render, on every MPI rank alike.
ExploreGrid parseExploreGrid(std::string_view text, const std::string& path);

// The scene of one job: its rasterizer options and film from the grid. Throws InputError (naming
// the grid file) when the combination is refused or the film is over the memory budget.
SceneDesc jobScene(const std::vector<SceneDesc>& scenes, const ExploreGrid& grid,
                   const struct ExploreJob& job, const SceneLimits& limits);

struct ExploreJob {
    std::size_t scene = 0;
    std::vector<std::size_t> rasterChoice;  // index into each raster axis
};

// Throws InputError (the grid file, its field) if a hardware axis's value does not apply to the
// job's hardware: a memory field when the hardware models no memory, a line size the caches do
// not share. Called before any render.
void checkGridHardware(const ExploreGrid& grid, const HardwareConfig& hardware);

std::vector<ExploreJob> exploreJobs(std::size_t sceneCount, const ExploreGrid& grid);

// One point of the grid: which value of every axis (rasterizer axes, then hardware axes), its
// modelled cycles, and its CSV line (without newline).
struct ExploreRow {
    std::size_t job = 0;
    std::vector<std::size_t> choice;
    double totalCycles = 0;
    std::string csv;
};

// Renders one job and returns its rows (one per hardware combination).
std::vector<ExploreRow> runExploreJob(const std::vector<SceneDesc>& scenes, const ExploreGrid& grid,
                                      const HardwareConfig& baseHardware, std::size_t jobIndex,
                                      int threads, const SceneLimits& limits = {});

// Rows as text for MPI ranks to send, and back (not CSV: the fields are separated by a unit
// separator, so nothing is parsed out of the CSV).
std::string packExploreRows(const std::vector<ExploreRow>& rows);
std::vector<ExploreRow> unpackExploreRows(const std::string& text);

std::string exploreCsvHeader(const ExploreGrid& grid);

// Throws InputError("command line", "scenes", ...) when two of the scene arguments name one file
// (the same path, or two spellings of it): its rows would come out twice, as sweep refuses too.
void checkDistinctScenes(const std::vector<std::string>& paths);

// Checks the scenes are distinct (checkDistinctScenes) and every job (jobScene) first, then runs
// jobs [0, n) for which `mine(j)` is true, in order; `emit(j, rows)` receives each job's rows.
void runExploreJobs(const std::vector<SceneDesc>& scenes, const ExploreGrid& grid,
                    const HardwareConfig& baseHardware, int threads, const SceneLimits& limits,
                    const std::function<bool(std::size_t)>& mine,
                    const std::function<void(std::size_t, const std::vector<ExploreRow>&)>& emit);

}  // namespace patchsim
