// The patchsim command: one binary, one subcommand per job (docs/ARCHITECTURE.md lists them).

#include <CLI/CLI.hpp>
#include <filesystem>
#include <iostream>

#include "pipeline/core/error.h"
#include "pipeline/core/scene_reader.h"
#include "pipeline/core/text_file.h"
#include "pipeline/driver/scene_info.h"
#include "pipeline/driver/stats_report.h"
#include "pipeline/driver/tessellation_export.h"

namespace {

using namespace patchsim;

struct CommonOptions {
    std::string scene;  // empty: the built-in default scene
    int threads = 0;
    std::uint64_t memoryBudgetMiB = 4096;
    EffectOverrides overrides;
};

SceneDesc loadScene(const CommonOptions& common) {
    SceneLimits limits;
    limits.memoryBudgetBytes = common.memoryBudgetMiB << 20;
    if (common.scene.empty()) return defaultScene();
    return readSceneOrCage(common.scene, limits);
}

void addCommonOptions(CLI::App& cmd, CommonOptions& common, bool effects) {
    cmd.add_option("scene", common.scene,
                   "Scene JSON file, or an OBJ cage to view alone (default: the built-in scene)");
    cmd.add_option("--threads", common.threads, "Worker threads (0: all cores)")
        ->check(CLI::NonNegativeNumber);
    cmd.add_option("--memory-budget-mib", common.memoryBudgetMiB,
                   "Largest film the scene may ask for, in MiB of per-sample state");
    if (effects) {
        cmd.add_flag("--no-motion", common.overrides.disableMotion, "Do not simulate motion blur");
        cmd.add_flag("--no-defocus", common.overrides.disableDefocus,
                     "Do not simulate defocus blur");
        cmd.add_flag("--no-transparency", common.overrides.disableTransparency,
                     "Treat every surface as opaque");
    }
}

void writeStats(const std::string& path, const StatsContext& context) {
    const CounterValues values = CounterRegistry::instance().snapshot();
    writeFileAtomically(path, [&](std::ostream& out) { writeStatsJson(out, context, values); });
}

int runInfo(const CommonOptions& common) {
    FrontEnd frontEnd(loadScene(common));
    const SceneInfo info = gatherSceneInfo(frontEnd, common.overrides, common.threads);
    printSceneInfo(std::cout, frontEnd, info);
    return 0;
}

int runTessellate(const CommonOptions& common, const std::string& output, float time,
                  const std::string& statsPath, bool quiet) {
    FrontEnd frontEnd(loadScene(common));
    TessellateOptions options;
    options.time = time;
    options.threads = common.threads;
    TessellationSummary summary;
    writeFileAtomically(
        output, [&](std::ostream& out) { summary = writeTessellationObj(frontEnd, options, out); });
    std::cout << "wrote " << output << ": " << summary.patches << " patches, " << summary.vertices
              << " vertices, " << summary.triangles << " triangles at t=" << time << "\n";
    StatsContext context{"tessellate", frontEnd.scene().path, {{"time", std::to_string(time)}}};
    if (!quiet) printCounterTable(std::cout, CounterRegistry::instance().snapshot());
    if (!statsPath.empty()) writeStats(statsPath, context);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{
        "patchsim: a cycle-approximate D3D11-style pipeline with a patch rasterizer for "
        "motion and defocus blur (US 8,791,945)"};
    app.require_subcommand(0, 1);

    CommonOptions infoOptions;
    CLI::App* info =
        app.add_subcommand("info", "Print a scene's patches, triangles, effects and mode");
    addCommonOptions(*info, infoOptions, /*effects=*/true);

    CommonOptions tessOptions;
    std::string tessOutput = "tessellation.obj", tessStats;
    float tessTime = 0.0f;
    bool tessQuiet = false;
    CLI::App* tess =
        app.add_subcommand("tessellate", "Run IA, VS, HS, TS and DS; write the mesh as OBJ");
    addCommonOptions(*tess, tessOptions, /*effects=*/false);
    tess->add_option("-o,--output", tessOutput, "Output OBJ file");
    tess->add_option("-t,--time", tessTime, "Shutter time of the written positions")
        ->check(CLI::Range(0.0f, 1.0f));
    tess->add_option("--stats", tessStats, "Also write the counters as stats JSON");
    tess->add_flag("-q,--quiet", tessQuiet, "Do not print the counter table");

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    }
    try {
        if (*info) return runInfo(infoOptions);
        if (*tess) return runTessellate(tessOptions, tessOutput, tessTime, tessStats, tessQuiet);
        // No subcommand: the main job on the built-in default scene.
        std::filesystem::create_directories("out");
        CommonOptions defaults;
        runInfo(defaults);
        return runTessellate(defaults, "out/default.obj", 0.5f, "out/stats.json", false);
    } catch (const InputError& e) {
        std::cerr << "patchsim: error: " << e.what() << "\n";
        return 2;
    } catch (const std::exception& e) {
        std::cerr << "patchsim: internal error: " << e.what() << "\n";
        return 3;
    }
}
