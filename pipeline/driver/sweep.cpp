#include "pipeline/driver/sweep.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <ostream>

#include "backend/image_metrics.h"
#include "pipeline/core/counters.h"
#include "pipeline/core/output_set.h"
#include "pipeline/core/progress.h"
#include "pipeline/driver/converged_image.h"
#include "pipeline/driver/plots.h"
#include "pipeline/driver/timing_model.h"

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

SweepRow measureRun(const SweepScene& s, VisibilityMethod method, int spp,
                    const ConvergedImage& converged, const SweepOptions& o, Image& picture) {
    SceneDesc scene = s.scene;
    scene.film.samplesPerPixel = spp;
    checkMemoryBudget(scene.film, o.limits, s.label, "--spp");
    RenderOptions options = o.render;
    options.method = method;
    options.progress = false;
    std::vector<double> seconds;
    SweepRow row;
    row.scene = s.label;
    row.method = visibilityMethodName(method);
    row.spp = spp;
    for (int r = 0; r < std::max(1, o.repeats); ++r) {
        CounterRegistry::instance().reset();
        RenderResult result = renderScene(scene, options);
        seconds.push_back(result.visibilitySeconds + result.shadingSeconds);
        if (r > 0) continue;
        const CounterValues counters = CounterRegistry::instance().snapshot();
        row.modelledCycles = simulateTiming(result.patchOps, o.hardware).totalCycles;
        row.visibility = visibilityTotals(counters, method);
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

std::string sweepCsvHeader() {
    return "scene,method,spp,wall_seconds,modelled_cycles,samples_tested,rays,visibility_samples,"
           "sample_test_efficiency,shading_invocations,rmse,psnr,ssim,coverage_error";
}

std::string sweepCsvRow(const SweepRow& r) {
    return r.scene + "," + r.method + "," + std::to_string(r.spp) + "," + number(r.wallSeconds) +
           "," + number(r.modelledCycles) + "," + std::to_string(r.visibility.samplesTested) + "," +
           std::to_string(r.visibility.rays) + "," +
           std::to_string(r.visibility.visibilitySamples) + "," +
           number(r.visibility.sampleTestEfficiency) + "," + std::to_string(r.shadingInvocations) +
           "," + number(r.rmse) + "," + number(r.psnr) + "," + number(r.ssim) + "," +
           number(r.coverageError);
}

std::vector<SweepRow> runSweep(const std::vector<SweepScene>& scenes, const SweepOptions& o,
                               std::ostream& log) {
    const std::string dir = o.outputDir;
    OutputSet outputs;
    outputs.folder(dir, "-o");
    outputs.folder(dir + "/images", "-o");
    outputs.file(dir + "/results.csv", "-o");
    const PlotJob plots{"sweep", dir + "/results.csv", dir + "/plots"};
    addPlotScript(outputs, plots, "-o");
    const int maxSpp = *std::max_element(o.samplesPerPixel.begin(), o.samplesPerPixel.end());
    const int convergedSpp =
        o.convergedSamplesPerPixel > 0 ? o.convergedSamplesPerPixel : 16 * maxSpp;
    std::vector<SweepRow> rows;
    Progress progress("sweep     ",
                      std::int64_t(scenes.size() * o.methods.size() * o.samplesPerPixel.size()), 1,
                      o.progress, "runs");
    for (const SweepScene& s : scenes) {
        progress.describe(s.label + ": converged image, " + std::to_string(convergedSpp) + " spp");
        const ConvergedImage converged =
            convergedImage(s.scene, convergedSpp, o.render, dir + "/converged");
        log << s.label << ": converged image (" << convergedSpp << " spp, patch method) "
            << (converged.fromCache ? "reused from " : "rendered into ") << converged.path << "\n";
        writePng(converged.color,
                 outputs.file(dir + "/images/" + s.label + "-converged.png", "-o"));
        for (VisibilityMethod method : o.methods) {
            for (int spp : o.samplesPerPixel) {
                const std::string run =
                    s.label + "-" + visibilityMethodName(method) + "-" + std::to_string(spp);
                progress.describe(run);
                Image picture;
                rows.push_back(measureRun(s, method, spp, converged, o, picture));
                writePng(picture, outputs.file(dir + "/images/" + run + ".png", "-o"));
                progress.advance();
            }
        }
    }
    outputs.writeText(dir + "/results.csv", "-o", [&](std::ostream& out) {
        out << sweepCsvHeader() << "\n";
        for (const SweepRow& r : rows) out << sweepCsvRow(r) << "\n";
    });
    outputs.commit();
    log << "wrote " << dir << "/results.csv (" << rows.size() << " runs) and their images in "
        << dir << "/images\n";
    drawPlots(plots, log);
    return rows;
}

}  // namespace patchsim
