#include "pipeline/driver/sweep.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <ostream>
#include <set>

#include "backend/images/image_metrics.h"
#include "core/counters.h"
#include "core/error.h"
#include "core/output_set.h"
#include "core/progress.h"
#include "core/rasterizer_options.h"
#include "pipeline/driver/converged_image.h"
#include "pipeline/driver/plots.h"
#include "pipeline/timing/timing_model.h"

namespace patchsim {

namespace {

std::string number(double v) {
    if (std::isinf(v)) return "inf";
    char text[40];
    std::snprintf(text, sizeof text, "%.10g", v);
    return text;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// The scene as a variant renders it: at `spp`, with the variant's rasterizer options.
SceneDesc variantScene(const SweepScene& s, const SweepVariant& v, int spp) {
    SceneDesc scene = s.scene;
    scene.film.samplesPerPixel = spp;
    for (const auto& [key, text] : v.rasterizer) {
        const RasterizerOptionField& field = *findRasterizerOptionField(key);
        const std::string error = field.set(scene.rasterizer, optionValueFromText(text));
        if (!error.empty()) throw InputError("command line", "--vary", error);
    }
    if (!v.rasterizer.empty()) scene.rasterizer.validate("--vary " + v.setting);
    return scene;
}

SweepRow measureRun(const SweepScene& s, const SweepVariant& variant, int spp,
                    const ConvergedImage& converged, const SweepOptions& o, Image& picture) {
    const SceneDesc scene = variantScene(s, variant, spp);
    const VisibilityMethod& method = *variant.method;
    RenderOptions options = variant.render;
    options.method = &method;
    options.progress = false;
    options.memoryTrace = o.hardware.memory.has_value();
    std::vector<double> seconds;
    SweepRow row;
    row.scene = s.label;
    row.method = method.name();
    row.setting = variant.setting;
    row.spp = spp;
    for (int r = 0; r < std::max(1, o.repeats); ++r) {
        CounterRegistry::instance().reset();
        RenderResult result = renderScene(scene, options);
        seconds.push_back(result.visibilitySeconds + result.shadingSeconds);
        if (r > 0) continue;
        const CounterValues counters = CounterRegistry::instance().snapshot();
        const FrameTiming timing = timeFrame(result, o.hardware);
        row.modelledCycles = timing.timing.totalCycles;
        if (timing.memory) row.dramBytes = timing.memory->dramBytes();
        if (timing.memory && timing.memory->config.dramBanks.modelled())
            row.dramRowHitRate = timing.memory->dramBanks.rowHitRate();
        row.energyNanojoules = timing.energy.totalPicojoules() / 1e3;
        row.visibility = method.totals(counters);
        row.shadingInvocations = counters[shadingCounters().invocations];
        row.rmse = rmse(result.frame.color, converged.color);
        row.psnr = psnr(result.frame.color, converged.color);
        row.ssim = ssim(result.frame.color, converged.color);
        row.coverageError = meanAbsoluteDifference(result.frame.coverage, converged.coverage);
        picture = std::move(result.frame.color);
    }
    row.wallSeconds = median(seconds);
    return row;
}

}  // namespace

SceneDesc scaleBlur(const SceneDesc& scene, float k) {
    SceneDesc s = scene;
    auto scaled = [k](const Vec3& open, const Vec3& close) { return open + k * (close - open); };
    for (ObjectDesc& o : s.objects) {
        o.close.translate = scaled(o.open.translate, o.close.translate);
        o.close.rotateDegrees = scaled(o.open.rotateDegrees, o.close.rotateDegrees);
        o.close.scale = scaled(o.open.scale, o.close.scale);
    }
    s.camera.close.position = scaled(s.camera.open.position, s.camera.close.position);
    s.camera.close.lookAt = scaled(s.camera.open.lookAt, s.camera.close.lookAt);
    s.lens.apertureRadius *= k;
    return s;
}

namespace {

// A path's stem with as many parent folders as it takes to tell it from the others ("a-motion",
// "b-motion"); "default" for the built-in scene (path "").
std::string pathLabel(const std::string& path, const std::vector<std::string>& paths) {
    namespace fs = std::filesystem;
    const auto components = [](const std::string& p) {
        std::vector<std::string> parts;
        fs::path normal = fs::path(p).lexically_normal();
        normal.replace_extension();
        for (const fs::path& part : normal)
            if (!part.empty() && part != "." && part != "/") parts.push_back(part.string());
        return parts;
    };
    const auto tail = [&](const std::string& p, std::size_t k) {
        if (p.empty()) return std::string("default");
        const std::vector<std::string> parts = components(p);
        std::string label;
        for (std::size_t i = parts.size() - std::min(k, parts.size()); i < parts.size(); ++i)
            label += (label.empty() ? "" : "-") + parts[i];
        return label;
    };
    // Folders cannot tell apart two files that differ only in their extension: numbered later.
    std::size_t k = 1;
    const auto collides = [&] {
        for (const std::string& other : paths)
            if (components(other) != components(path) && tail(other, k) == tail(path, k))
                return true;
        return false;
    };
    while (collides() && k < components(path).size()) ++k;
    return tail(path, k);
}

// Labels name files and CSV fields: anything but letters, digits, '.', '_' and '-' becomes '_'.
std::string safeLabel(std::string label) {
    for (char& c : label)
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '_' && c != '-')
            c = '_';
    return label;
}

}  // namespace

std::vector<std::string> sweepSceneLabels(const std::vector<std::string>& paths,
                                          const std::vector<float>& blurs) {
    namespace fs = std::filesystem;
    std::vector<std::string> normal;
    for (const std::string& p : paths) {
        const std::string n = p.empty() ? p : fs::path(p).lexically_normal().string();
        if (std::find(normal.begin(), normal.end(), n) != normal.end())
            throw InputError("command line", "scenes", "names '" + p + "' twice");
        normal.push_back(n);
    }
    std::vector<std::string> labels;
    for (const std::string& path : normal) {
        const std::string base = safeLabel(pathLabel(path, normal));
        for (float blur : blurs) {
            char suffix[32] = "";
            if (blur != 1.0f) std::snprintf(suffix, sizeof suffix, "-blur%.9g", double(blur));
            labels.push_back(base + suffix);
        }
    }
    // Still equal ("motion" at blur 2 and a scene named "motion-blur2", or two files that differ
    // only in their extension): numbered in order, so every run has its own name.
    std::set<std::string> taken;
    for (std::string& label : labels) {
        const std::string base = label;
        for (int copy = 2; taken.count(label); ++copy) label = base + "-" + std::to_string(copy);
        taken.insert(label);
    }
    return labels;
}

std::string SweepVariant::label() const {
    return safeLabel(setting.empty() ? std::string(method->name())
                                     : std::string(method->name()) + "-" + setting);
}

void markParetoFronts(std::vector<SweepRow>& rows) {
    const auto sameRun = [](const SweepRow& a, const SweepRow& b) {
        return a.scene == b.scene && a.spp == b.spp && a.method == b.method;
    };
    for (SweepRow& r : rows) {
        r.front = true;
        for (const SweepRow& other : rows) {
            if (&other == &r || !sameRun(r, other)) continue;
            const bool noWorse = other.modelledCycles <= r.modelledCycles && other.rmse <= r.rmse;
            const bool better = other.modelledCycles < r.modelledCycles || other.rmse < r.rmse;
            if (noWorse && better) r.front = false;
        }
    }
}

std::string sweepCsvHeader() {
    return "scene,method,setting,spp,wall_seconds,modelled_cycles,samples_tested,rays,"
           "visibility_samples,sample_test_efficiency,shading_invocations,rmse,psnr,ssim,"
           "coverage_error,front,dram_bytes,dram_row_hit_rate,energy_nj";
}

std::string sweepCsvRow(const SweepRow& r) {
    return r.scene + "," + r.method + "," + r.setting + "," + std::to_string(r.spp) + "," +
           number(r.wallSeconds) + "," + number(r.modelledCycles) + "," +
           std::to_string(r.visibility.samplesTested) + "," + std::to_string(r.visibility.rays) +
           "," + std::to_string(r.visibility.visibilitySamples) + "," +
           number(r.visibility.sampleTestEfficiency) + "," + std::to_string(r.shadingInvocations) +
           "," + number(r.rmse) + "," + number(r.psnr) + "," + number(r.ssim) + "," +
           number(r.coverageError) + "," + (r.front ? "1" : "0") + "," +
           (r.dramBytes ? std::to_string(*r.dramBytes) : std::string()) + "," +
           (r.dramRowHitRate ? number(*r.dramRowHitRate) : std::string()) + "," +
           number(r.energyNanojoules);
}

namespace {

// Every run's film and the rasterizer's scratch against the memory budget, before the first run:
// a run over budget must not be found after hours of earlier runs.
void checkEveryRun(const std::vector<SweepScene>& scenes, const SweepOptions& o, int convergedSpp) {
    for (const SweepScene& s : scenes) {
        for (int spp : o.samplesPerPixel) {
            checkMemoryBudget(variantScene(s, {}, spp).film, o.limits, s.label, "--spp");
            for (const SweepVariant& v : o.variants) {
                const SceneDesc scene = variantScene(s, v, spp);
                scene.rasterizer.validateTileSamples(spp, s.label);
                RenderOptions options = v.render;
                options.method = v.method;
                checkRender(scene, options);
            }
        }
        // The converged image: the patch method at the scene's own settings, in passes.
        const int spp = std::min(convergedSpp, kConvergedSamplesPerPass);
        const SceneDesc scene = variantScene(s, {}, spp);
        checkMemoryBudget(scene.film, o.limits, s.label, "--converged-spp");
        scene.rasterizer.validateTileSamples(spp, s.label);
        RenderOptions options = o.render;
        options.method = nullptr;
        checkRender(scene, options);
    }
}

// The images/ folder belongs to the sweep: images an earlier sweep left there (other scenes,
// methods or counts) would sit beside a CSV that does not list them.
std::size_t removeStaleImages(const std::string& imagesDir, const std::set<std::string>& written) {
    namespace fs = std::filesystem;
    std::size_t removed = 0;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(imagesDir, ec)) {
        const fs::path& p = entry.path();
        if (p.extension() != ".png" || written.count(p.filename().string())) continue;
        if (entry.is_regular_file(ec) && fs::remove(p, ec)) ++removed;
    }
    return removed;
}

}  // namespace

std::vector<SweepRow> runSweep(const std::vector<SweepScene>& scenes, const SweepOptions& o,
                               std::ostream& log) {
    const std::string dir = o.outputDir;
    const int maxSpp = *std::max_element(o.samplesPerPixel.begin(), o.samplesPerPixel.end());
    const int convergedSpp =
        o.convergedSamplesPerPixel > 0 ? o.convergedSamplesPerPixel : 16 * maxSpp;
    checkEveryRun(scenes, o, convergedSpp);
    OutputSet outputs;
    for (const auto& [path, field] : o.inputs) outputs.input(path, field);
    outputs.folder(dir, "-o");
    const std::string imagesDir = joinOutputPath(dir, "images");
    outputs.folder(imagesDir, "-o");
    // Every run's image is reserved now, so a path that cannot be written fails before any run.
    for (const SweepScene& s : scenes) {
        outputs.file(joinOutputPath(imagesDir, s.label + "-converged.png"), "-o");
        for (const SweepVariant& v : o.variants)
            for (int spp : o.samplesPerPixel)
                outputs.file(joinOutputPath(imagesDir, s.label + "-" + v.label() + "-" +
                                                           std::to_string(spp) + ".png"),
                             "-o");
    }
    outputs.file(joinOutputPath(dir, "results.csv"), "-o");
    outputs.file(joinOutputPath(dir, "best.csv"), "-o");
    const PlotJob plots{"sweep", joinOutputPath(dir, "results.csv"), joinOutputPath(dir, "plots")};
    addPlotScript(outputs, plots, "-o");
    std::vector<SweepRow> rows;
    std::set<std::string> images;
    Progress progress("sweep     ",
                      std::int64_t(scenes.size() * o.variants.size() * o.samplesPerPixel.size()), 1,
                      o.progress, "runs");
    const auto say = [&](const std::string& line) {
        progress.clear();
        log << line << "\n" << std::flush;
    };
    if (convergedSpp < maxSpp)
        say("warning: --converged-spp " + std::to_string(convergedSpp) +
            " is below the largest --spp " + std::to_string(maxSpp) +
            ": the error of the runs above it measures the converged image's own noise");
    const auto writeImage = [&](const Image& picture, const std::string& name) {
        writePng(picture, outputs.file(joinOutputPath(imagesDir, name), "-o"));
        images.insert(name);
    };
    for (const SweepScene& s : scenes) {
        progress.describe(s.label + ": converged image, " + std::to_string(convergedSpp) + " spp");
        const ConvergedImage converged =
            convergedImage(s.scene, convergedSpp, o.render, joinOutputPath(dir, "converged"));
        say(s.label + ": converged image (" + std::to_string(convergedSpp) +
            " spp, patch method) " + (converged.fromCache ? "reused from " : "rendered into ") +
            converged.path + (converged.note.empty() ? "" : " (" + converged.note + ")"));
        writeImage(converged.color, s.label + "-converged.png");
        for (const SweepVariant& v : o.variants) {
            for (int spp : o.samplesPerPixel) {
                const std::string run = s.label + "-" + v.label() + "-" + std::to_string(spp);
                progress.describe(run);
                Image picture;
                rows.push_back(measureRun(s, v, spp, converged, o, picture));
                writeImage(picture, run + ".png");
                progress.advance();
            }
        }
    }
    progress.clear();
    markParetoFronts(rows);
    for (const char* name : {"results.csv", "best.csv"}) {
        const bool all = std::string(name) == "results.csv";
        outputs.writeText(joinOutputPath(dir, name), "-o", [&](std::ostream& out) {
            out << sweepCsvHeader() << "\n";
            for (const SweepRow& r : rows)
                if (all || r.front) out << sweepCsvRow(r) << "\n";
        });
    }
    outputs.commit();
    const std::size_t stale = removeStaleImages(imagesDir, images);
    log << "wrote " << dir << "/results.csv (" << rows.size() << " runs), " << dir
        << "/best.csv (each method's Pareto-best settings) and the runs' images in " << imagesDir;
    if (stale > 0) log << "; removed " << stale << " images of an earlier sweep";
    log << "\n";
    drawPlots(plots, log);
    return rows;
}

}  // namespace patchsim
