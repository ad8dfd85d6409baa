// The patchsim command: one binary, one subcommand per job (docs/ARCHITECTURE.md lists them).

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "backend/heat_map.h"
#include "backend/image.h"
#include "pipeline/app/mpi_context.h"
#include "pipeline/core/error.h"
#include "pipeline/core/hardware_config.h"
#include "pipeline/core/output_set.h"
#include "pipeline/core/rasterizer_options.h"
#include "pipeline/core/scene_reader.h"
#include "pipeline/core/text_file.h"
#include "pipeline/driver/explore.h"
#include "pipeline/driver/plots.h"
#include "pipeline/driver/render.h"
#include "pipeline/driver/scene_info.h"
#include "pipeline/driver/stats_report.h"
#include "pipeline/driver/sweep.h"
#include "pipeline/driver/tessellation_export.h"
#include "rasterizer/tile_test_verifier.h"

namespace {

using namespace patchsim;

struct CommonOptions {
    std::string scene;  // empty: the built-in default scene
    int threads = 0;
    std::uint64_t memoryBudgetMiB = 4096;
    EffectOverrides overrides;
};

constexpr std::uint64_t kMaxMemoryBudgetMiB = std::uint64_t(1) << 30;  // 1 PiB

SceneLimits limitsOf(std::uint64_t budgetMiB) {
    SceneLimits limits;
    limits.memoryBudgetBytes = budgetMiB << 20;
    return limits;
}

SceneDesc loadScene(const CommonOptions& common) {
    const SceneLimits limits = limitsOf(common.memoryBudgetMiB);
    if (common.scene.empty()) return defaultScene(limits);
    return readSceneOrCage(common.scene, limits);
}

// 0 (all cores) or a positive count; CLI11's own check prints the largest double as the bound.
const CLI::Validator kThreadCount(
    [](std::string& text) -> std::string {
        try {
            std::size_t used = 0;
            const long n = std::stol(text, &used);
            if (used == text.size() && n >= 0 && n <= 4096) return {};
        } catch (const std::exception&) {
        }
        return "must be 0 (all cores) or a number of threads up to 4096, not '" + text + "'";
    },
    "0..4096", "thread count");

const CLI::Validator kBudgetMiB = CLI::Range(std::uint64_t(1), kMaxMemoryBudgetMiB);

void addCommonOptions(CLI::App& cmd, CommonOptions& common, bool effects) {
    cmd.add_option("scene", common.scene,
                   "Scene JSON file, or an OBJ cage to view alone (default: the built-in scene)");
    cmd.add_option("--threads", common.threads, "Worker threads (0: all cores)")
        ->check(kThreadCount);
    cmd.add_option("--memory-budget-mib", common.memoryBudgetMiB,
                   "MiB the film's samples and the rasterizer's tile scratch may take")
        ->check(kBudgetMiB);
    if (effects) {
        cmd.add_flag("--no-motion", common.overrides.disableMotion, "Do not simulate motion blur");
        cmd.add_flag("--no-defocus", common.overrides.disableDefocus,
                     "Do not simulate defocus blur");
        cmd.add_flag("--no-transparency", common.overrides.disableTransparency,
                     "Treat every surface as opaque");
    }
}

void writeStats(OutputSet& outputs, const std::string& path, const std::string& field,
                const StatsContext& context) {
    const CounterValues values = CounterRegistry::instance().snapshot();
    outputs.writeText(path, field,
                      [&](std::ostream& out) { writeStatsJson(out, context, values); });
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
    OutputSet outputs;
    outputs.file(output, "-o");  // checked before the work
    if (!statsPath.empty()) outputs.file(statsPath, "--stats");
    TessellateOptions options;
    options.time = time;
    options.threads = common.threads;
    TessellationSummary summary;
    outputs.writeText(output, "-o", [&](std::ostream& out) {
        summary = writeTessellationObj(frontEnd, options, out);
    });
    StatsContext context{"tessellate", frontEnd.scene().path, {{"time", std::to_string(time)}}};
    if (!statsPath.empty()) writeStats(outputs, statsPath, "--stats", context);
    outputs.commit();
    std::cout << "wrote " << output << ": " << summary.patches << " patches, " << summary.vertices
              << " vertices, " << summary.triangles << " triangles at t=" << time << "\n";
    if (!quiet) printCounterTable(std::cout, CounterRegistry::instance().snapshot());
    return 0;
}

// The postprocess method's filter (backend/motion_blur_postprocess.h), for render and sweep.
void addPostprocessOptions(CLI::App& cmd, PostprocessOptions& p, float& edgeThreshold,
                           ReprojectionOptions& reprojection, TFragmentOptions& tfragment) {
    cmd.add_option("--pp-tile-size", p.tileSize,
                   "postprocess: TileMax tile size k in pixels (velocities are clamped to it)")
        ->check(CLI::Range(1, 1024))
        ->capture_default_str();
    cmd.add_option("--pp-samples", p.samples, "postprocess: samples gathered per pixel (odd)")
        ->check(CLI::Range(3, 255))
        ->capture_default_str();
    cmd.add_option("--soft-z-extent", p.softZExtent,
                   "postprocess: SOFT_Z_EXTENT, the depth over which samples blend from in front "
                   "to behind (scene units)")
        ->check(CLI::Range(1e-6f, 1e6f))
        ->capture_default_str();
    cmd.add_option("--edge-threshold", edgeThreshold,
                   "hybrid: Sobel edge threshold e of the ray mask, in [0, 1)")
        ->check(CLI::Range(0.0f, 0.999f))
        ->capture_default_str();
    cmd.add_option("--camera-steps", reprojection.cameraSteps,
                   "reprojection: interpolated cameras per reprojection cycle")
        ->check(CLI::Range(2, 1024))
        ->capture_default_str();
    cmd.add_option("--motion-samples", tfragment.motionSamples,
                   "tfragment: time samples per lens ray (the paper's 4 and 32)")
        ->check(CLI::Range(1, 256))
        ->capture_default_str();
}

struct RenderCommand {
    CommonOptions common;
    std::string outputDir = "out";
    std::string method = "patch";
    int timeStrata = 4;
    PostprocessOptions postprocess;
    float edgeThreshold = HybridOptions{}.edgeThreshold;
    ReprojectionOptions reprojection;
    TFragmentOptions tfragment;
    bool timeSampled = false;
    // Rasterizer options given on the command line override the scene's, by their table key.
    std::map<std::string, std::string> rasterizer;
    bool noTimeRefinement = false, noZCulling = false, quiet = false;
    std::string filter = "box", shadingRate = "per-fragment";
    int maxLayers = 16;
    bool heatMaps = false, noProgress = false;
    std::string hardware, trace;
};

void addRenderOptions(CLI::App& cmd, RenderCommand& r) {
    addCommonOptions(cmd, r.common, /*effects=*/true);
    cmd.add_option("-o,--output", r.outputDir,
                   "Output folder for image.exr, image.png, stats.json");
    std::vector<std::string> methods;
    for (const VisibilityMethodInfo& m : visibilityMethods()) methods.push_back(m.name);
    cmd.add_option("--method", r.method, "Visibility method: " + visibilityMethodNames())
        ->check(CLI::IsMember(methods));
    cmd.add_option("--time-strata", r.timeStrata, "Time strata of the interval method")
        ->check(CLI::Range(1, 64));
    addPostprocessOptions(cmd, r.postprocess, r.edgeThreshold, r.reprojection, r.tfragment);
    cmd.add_flag("--time-sampled", r.timeSampled,
                 "tfragment: trace once per motion sample instead of once per lens ray (the "
                 "paper's comparison)");
    for (const RasterizerOptionField& field : rasterizerOptionFields()) {
        cmd.add_option_function<std::string>(
            field.flag, [&r, key = field.key](const std::string& v) { r.rasterizer[key] = v; },
            field.help);
    }
    cmd.add_flag("--no-time-refinement", r.noTimeRefinement, "Same as --time-refinement false");
    cmd.add_flag("--no-z-culling", r.noZCulling, "Same as --z-culling false");
    cmd.add_flag("-q,--quiet", r.quiet, "Do not print the counter table");
    cmd.add_option("--filter", r.filter, "Resolve filter")
        ->check(CLI::IsMember({"box", "gaussian"}));
    cmd.add_option("--shading-rate", r.shadingRate,
                   "per-fragment (every t-fragment) or per-pixel-primitive (MSAA-style reuse)")
        ->check(CLI::IsMember({"per-fragment", "per-pixel-primitive"}));
    cmd.add_option("--max-layers", r.maxLayers, "Transparent t-fragments kept per sample")
        ->check(CLI::Range(1, 255));
    cmd.add_flag("--heatmaps", r.heatMaps,
                 "Also write per-pixel and per-tile heat maps of the rasterizer's work");
    cmd.add_flag("--no-progress", r.noProgress, "No progress bar");
    cmd.add_option(
        "--hw", r.hardware,
        "Hardware configuration JSON for the timing model (default: pipeline/hw/default.json)");
    cmd.add_option("--trace", r.trace, "Write the per-patch timeline as Chrome trace-event JSON");
}

int runRender(const RenderCommand& r, const MpiContext& mpi) {
    SceneDesc scene = loadScene(r.common);
    RasterizerOptions& o = scene.rasterizer;
    std::map<std::string, std::string> given = r.rasterizer;
    if (r.noTimeRefinement) given["time_refinement"] = "false";
    if (r.noZCulling) given["z_culling"] = "false";
    for (const auto& [key, text] : given) {
        const RasterizerOptionField& field = *findRasterizerOptionField(key);
        const std::string error = field.set(o, optionValueFromText(text));
        if (!error.empty()) throw InputError("command line", field.flag, error);
    }
    o.validate("command line");
    RenderOptions options;
    parseVisibilityMethod(r.method, options.method);  // CLI11 checked the name
    options.timeStrata = r.timeStrata;
    options.postprocess = r.postprocess;
    options.edgeThreshold = r.edgeThreshold;
    options.reprojection = r.reprojection;
    options.tfragment = r.tfragment;
    options.tfragmentTimeSampled = r.timeSampled;
    options.overrides = r.common.overrides;
    options.threads = mpi.threadsPerRank(r.common.threads);
    options.memoryBudgetBytes = limitsOf(r.common.memoryBudgetMiB).memoryBudgetBytes;
    options.maxLayers = r.maxLayers;
    options.resolve.filter = r.filter == "gaussian" ? ResolveFilter::Gaussian : ResolveFilter::Box;
    options.resolve.shadingRate = r.shadingRate == "per-pixel-primitive"
                                      ? ShadingRate::PerPixelPrimitive
                                      : ShadingRate::PerFragment;
    options.heatMaps = r.heatMaps;
    options.progress = !r.noProgress;
    const HardwareConfig hardware =
        r.hardware.empty() ? defaultHardwareConfig() : readHardwareConfig(r.hardware);
    // Every output path is checked before the work; nothing is written unless all succeed. Under
    // mpirun the frame is split across ranks by screen tiles and rank 0 writes the one output.
    OutputSet outputs;
    const std::string exr = r.outputDir + "/image.exr", png = r.outputDir + "/image.png",
                      stats = r.outputDir + "/stats.json";
    std::exception_ptr outputError;
    if (mpi.rank() == 0) {
        try {
            outputs.folder(r.outputDir, "-o");
            for (const std::string& file : {exr, png, stats}) outputs.file(file, "-o");
            if (!r.trace.empty()) outputs.file(r.trace, "--trace");
        } catch (const InputError&) {
            outputError = std::current_exception();
        }
    }
    if (!mpi.allSucceeded(outputError == nullptr)) {
        if (outputError) std::rethrow_exception(outputError);
        return 2;  // rank 0 refused the outputs and said why
    }
    if (mpi.active()) {
        options.share = {mpi.rank(), mpi.size(),
                         [&mpi](const std::string& mine) { return mpi.gather(mine); },
                         [&mpi] { return mpi.makeProgressShare(); }};
        options.progress = options.progress && mpi.rank() == 0;
    }
    CounterRegistry::instance().reset();
    const RenderResult result = renderScene(scene, options);
    if (!result.complete) return 0;  // another rank writes the frame
    for (const std::string& note : result.notes) std::cerr << "patchsim: " << note << "\n";
    const TimingReport timing = simulateTiming(result.patchOps, hardware);
    const CounterValues counters = CounterRegistry::instance().snapshot();
    writeExrWithAovs(result.frame, outputs.file(exr, "-o"));
    writePng(result.frame.color, outputs.file(png, "-o"));
    std::vector<std::string> heatMaps;
    if (result.pixels) heatMaps = writeHeatMaps(*result.pixels, r.outputDir, outputs);
    const double ste = counters.ratio(sampleTestEfficiencyOf(options.method));
    StatsContext context{"render", scene.path, {}, &timing};
    context.facts = {{"method", visibilityMethodName(options.method)},
                     {"mode", describeMode(result.effects)},
                     {"width", std::to_string(scene.film.width)},
                     {"height", std::to_string(scene.film.height)},
                     {"spp", std::to_string(scene.film.samplesPerPixel)},
                     {"patches", std::to_string(result.patches)},
                     {"triangles", std::to_string(result.triangles)},
                     {"sample test efficiency", std::to_string(ste)},
                     {"shading rate", shadingRateName(options.resolve.shadingRate)},
                     {"shading reuse rate", std::to_string(shadingReuseRate(counters))},
                     {"filter", resolveFilterName(options.resolve.filter)},
                     {"max layers", std::to_string(options.maxLayers)},
                     {"tile size", std::to_string(o.tileSize)},
                     {"leaf size", std::to_string(o.leafSize)},
                     {"branch method", branchMethodName(o.branchMethod)},
                     {"bounds space", boundsSpaceName(o.boundsSpace)},
                     {"merge triangles below", std::to_string(o.mergeTrianglesBelow)},
                     {"time refinement", !o.timeRefinement          ? "off"
                                         : o.interiorTimeRefinement ? "every level"
                                                                    : "leaves"},
                     {"z culling", o.zCulling ? "on" : "off"}};
    context.facts.push_back(
        {"hardware", r.hardware.empty() ? "builtin:hw/default.json" : r.hardware});
    writeStats(outputs, stats, "-o", context);
    if (!r.trace.empty())
        outputs.writeText(r.trace, "--trace",
                          [&](std::ostream& out) { writeChromeTrace(timing, out); });
    outputs.commit();
    if (!r.quiet) printCounterTable(std::cout, counters);
    if (mpi.active())
        std::cout << "split across " << mpi.size() << " MPI ranks by tile-row classes\n";
    printTimingReport(timing, std::cout);
    std::cout << "rendered " << scene.path << " (" << describeMode(result.effects) << ") with the "
              << visibilityMethodName(options.method) << " method: " << result.patches
              << " patches, " << result.triangles << " triangles; front end "
              << result.frontEndSeconds << " s, visibility " << result.visibilitySeconds
              << " s, shading " << result.shadingSeconds << " s; STE " << ste << "\nwrote "
              << r.outputDir
              << "/image.exr (R G B Z coverage motion.x motion.y), image.png, stats.json";
    if (!heatMaps.empty()) std::cout << " and " << heatMaps.size() << " heat maps";
    std::cout << "\n";
    return 0;
}

struct ExploreCommand {
    std::vector<std::string> scenes;
    std::string grid, output = "explore.csv", plots, hardware;
    int threads = 0;
    std::uint64_t memoryBudgetMiB = 4096;
};

int runExplore(const ExploreCommand& e, const MpiContext& mpi) {
    const SceneLimits limits = limitsOf(e.memoryBudgetMiB);
    std::vector<SceneDesc> scenes;
    for (const std::string& s : e.scenes) scenes.push_back(readSceneOrCage(s, limits));
    if (scenes.empty()) scenes.push_back(defaultScene(limits));
    const ExploreGrid grid = parseExploreGrid(readTextFile(e.grid), e.grid);
    const HardwareConfig hardware =
        e.hardware.empty() ? defaultHardwareConfig() : readHardwareConfig(e.hardware);
    OutputSet outputs;  // only rank 0 writes; every rank checks the paths alike
    // The plots' folder first: it may be the CSV's too, made by this command.
    const PlotJob plots{"explore", e.output, e.plots};
    if (!e.plots.empty()) addPlotScript(outputs, plots, "--plots");
    outputs.file(e.output, "-o");
    const std::size_t jobs = exploreJobs(scenes.size(), grid).size();
    // Jobs are dealt round-robin over ranks; each rank tags its rows with the job number. A job
    // that fails on one rank must not leave the others waiting: every rank reports, then all stop.
    std::vector<ExploreRow> mine;
    std::exception_ptr failure;
    try {
        runExploreJobs(
            scenes, grid, hardware, mpi.threadsPerRank(e.threads), limits,
            [&](std::size_t j) { return int(j % std::size_t(mpi.size())) == mpi.rank(); },
            [&](std::size_t j, const std::vector<ExploreRow>& rows) {
                mine.insert(mine.end(), rows.begin(), rows.end());
                if (mpi.rank() == 0)
                    std::cerr << "explore: job " << j + 1 << " of " << jobs << " done\n";
            });
    } catch (const InputError&) {
        failure = std::current_exception();
    }
    if (!mpi.allSucceeded(failure == nullptr)) {
        if (failure) std::rethrow_exception(failure);
        return 2;  // another rank failed and printed why
    }
    const std::vector<std::string> parts = mpi.gather(packExploreRows(mine));
    if (mpi.rank() != 0) return 0;
    std::vector<ExploreRow> rows;
    for (const std::string& part : parts) {
        const std::vector<ExploreRow> theirs = unpackExploreRows(part);
        rows.insert(rows.end(), theirs.begin(), theirs.end());
    }
    std::stable_sort(rows.begin(), rows.end(),
                     [](const ExploreRow& a, const ExploreRow& b) { return a.job < b.job; });
    std::string csv = exploreCsvHeader(grid) + "\n";
    for (const ExploreRow& row : rows) csv += row.csv + "\n";
    outputs.writeText(e.output, "-o", [&](std::ostream& out) { out << csv; });
    outputs.commit();
    std::cout << "wrote " << e.output << ": " << rows.size() << " points (" << jobs << " renders"
              << (mpi.active() ? " over " + std::to_string(mpi.size()) + " MPI ranks"
                               : std::string())
              << ")\n";
    if (!e.plots.empty()) drawPlots(plots, std::cout);
    return 0;
}

struct SweepCommand {
    std::vector<std::string> scenes;
    std::string methods =
                    "patch,triangle-bbox,interval,interleaved,postprocess,hybrid,reprojection,"
                    "tfragment",
                spp = "1,4,16,64", blur = "1", output = "sweep", hardware;
    int repeats = 3, convergedSpp = 0, threads = 0, timeStrata = 4;
    PostprocessOptions postprocess;
    float edgeThreshold = HybridOptions{}.edgeThreshold;
    ReprojectionOptions reprojection;
    TFragmentOptions tfragment;
    std::uint64_t memoryBudgetMiB = 4096;
    bool noProgress = false;
};

std::vector<std::string> splitList(const std::string& text) {
    std::vector<std::string> items;
    std::stringstream in(text);
    for (std::string item; std::getline(in, item, ',');)
        if (!item.empty()) items.push_back(item);
    return items;
}

int runSweepCommand(const SweepCommand& c) {
    SweepOptions o;
    for (const std::string& name : splitList(c.methods)) {
        VisibilityMethod m;
        if (!parseVisibilityMethod(name, m))
            throw InputError("command line", "--methods",
                             "unknown method '" + name + "' (" + visibilityMethodNames() + ")");
        o.methods.push_back(m);
    }
    for (const std::string& text : splitList(c.spp)) {
        const nlohmann::json v = optionValueFromText(text);
        if (!v.is_number_integer() || v.get<std::int64_t>() < 1 || v.get<std::int64_t>() > 4096)
            throw InputError("command line", "--spp",
                             "'" + text + "' is not a whole number in [1, 4096]");
        o.samplesPerPixel.push_back(int(v.get<std::int64_t>()));
    }
    std::vector<float> blurs;
    for (const std::string& text : splitList(c.blur)) {
        const nlohmann::json v = optionValueFromText(text);
        if (!v.is_number() || !(v.get<double>() > 0) || v.get<double>() > 1e3)
            throw InputError("command line", "--blur",
                             "'" + text + "' is not a scale in (0, 1000]");
        blurs.push_back(float(v.get<double>()));
    }
    if (o.methods.empty() || o.samplesPerPixel.empty() || blurs.empty())
        throw InputError("command line", "--methods/--spp/--blur", "needs at least one value");
    o.repeats = c.repeats;
    o.convergedSamplesPerPixel = c.convergedSpp;
    o.render.threads = c.threads;
    o.render.timeStrata = c.timeStrata;
    o.render.postprocess = c.postprocess;
    o.render.edgeThreshold = c.edgeThreshold;
    o.render.reprojection = c.reprojection;
    o.render.tfragment = c.tfragment;
    o.hardware = c.hardware.empty() ? defaultHardwareConfig() : readHardwareConfig(c.hardware);
    o.limits = limitsOf(c.memoryBudgetMiB);
    o.render.memoryBudgetBytes = o.limits.memoryBudgetBytes;
    o.outputDir = c.output;
    o.progress = !c.noProgress;
    std::vector<SweepScene> scenes;
    std::vector<std::string> paths = c.scenes;
    if (paths.empty()) paths.push_back("");
    for (const std::string& path : paths) {
        const SceneDesc scene =
            path.empty() ? defaultScene(o.limits) : readSceneOrCage(path, o.limits);
        const std::string stem =
            path.empty() ? "default" : std::filesystem::path(path).stem().string();
        for (float blur : blurs) {
            char suffix[32] = "";
            if (blur != 1.0f) std::snprintf(suffix, sizeof suffix, "-blur%g", double(blur));
            scenes.push_back({stem + suffix, blur == 1.0f ? scene : scaleBlur(scene, blur)});
        }
    }
    runSweep(scenes, o, std::cout);
    return 0;
}

struct VerifyCommand {
    std::int64_t cases = 2000;
    std::uint64_t seed = 1;
    int threads = 0;
    int witnessEvery = 64;
    std::string csv, summary, replay;
};

void writeVerifySummary(const TileVerifierResult& result, std::ostream& out) {
    out << "variant,model,cases,true_hits,true_misses,false_rejects,false_accepts,"
           "false_accept_percent,excess_median,excess_p90,excess_p95,excess_p99,excess_unit\n";
    for (const TileTestReport& r : result.reports) {
        char line[512];
        std::snprintf(
            line, sizeof line, "%s,%s,%lld,%lld,%lld,%lld,%lld,%.4f,%.4g,%.4g,%.4g,%.4g,%s\n",
            r.name.c_str(), caseModelName(r.model), static_cast<long long>(r.cases),
            static_cast<long long>(r.trueHits), static_cast<long long>(r.trueMisses),
            static_cast<long long>(r.falseRejects), static_cast<long long>(r.falseAccepts),
            r.falseAcceptPercent(), r.excess.quantile(0.5), r.excess.quantile(0.9),
            r.excess.quantile(0.95), r.excess.quantile(0.99), r.excessUnit);
        out << line;
    }
}

int runVerifyTiles(const VerifyCommand& c) {
    if (!c.replay.empty()) {
        if (!replayTileCase(c.replay, c.seed, std::cout))
            throw InputError(
                "command line", "--replay",
                "'" + c.replay + "' is not a case name (pinhole:N, lens:N or hierarchy:N)");
        return 0;
    }
    TileVerifierOptions o;
    o.cases = c.cases;
    o.seed = c.seed;
    o.threads = c.threads;
    o.witnessEvery = c.witnessEvery;
    OutputSet outputs;
    std::ofstream csv;
    if (!c.csv.empty()) {
        // Streamed into the reserved temporary: a million cases are too many rows to hold.
        csv.open(outputs.file(c.csv, "--csv"));
        if (!csv) throw InputError(c.csv, "--csv", "cannot write the file");
        o.csv = &csv;
    }
    const TileVerifierResult result = verifyTileTests(o);
    if (csv.is_open()) {
        csv.close();
        if (!csv) throw InputError(c.csv, "--csv", "writing the file failed");
    }
    if (!c.summary.empty())
        outputs.writeText(c.summary, "--summary",
                          [&](std::ostream& out) { writeVerifySummary(result, out); });
    for (const TileTestReport& r : result.reports) {
        char line[512], excess[128] = "excess -";
        if (r.excess.count > 0)
            std::snprintf(excess, sizeof excess, "excess median %.3g, p95 %.3g %s",
                          r.excess.quantile(0.5), r.excess.quantile(0.95), r.excessUnit);
        std::snprintf(line, sizeof line,
                      "%s (%s): cases %lld, false rejects %lld, false accepts %lld of %lld misses "
                      "(%.2f%%), %s",
                      r.name.c_str(), caseModelName(r.model), static_cast<long long>(r.cases),
                      static_cast<long long>(r.falseRejects),
                      static_cast<long long>(r.falseAccepts), static_cast<long long>(r.trueMisses),
                      r.falseAcceptPercent(), excess);
        std::cout << line << "\n";
        if (r.falseRejects > 0)
            std::cout << "  first false reject: patchsim verify-tiles --seed " << c.seed
                      << " --replay " << r.firstFailure << "\n";
    }
    std::cout << "witness: " << result.witnessCases << " cases sampled, " << result.witnessHits
              << " sampled hits, " << result.witnessOutsideTruth << " outside the exact truth\n";
    outputs.commit();
    return result.anyFalseReject() ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv) {
    const MpiContext mpi(argc, argv);
    CLI::App app{
        "patchsim: a cycle-approximate D3D11-style pipeline with a patch rasterizer for "
        "motion and defocus blur (US 8,791,945)"};
    app.require_subcommand(0, 1);
    app.footer(
        "With no subcommand, patchsim renders the built-in default scene (motion blur and "
        "defocus) into out/ (out/image.exr, out/image.png, out/stats.json), as "
        "`patchsim render -o out` would.");

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

    RenderCommand renderOptions;
    CLI::App* render =
        app.add_subcommand("render", "Render a frame: image.exr, image.png and stats.json");
    addRenderOptions(*render, renderOptions);

    VerifyCommand verifyOptions;
    CLI::App* verify = app.add_subcommand(
        "verify-tiles", "Check the tile tests against exact ground truth (docs/TILE_TESTS.md)");
    verify->add_option("--cases", verifyOptions.cases, "Random cases per model")
        ->check(CLI::Range(std::int64_t(1), std::int64_t(1) << 40))
        ->capture_default_str();
    verify->add_option("--seed", verifyOptions.seed, "Seed of the random cases")
        ->capture_default_str();
    verify->add_option("--threads", verifyOptions.threads, "Worker threads (0: all cores)")
        ->check(kThreadCount);
    verify
        ->add_option("--witness-every", verifyOptions.witnessEvery,
                     "Check the exact truth with sampled rays on every Nth case (0: never)")
        ->check(CLI::Range(0, 1 << 30))
        ->capture_default_str();
    verify->add_option("--csv", verifyOptions.csv, "Write one row per case and variant");
    verify->add_option("--summary", verifyOptions.summary,
                       "Write one row per variant (for scripts/plot_tile_tests.py)");
    verify->add_option("--replay", verifyOptions.replay,
                       "Print one case (e.g. lens:1234) in full and every variant's answer");

    SweepCommand sweepOptions;
    CLI::App* sweep = app.add_subcommand(
        "sweep", "Accuracy against time: every method at every sample count (docs/ACCURACY.md)");
    sweep->add_option("scenes", sweepOptions.scenes,
                      "Scene JSON files or cages (default: the built-in scene)");
    sweep
        ->add_option("--methods", sweepOptions.methods,
                     "Comma-separated methods: " + visibilityMethodNames())
        ->capture_default_str();
    sweep->add_option("--spp", sweepOptions.spp, "Comma-separated samples per pixel")
        ->capture_default_str();
    sweep
        ->add_option("--blur", sweepOptions.blur,
                     "Comma-separated scales of every scene's motion and aperture")
        ->capture_default_str();
    sweep
        ->add_option("-o,--output", sweepOptions.output,
                     "Folder for results.csv, images/, plots/ and the converged cache")
        ->capture_default_str();
    sweep->add_option("--repeats", sweepOptions.repeats, "Renders per run; the median time counts")
        ->check(CLI::Range(1, 100))
        ->capture_default_str();
    sweep
        ->add_option("--converged-spp", sweepOptions.convergedSpp,
                     "Samples per pixel of the converged image (0: 16 x the largest --spp)")
        ->check(CLI::Range(0, 1 << 20));
    sweep->add_option("--time-strata", sweepOptions.timeStrata, "K of the interval method")
        ->check(CLI::Range(1, 64));
    addPostprocessOptions(*sweep, sweepOptions.postprocess, sweepOptions.edgeThreshold,
                          sweepOptions.reprojection, sweepOptions.tfragment);
    sweep->add_option("--threads", sweepOptions.threads, "Worker threads (0: all cores)")
        ->check(kThreadCount);
    sweep->add_option("--hw", sweepOptions.hardware, "Hardware configuration for modelled cycles");
    sweep
        ->add_option("--memory-budget-mib", sweepOptions.memoryBudgetMiB,
                     "MiB a run's film samples and tile scratch may take")
        ->check(kBudgetMiB);
    sweep->add_flag("--no-progress", sweepOptions.noProgress, "No progress bar");

    ExploreCommand exploreOptions;
    CLI::App* explore =
        app.add_subcommand("explore", "Design-space sweep: one CSV row per grid point");
    explore->add_option("scenes", exploreOptions.scenes,
                        "Scene JSON files (default: the built-in scene)");
    explore->add_option("--grid", exploreOptions.grid, "Grid file (docs/EXPLORE.md)")->required();
    explore->add_option("-o,--output", exploreOptions.output, "CSV file to write");
    explore->add_option("--plots", exploreOptions.plots,
                        "Folder for the plots (PNG and SVG: cycles against each parameter, "
                        "heat maps of each pair)");
    explore->add_option("--hw", exploreOptions.hardware, "Base hardware configuration");
    explore
        ->add_option("--threads", exploreOptions.threads,
                     "Worker threads per render (0: all cores, or under mpirun this rank's share)")
        ->check(kThreadCount);
    explore
        ->add_option("--memory-budget-mib", exploreOptions.memoryBudgetMiB,
                     "MiB a grid point's film samples and tile scratch may take")
        ->check(kBudgetMiB);

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        // CLI11 prints the help, or the error with a hint; a bad command line is bad input, so it
        // exits 2 like a bad file (CLI11's own codes are 1xx).
        return app.exit(e) == 0 ? 0 : 2;
    }
    try {
        if (*info) return runInfo(infoOptions);
        if (*tess) return runTessellate(tessOptions, tessOutput, tessTime, tessStats, tessQuiet);
        if (*render) return runRender(renderOptions, mpi);
        if (*verify) return runVerifyTiles(verifyOptions);
        if (*explore) return runExplore(exploreOptions, mpi);
        if (*sweep) return runSweepCommand(sweepOptions);
        // No subcommand: the main job, a render of the built-in default scene into out/.
        const RenderCommand defaults;
        return runRender(defaults, mpi);
    } catch (const InputError& e) {
        std::cerr << "patchsim: error: " << e.what() << "\n";
        return 2;
    } catch (const std::exception& e) {
        std::cerr << "patchsim: internal error: " << e.what() << "\n";
        return 3;
    }
}
