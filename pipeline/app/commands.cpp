#include "pipeline/app/commands.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <future>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "backend/images/heat_map.h"
#include "backend/images/image.h"
#include "backend/images/image_io_module.h"
#include "core/effects.h"
#include "core/error.h"
#include "core/memory_trace.h"
#include "core/output_set.h"
#include "core/parallel.h"
#include "core/rasterizer_options.h"
#include "core/text_file.h"
#include "pipeline/driver/explore.h"
#include "pipeline/driver/plots.h"
#include "pipeline/driver/render.h"
#include "pipeline/driver/scene_info.h"
#include "pipeline/driver/stats_report.h"
#include "pipeline/driver/sweep.h"
#include "pipeline/driver/tessellation_export.h"
#include "pipeline/methods/visibility_method.h"
#include "pipeline/timing/hardware_config.h"
#include "rasterizer/verifier/tile_test_verifier.h"

namespace patchsim {

namespace {

// Reads a file named on the command line; an error about the file itself (it cannot be opened, is
// not a regular file) names the option it came from.
template <class Read>
auto readNamedFile(const std::string& path, const char* option, Read read) {
    try {
        return read(path);
    } catch (const InputError& e) {
        if (e.file() != path || !e.field().empty()) throw;
        const std::string what = e.what(), prefix = path + ": ";
        throw InputError(path, option,
                         what.rfind(prefix, 0) == 0 ? what.substr(prefix.size()) : what);
    }
}

SceneDesc readScene(const std::string& path, const SceneLimits& limits) {
    return readNamedFile(path, "scene",
                         [&](const std::string& p) { return readSceneOrCage(p, limits); });
}

EffectOverrides overridesOf(const JobSettings& s) {
    EffectOverrides o;
    o.disableMotion = s.noMotion;
    o.disableDefocus = s.noDefocus;
    o.disableTransparency = s.noTransparency;
    return o;
}

// Scenes are read without a film budget: the film a command renders is checked where it is
// known (render after --spp/--width/--height; sweep at every --spp; explore at every grid film).
// info and tessellate render no film.
SceneLimits unlimited() {
    SceneLimits l;
    l.memoryBudgetBytes = ~std::uint64_t(0);
    return l;
}

// The one scene of info, tessellate and render: the built-in one when none is named.
SceneDesc loadScene(const JobSettings& s) {
    if (s.scenes.empty()) return defaultScene(unlimited());
    return readScene(s.scenes.front(), unlimited());
}

HardwareConfig hardwareOf(const JobSettings& s) {
    if (s.hardware.empty()) return defaultHardwareConfig();
    return readNamedFile(s.hardware, "--hw",
                         [](const std::string& p) { return readHardwareConfig(p); });
}

// Everything of a render that the options choose, other than the method (sweep sets its own).
RenderOptions renderOptionsOf(const JobSettings& s) {
    RenderOptions o;
    o.method = &methodNamed(s.method);  // checked against the method table
    o.overrides = overridesOf(s);
    o.threads = s.threads;
    o.memoryBudgetBytes = s.limits().memoryBudgetBytes;
    o.maxLayers = s.maxLayers;
    o.timeStrata = s.timeStrata;
    parseTriangleBound(s.bboxBound, o.triangleBound);  // checked against the option's list
    o.postprocess.tileSize = s.ppTileSize;
    o.postprocess.samples = s.ppSamples;
    o.postprocess.softZExtent = s.softZExtent;
    o.edgeThreshold = s.edgeThreshold;
    o.reprojection.cameraSteps = s.cameraSteps;
    o.tfragment.motionSamples = s.motionSamples;
    o.tfragment.maxCollected = s.tfragmentLimit;
    o.tfragmentTimeSampled = s.timeSampled;
    o.resolve.filter = s.filter == "gaussian" ? ResolveFilter::Gaussian : ResolveFilter::Box;
    o.resolve.shadingRate = s.shadingRate == "per-pixel-primitive" ? ShadingRate::PerPixelPrimitive
                                                                   : ShadingRate::PerFragment;
    o.heatMaps = s.heatMaps;
    o.progress = !s.noProgress;
    return o;
}

// The options stats.json records: every row of this command that names a key, then the scene's
// rasterizer options as rendered.
std::vector<std::pair<std::string, std::string>> recordedOptions(Command command,
                                                                 const JobSettings& s,
                                                                 const RasterizerOptions* raster) {
    std::vector<std::pair<std::string, std::string>> out;
    for (const JobOption& o : jobOptions())
        if (o.takes(command) && o.statsKey) out.emplace_back(o.statsKey, jobOptionValue(o, s));
    if (raster)
        for (const RasterizerOptionField& f : rasterizerOptionFields())
            out.emplace_back(std::string("rasterizer.") + f.key, f.get(*raster));
    return out;
}

void writeStats(OutputSet& outputs, const std::string& path, const std::string& field,
                const StatsContext& context) {
    const CounterValues values = CounterRegistry::instance().snapshot();
    outputs.writeText(path, field,
                      [&](std::ostream& out) { writeStatsJson(out, context, values); });
}

// The scene's rasterizer and film with the command line's options applied.
void applyRenderOverrides(const JobSettings& s, SceneDesc& scene) {
    RasterizerOptions& o = scene.rasterizer;
    std::map<std::string, std::string> given = s.rasterizer;
    if (s.noTimeRefinement) given["time_refinement"] = "false";
    if (s.noZCulling) given["z_culling"] = "false";
    for (const auto& [key, text] : given) {
        const RasterizerOptionField& field = *findRasterizerOptionField(key);
        const std::string error = field.set(o, optionValueFromText(text));
        if (!error.empty()) throw InputError("command line", field.flag, error);
    }
    o.validate("command line");
    if (s.spp > 0) scene.film.samplesPerPixel = s.spp;
    if (s.width > 0) scene.film.width = s.width;
    if (s.height > 0) scene.film.height = s.height;
    if (s.spp > 0 || s.width > 0 || s.height > 0) {
        const char* field = s.spp > 0 ? "--spp" : s.width > 0 ? "--width" : "--height";
        checkMemoryBudget(scene.film, s.limits(), "command line", field);
    } else {
        checkMemoryBudget(scene.film, s.limits(), scene.path);
    }
}

std::vector<std::pair<std::string, std::string>> renderFacts(
    const SceneDesc& scene, const RenderOptions& options, const RenderResult& result,
    const CounterValues& counters, double ste, const std::string& hardware) {
    const RasterizerOptions& o = scene.rasterizer;
    return {{"method", options.visibilityMethod().name()},
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
            {"z culling", o.zCulling ? "on" : "off"},
            {"hardware", hardware.empty() ? "builtin:hw/default.json" : hardware}};
}

// The files a command reads, so that no output of its may overwrite one of them.
void protectInputs(OutputSet& outputs, const JobSettings& s,
                   const std::vector<const SceneDesc*>& scenes) {
    for (const SceneDesc* scene : scenes) {
        outputs.input(scene->path, "scene");
        for (std::size_t i = 0; i < scene->objects.size(); ++i) {
            const ObjectDesc& o = scene->objects[i];
            const std::string field = "objects[" + std::to_string(i) + "]";
            outputs.input(o.cagePath, field + ".cage");
            outputs.input(o.cageClosePath, field + ".cage_close");
        }
    }
    outputs.input(s.hardware, "--hw");
    outputs.input(s.grid, "--grid");
}

// Runs `read` on every rank. An input every rank reads alike fails on all of them: rank 0 says
// why, once, and every rank stops (false). Outside mpirun the error goes up as any other.
template <class Read>
bool readOnEveryRank(const MpiContext& mpi, Read read) {
    if (!mpi.active()) {
        read();
        return true;
    }
    std::string error;
    try {
        read();
    } catch (const InputError& e) {
        error = e.what();
    }
    const std::vector<std::string> errors = mpi.gather(error);
    if (mpi.allSucceeded(error.empty())) return true;
    for (std::size_t r = 0; r < errors.size(); ++r) {
        if (errors[r].empty()) continue;
        std::cerr << "patchsim: error: " << (r > 0 ? "rank " + std::to_string(r) + ": " : "")
                  << errors[r] << "\n";
        break;
    }
    return false;
}

// Reserves render's outputs on rank 0; every rank learns whether that succeeded.
bool reserveRenderOutputs(const JobSettings& s, const SceneDesc& scene, const MpiContext& mpi,
                          OutputSet& outputs) {
    std::exception_ptr outputError;
    if (mpi.rank() == 0) {
        try {
            protectInputs(outputs, s, {&scene});
            outputs.folder(s.output, "-o");
            for (const char* name : {"image.exr", "image.png", "stats.json"})
                outputs.file(joinOutputPath(s.output, name), "-o");
            if (!s.trace.empty()) outputs.file(s.trace, "--trace");
        } catch (const InputError&) {
            outputError = std::current_exception();
        }
    }
    if (!mpi.allSucceeded(outputError == nullptr)) {
        if (outputError) std::rethrow_exception(outputError);
        return false;  // rank 0 refused the outputs and said why
    }
    return true;
}

// The frame's files, through `outputs`; returns the heat maps written.
std::vector<std::string> writeRenderOutputs(const JobSettings& s, const RenderResult& result,
                                            const StatsContext& context,
                                            const CounterValues& counters, OutputSet& outputs) {
    const std::string exr = outputs.file(joinOutputPath(s.output, "image.exr"), "-o");
    const std::string png = outputs.file(joinOutputPath(s.output, "image.png"), "-o");
    // The two files are independent: with a second thread the PNG is written beside the EXR.
    if (resolveThreadCount(s.threads) > 1) {
        auto pngWritten =
            std::async(std::launch::async, [&] { writePng(result.frame.color, png); });
        writeExrWithAovs(result.frame, exr);
        pngWritten.get();
    } else {
        writeExrWithAovs(result.frame, exr);
        writePng(result.frame.color, png);
    }
    std::vector<std::string> heatMaps;
    if (result.pixels) heatMaps = writeHeatMaps(*result.pixels, s.output, outputs);
    outputs.writeText(joinOutputPath(s.output, "stats.json"), "-o",
                      [&](std::ostream& out) { writeStatsJson(out, context, counters); });
    if (!s.trace.empty())
        outputs.writeText(s.trace, "--trace", [&](std::ostream& out) {
            writeChromeTrace(*context.timing, out, context.memory);
        });
    return heatMaps;
}

// Heat maps an earlier render left in the folder would sit beside a frame they do not describe.
void removeEarlierHeatMaps(const std::string& folder, const std::vector<std::string>& written) {
    namespace fs = std::filesystem;
    std::vector<std::string> names;
    for (const std::string& w : written) names.push_back(fs::path(w).filename().string());
    for (const std::string& name : heatMapFileNames()) {
        if (std::find(names.begin(), names.end(), name) != names.end()) continue;
        std::error_code ec;
        const fs::path p = fs::path(folder) / name;
        if (fs::is_regular_file(p, ec)) fs::remove(p, ec);
    }
}

void printRenderSummary(const JobSettings& s, const SceneDesc& scene, const RenderOptions& options,
                        const RenderResult& result, double ste, std::size_t heatMaps) {
    std::cout << "rendered " << scene.path << " (" << describeMode(result.effects) << ") with the "
              << options.visibilityMethod().name() << " method: " << result.patches << " patches, "
              << result.triangles << " triangles; front end " << result.frontEndSeconds
              << " s, visibility " << result.visibilitySeconds << " s, shading "
              << result.shadingSeconds << " s; STE " << ste << "\nwrote " << s.output
              << "/image.exr (R G B Z coverage motion.x motion.y), image.png, stats.json";
    if (heatMaps > 0) std::cout << " and " << heatMaps << " heat maps";
    std::cout << "\n";
}

}  // namespace

int runInfo(const JobSettings& s) {
    FrontEnd frontEnd(loadScene(s));
    const SceneInfo info = gatherSceneInfo(frontEnd, overridesOf(s), s.threads);
    printSceneInfo(std::cout, frontEnd, info);
    return 0;
}

int runTessellate(const JobSettings& s) {
    FrontEnd frontEnd(loadScene(s));
    OutputSet outputs;
    protectInputs(outputs, s, {&frontEnd.scene()});
    outputs.file(s.output, "-o");  // checked before the work
    if (!s.stats.empty()) outputs.file(s.stats, "--stats");
    TessellateOptions options;
    options.time = s.time;
    options.threads = s.threads;
    TessellationSummary summary;
    outputs.writeText(s.output, "-o", [&](std::ostream& out) {
        summary = writeTessellationObj(frontEnd, options, out);
    });
    StatsContext context{"tessellate", frontEnd.scene().path, {}, {}};
    context.options = recordedOptions(Command::Tessellate, s, nullptr);
    if (!s.stats.empty()) writeStats(outputs, s.stats, "--stats", context);
    outputs.commit();
    std::cout << "wrote " << s.output << ": " << summary.patches << " patches, " << summary.vertices
              << " vertices, " << summary.triangles << " triangles at t=" << s.time << "\n";
    if (!s.quiet) printCounterTable(std::cout, CounterRegistry::instance().snapshot());
    return 0;
}

namespace {

// OpenImageIO's libraries are bound on a side thread while the frame is computed. The workers
// start first (up to one per core; more start on demand), as a thread started during dlopen
// waits for it to finish (backend/images/image_io_module.h).
void startWorkersThenImageModule(int threads) {
    const int workers = std::min(resolveThreadCount(threads), resolveThreadCount(0));
    WorkerPool::shared().startHelpers(std::size_t(workers - 1));
    setImageWriterThreads(workers);
    preloadImageIo();
}

}  // namespace

int runRender(const JobSettings& s, const MpiContext& mpi) {
    SceneDesc scene;
    RenderOptions options;
    HardwareConfig hardware;
    const bool read = readOnEveryRank(mpi, [&] {
        scene = loadScene(s);
        applyRenderOverrides(s, scene);
        options = renderOptionsOf(s);
        hardware = hardwareOf(s);
        if (hardware.memory && mpi.size() > 1)
            throw InputError(s.hardware, "memory",
                             "the memory model replays one process's frame and does not run "
                             "under mpirun yet: drop the section or run one rank");
    });
    if (!read) return 2;
    options.threads = mpi.threadsPerRank(s.threads);
    options.memoryTrace = hardware.memory.has_value();
    // Every output path is checked before the work; nothing is written unless all succeed. Under
    // mpirun the frame is split across ranks by screen tiles and rank 0 writes the one output.
    OutputSet outputs;
    if (!reserveRenderOutputs(s, scene, mpi, outputs)) return 2;
    if (mpi.rank() == 0) startWorkersThenImageModule(options.threads);
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
    const FrameTiming frameTiming = timeFrame(result, hardware);
    const TimingReport& timing = frameTiming.timing;
    const CounterValues counters = CounterRegistry::instance().snapshot();
    const double ste = counters.ratio(options.visibilityMethod().sampleTestEfficiency());
    StatsContext context{"render",
                         scene.path,
                         {},
                         {},
                         &timing,
                         frameTiming.memory ? &*frameTiming.memory : nullptr,
                         &frameTiming.energy};
    context.facts = renderFacts(scene, options, result, counters, ste, s.hardware);
    context.options = recordedOptions(Command::Render, s, &scene.rasterizer);
    const std::vector<std::string> heatMaps =
        writeRenderOutputs(s, result, context, counters, outputs);
    outputs.commit();
    removeEarlierHeatMaps(s.output, heatMaps);
    if (!s.quiet) printCounterTable(std::cout, counters);
    if (mpi.active())
        std::cout << "split across " << mpi.size() << " MPI ranks by tile-row classes\n";
    printTimingReport(timing, std::cout);
    if (frameTiming.memory) printMemoryReport(*frameTiming.memory, std::cout);
    if (frameTiming.memoryNotModelled)
        std::cout << "memory: not modelled for the " << options.visibilityMethod().name()
                  << " method yet ("
                  << (result.memoryTraceDropped
                          ? "it records no surface traffic on transparent frames"
                          : "it records no surface traffic")
                  << "); the timing above is the compute-only model's\n";
    printEnergyReport(frameTiming.energy, std::cout);
    printRenderSummary(s, scene, options, result, ste, heatMaps.size());
    return 0;
}

namespace {

// Every rank's rows, in the order of their jobs.
std::vector<ExploreRow> rowsInJobOrder(const std::vector<std::string>& parts) {
    std::vector<ExploreRow> rows;
    for (const std::string& part : parts) {
        const std::vector<ExploreRow> theirs = unpackExploreRows(part);
        rows.insert(rows.end(), theirs.begin(), theirs.end());
    }
    std::stable_sort(rows.begin(), rows.end(),
                     [](const ExploreRow& a, const ExploreRow& b) { return a.job < b.job; });
    return rows;
}

}  // namespace

int runExplore(const JobSettings& s, const MpiContext& mpi) {
    checkDistinctScenes(s.scenes);
    const SceneLimits limits = s.limits();
    std::vector<SceneDesc> scenes;
    ExploreGrid grid;
    HardwareConfig hardware;
    const bool read = readOnEveryRank(mpi, [&] {
        for (const std::string& path : s.scenes) scenes.push_back(readScene(path, unlimited()));
        if (scenes.empty()) scenes.push_back(defaultScene(unlimited()));
        grid = parseExploreGrid(
            readNamedFile(s.grid, "--grid", [](const std::string& p) { return readTextFile(p); }),
            s.grid);
        hardware = hardwareOf(s);
        checkGridHardware(grid, hardware);
    });
    if (!read) return 2;
    OutputSet outputs;  // only rank 0 writes; every rank checks the paths alike
    std::vector<const SceneDesc*> inputs;
    for (const SceneDesc& scene : scenes) inputs.push_back(&scene);
    protectInputs(outputs, s, inputs);
    // The plots' folder first: it may be the CSV's too, made by this command.
    const PlotJob plots{"explore", s.output, s.plots};
    if (!s.plots.empty()) addPlotScript(outputs, plots, "--plots");
    outputs.file(s.output, "-o");
    const std::size_t jobs = exploreJobs(scenes.size(), grid).size();
    // Jobs are dealt round-robin over ranks; each rank tags its rows with the job number. A job
    // that fails on one rank must not leave the others waiting: every rank reports, then all stop.
    std::vector<ExploreRow> mine;
    std::exception_ptr failure;
    try {
        runExploreJobs(
            scenes, grid, hardware, mpi.threadsPerRank(s.threads), limits,
            [&](std::size_t j) { return int(j % std::size_t(mpi.size())) == mpi.rank(); },
            [&](std::size_t j, const std::vector<ExploreRow>& rows) {
                mine.insert(mine.end(), rows.begin(), rows.end());
                if (mpi.rank() == 0 && !s.noProgress)
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
    const std::vector<ExploreRow> rows = rowsInJobOrder(parts);
    std::string csv = exploreCsvHeader(grid) + "\n";
    for (const ExploreRow& row : rows) csv += row.csv + "\n";
    outputs.writeText(s.output, "-o", [&](std::ostream& out) { out << csv; });
    outputs.commit();
    std::cout << "wrote " << s.output << ": " << rows.size() << " points (" << jobs << " renders"
              << (mpi.active() ? " over " + std::to_string(mpi.size()) + " MPI ranks"
                               : std::string())
              << ")\n";
    if (!s.plots.empty()) drawPlots(plots, std::cout);
    return 0;
}

// Each method of --methods at every combination of its own --vary axes' values (one variant, at
// the options' values, when none varies it).
std::vector<SweepVariant> sweepVariants(const JobSettings& s) {
    std::vector<SweepAxis> axes;
    for (const std::string& text : s.vary) axes.push_back(parseSweepAxis(text));
    for (const SweepAxis& axis : axes) {
        const auto runs = [&](const std::string& m) {
            return std::find(s.methods.begin(), s.methods.end(), m) != s.methods.end();
        };
        if (std::none_of(axis.methods.begin(), axis.methods.end(), runs)) {
            std::string owners;
            for (std::size_t k = 0; k < axis.methods.size(); ++k)
                owners += (k == 0                         ? ""
                           : k + 1 == axis.methods.size() ? " and "
                                                          : ", ") +
                          axis.methods[k];
            throw InputError("command line", "--vary",
                             axis.name + " is a parameter of " + owners + ", " +
                                 (axis.methods.size() == 1 ? "which --methods does not run"
                                                           : "none of which --methods runs"));
        }
    }
    std::vector<SweepVariant> variants;
    for (const std::string& name : s.methods) {
        std::vector<const SweepAxis*> mine;
        for (const SweepAxis& axis : axes)
            if (std::find(axis.methods.begin(), axis.methods.end(), name) != axis.methods.end())
                mine.push_back(&axis);
        // An odometer over the axes' values, the last axis fastest.
        std::vector<std::size_t> at(mine.size(), 0);
        for (bool more = true; more;) {
            JobSettings c = s;
            SweepVariant v;
            v.method = &methodNamed(name);  // checked against the method table
            for (std::size_t k = 0; k < mine.size(); ++k) {
                const std::string& value = mine[k]->values[at[k]];
                v.setting += (k ? ";" : "") + mine[k]->name + "=" + value;
                if (mine[k]->option)
                    applyJobOption(*mine[k]->option, value, c);
                else
                    v.rasterizer.push_back({mine[k]->field->key, value});
            }
            v.render = renderOptionsOf(c);
            variants.push_back(std::move(v));
            more = false;
            for (std::size_t k = mine.size(); k-- > 0 && !more;) {
                more = ++at[k] < mine[k]->values.size();
                if (!more) at[k] = 0;
            }
        }
    }
    return variants;
}

namespace {

// A sweep compares methods: with the memory system modelled, each must be charged its traffic
// on every scene. An opaque-only trace (interleaved, reprojection) is dropped for transparent
// frames (render.cpp).
void checkSweepMethodsTraceMemory(const std::vector<SweepVariant>& variants,
                                  const std::vector<SweepScene>& scenes,
                                  const EffectOverrides& overrides, const std::string& hardware) {
    bool transparent = false;
    for (const SweepScene& scene : scenes)
        transparent =
            transparent ||
            applyOverrides(detectEffects(scene.scene, false, false), overrides).transparency;
    std::string missing;
    int count = 0;
    SceneDesc probe;
    probe.film.width = probe.film.height = probe.film.samplesPerPixel = 1;
    for (const SweepVariant& v : variants) {
        const std::unique_ptr<MemoryTrace> trace = v.method->makeMemoryTrace(probe);
        if ((!trace || (transparent && trace->opaqueOnly())) &&
            missing.find(v.method->name()) == std::string::npos) {
            missing += (missing.empty() ? "" : ", ") + std::string(v.method->name());
            ++count;
        }
    }
    if (!missing.empty())
        throw InputError(hardware, "memory",
                         "sweep compares its methods on modelled cycles, and " + missing +
                             (count == 1 ? " records" : " record") + " no memory traffic" +
                             (transparent ? " on transparent frames" : "") +
                             " yet: with memory charged to some methods only the comparison "
                             "would be unequal; drop those methods or the memory section");
}

}  // namespace

int runSweepCommand(const JobSettings& s) {
    imageIoModulePath();  // its pictures need the image module: refuse its absence before the work
    SweepOptions o;
    o.variants = sweepVariants(s);
    o.samplesPerPixel = s.sppList;
    o.repeats = s.repeats;
    o.convergedSamplesPerPixel = s.convergedSpp;
    o.render = renderOptionsOf(s);
    o.hardware = hardwareOf(s);
    o.limits = s.limits();
    o.outputDir = s.output;
    o.progress = !s.noProgress;
    std::vector<std::string> paths = s.scenes;
    if (paths.empty()) paths.push_back("");
    const std::vector<std::string> labels = sweepSceneLabels(paths, s.blurList);
    std::vector<SweepScene> scenes;
    for (const std::string& path : paths) {
        const SceneDesc scene =
            path.empty() ? defaultScene(unlimited()) : readScene(path, unlimited());
        for (float blur : s.blurList) {
            scenes.push_back(
                {labels[scenes.size()], blur == 1.0f ? scene : scaleBlur(scene, blur)});
        }
    }
    if (o.hardware.memory)
        checkSweepMethodsTraceMemory(o.variants, scenes, o.render.overrides, s.hardware);
    for (const SweepScene& scene : scenes) {
        o.inputs.push_back({scene.scene.path, "scene"});
        for (const ObjectDesc& object : scene.scene.objects) {
            o.inputs.push_back({object.cagePath, "cage"});
            o.inputs.push_back({object.cageClosePath, "cage_close"});
        }
    }
    o.inputs.push_back({s.hardware, "--hw"});
    runSweep(scenes, o, std::cout);
    return 0;
}

namespace {

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

void printVerifyReport(const TileVerifierResult& result, std::uint64_t seed, CaseFamily family) {
    const std::string familyFlag =
        family == CaseFamily::Mixed ? "" : std::string(" --family ") + caseFamilyName(family);
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
            std::cout << "  first false reject: patchsim verify-tiles --seed " << seed << familyFlag
                      << " --replay " << r.firstFailure << "\n";
    }
    std::cout << "witness: " << result.witnessCases << " cases sampled, " << result.witnessHits
              << " sampled hits, " << result.witnessOutsideTruth << " outside the exact truth\n";
}

// --format's variants, registered for the run (those already registered are kept as they are).
std::vector<std::unique_ptr<ScopedTileTest>> registerFormatTileTests(const std::string& list) {
    std::vector<std::unique_ptr<ScopedTileTest>> scoped;
    if (list.empty()) return scoped;
    const std::string formats = list == "all" ? "fp16,bf16,fixed16.8" : list;
    for (std::size_t begin = 0; begin <= formats.size();) {
        const std::size_t end = std::min(formats.find(',', begin), formats.size());
        const std::string item = formats.substr(begin, end - begin);
        begin = end + 1;
        NumberFormat format;
        if (!parseNumberFormat(item, format) || format == NumberFormat::fp32())
            throw InputError("command line", "--format",
                             "'" + item + "' is not a reduced number format (fp16, bf16, " +
                                 "fixedI.F with I in 2..32, F in 0..30, I + F <= 48; or all)");
        for (auto& variant : formatTileTests(format)) {
            const bool known =
                std::any_of(registeredTileTests().begin(), registeredTileTests().end(),
                            [&](const auto& v) { return v->name() == variant->name(); });
            if (!known) scoped.push_back(std::make_unique<ScopedTileTest>(std::move(variant)));
        }
    }
    return scoped;
}

}  // namespace

int runVerifyTiles(const JobSettings& s) {
    const auto seed = std::uint64_t(s.seed);
    CaseFamily family;
    if (!parseCaseFamily(s.family, family))
        throw InputError("command line", "--family",
                         "'" + s.family + "' is not a case family (" + caseFamilyNames() + ")");
    const auto formatVariants = registerFormatTileTests(s.formats);
    if (!s.replay.empty()) {
        if (!replayTileCase(s.replay, seed, std::cout, family))
            throw InputError(
                "command line", "--replay",
                "'" + s.replay + "' is not a case name (pinhole:N, lens:N or hierarchy:N)");
        return 0;
    }
    TileVerifierOptions o;
    o.cases = s.cases;
    o.seed = seed;
    o.threads = s.threads;
    o.witnessEvery = s.witnessEvery;
    o.family = family;
    OutputSet outputs;
    std::ofstream csv;
    if (!s.summary.empty()) outputs.file(s.summary, "--summary");  // checked before the work
    if (!s.csv.empty()) {
        // Streamed into the reserved temporary: a million cases are too many rows to hold.
        csv.open(outputs.file(s.csv, "--csv"));
        if (!csv) throw InputError(s.csv, "--csv", "cannot write the file");
        o.csv = &csv;
    }
    const TileVerifierResult result = verifyTileTests(o);
    if (csv.is_open()) {
        csv.close();
        if (!csv) throw InputError(s.csv, "--csv", "writing the file failed");
    }
    if (!s.summary.empty())
        outputs.writeText(s.summary, "--summary",
                          [&](std::ostream& out) { writeVerifySummary(result, out); });
    printVerifyReport(result, seed, family);
    outputs.commit();
    return result.anyFalseReject() ? 1 : 0;
}

}  // namespace patchsim
