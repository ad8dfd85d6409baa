#include "pipeline/app/job_options.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "core/error.h"
#include "core/rasterizer_options.h"
#include "pipeline/methods/visibility_method.h"

namespace patchsim {

namespace {

constexpr unsigned kInfo = commandBit(Command::Info), kTess = commandBit(Command::Tessellate),
                   kRender = commandBit(Command::Render),
                   kVerify = commandBit(Command::VerifyTiles), kSweep = commandBit(Command::Sweep),
                   kExplore = commandBit(Command::Explore);
constexpr unsigned kScenes = kInfo | kTess | kRender | kSweep | kExplore;
constexpr unsigned kFilms = kRender | kSweep | kExplore;  // the commands that render films

std::vector<std::string> methodNames() {
    std::vector<std::string> names;
    for (const VisibilityMethod* m : visibilityMethods()) names.push_back(m->name());
    return names;
}

using S = JobSettings;
using K = ValueKind;

// Rows in the order the help lists them. A flag may have one row per command when its meaning
// differs (-o names a folder for render, a file for tessellate).
std::vector<JobOption> makeTable() {
    const double kMaxSeed = 9.2e18;  // below 2^63
    const unsigned kPerMethod = kRender | kSweep;
    using O = JobOption;
    std::vector<JobOption> t;
    t.push_back(O("scene", kInfo | kTess | kRender, K::InputPath, &S::scenes,
                  "Scene JSON file, or an OBJ cage to view alone (default: the built-in scene)"));
    t.push_back(O("scenes", kSweep | kExplore, K::InputPath, &S::scenes,
                  "Scene JSON files or OBJ cages (default: the built-in scene)"));
    t.push_back(O("-o,--output", kRender, K::OutputFolder, &S::output,
                  "Output folder for image.exr, image.png, stats.json (and heat maps)"));
    t.push_back(O("-o,--output", kTess, K::OutputFile, &S::output, "Output OBJ file"));
    t.push_back(O("-o,--output", kSweep, K::OutputFolder, &S::output,
                  "Folder for results.csv, images/, plots/ and the converged-image cache"));
    t.push_back(O("-o,--output", kExplore, K::OutputFile, &S::output, "CSV file to write"));
    t.push_back(
        O("--grid", kExplore, K::InputPath, &S::grid, "Grid file (docs/EXPLORE.md); required"));
    t.push_back(O("--plots", kExplore, K::OutputFolder, &S::plots,
                  "Folder for the plots (PNG and SVG: cycles against each parameter, heat maps "
                  "of each pair)"));
    t.push_back(O("--method", kRender, K::Name, &S::method, "Visibility method")
                    .oneOf(methodNames())
                    .recordedAs("method"));
    t.push_back(
        O("--methods", kSweep, K::NameList, &S::methods, "Comma-separated visibility methods")
            .oneOf(methodNames()));
    t.push_back(O("--spp", kRender, K::Integer, &S::spp,
                  "Samples per pixel, instead of the scene's film.spp (0: the scene's)")
                    .in(0, 4096));
    t.push_back(O("--spp", kSweep, K::IntegerList, &S::sppList, "Comma-separated samples per pixel")
                    .in(1, 4096));
    t.push_back(O("--width", kRender, K::Integer, &S::width,
                  "Film width in pixels, instead of the scene's (0: the scene's)")
                    .in(0, 16384));
    t.push_back(O("--height", kRender, K::Integer, &S::height,
                  "Film height in pixels, instead of the scene's (0: the scene's)")
                    .in(0, 16384));
    t.push_back(O("--blur", kSweep, K::RealList, &S::blurList,
                  "Comma-separated scales of every scene's motion and aperture")
                    .in(0, 1000)
                    .openBelow());
    t.push_back(
        O("--repeats", kSweep, K::Integer, &S::repeats, "Renders per run; the median time counts")
            .in(1, 100));
    t.push_back(
        O("--vary", kSweep, K::Variation, &S::vary,
          "A method parameter's values, NAME=V1,V2,... (repeatable): the method runs at "
          "every combination of its own parameters' values, e.g. time-strata=0,4,16, "
          "bbox-bound=hull,oriented,box, edge-threshold=0.9,0.98, tfragment-limit=128,4096, "
          "or a rasterizer option of the methods that rasterize patches (leaf-size=2,4,8); "
          "its values replace the option's own; results.csv marks each method's Pareto-best "
          "settings and best.csv lists them"));
    t.push_back(O("--converged-spp", kSweep, K::Integer, &S::convergedSpp,
                  "Samples per pixel of the converged image (0: 16 x the largest --spp)")
                    .in(0, 1 << 20));
    t.push_back(
        O("--time-strata", kPerMethod, K::Integer, &S::timeStrata,
          "interval: time strata K (0: one per sample of a pixel, as Fatahalian et al. run it; "
          "one when nothing moves)")
            .in(0, 4096)
            .ofMethods({"interval"})
            .recordedAs("time_strata"));
    t.push_back(O("--bbox-bound", kPerMethod, K::Name, &S::bboxBound,
                  "triangle-bbox: the bound whose samples are ray-tested (hull: the convex hull of "
                  "the moving, defocused triangle, as McGuire et al. 2010; oriented: the "
                  "least-area rectangle holding that hull; box: its screen box)")
                    .oneOf({"hull", "oriented", "box"})
                    .ofMethods({"triangle-bbox"})
                    .recordedAs("bbox_bound"));
    t.push_back(O("--pp-tile-size", kPerMethod, K::Integer, &S::ppTileSize,
                  "postprocess: TileMax tile size k in pixels (velocities are clamped to it)")
                    .in(1, 1024)
                    .ofMethods({"postprocess", "hybrid"})
                    .recordedAs("pp_tile_size"));
    t.push_back(O("--pp-samples", kPerMethod, K::Integer, &S::ppSamples,
                  "postprocess: samples gathered per pixel (odd: the centre is the pixel itself)")
                    .in(3, 255)
                    .oddOnly()
                    .ofMethods({"postprocess", "hybrid"})
                    .recordedAs("pp_samples"));
    t.push_back(O("--soft-z-extent", kPerMethod, K::Real, &S::softZExtent,
                  "postprocess: SOFT_Z_EXTENT, the depth over which samples blend from in front "
                  "to behind (scene units)")
                    .in(1e-6, 1e6)
                    .ofMethods({"postprocess", "hybrid"})
                    .recordedAs("soft_z_extent"));
    t.push_back(
        O("--edge-threshold", kPerMethod, K::Real, &S::edgeThreshold,
          "hybrid: Sobel edge threshold e of the ray mask, on Tan et al.'s scale (x_n of the "
          "unnormalised 5x5 Sobel; they use 0.9 to 0.98)")
            .in(0, 1)
            .openAbove()
            .ofMethods({"hybrid"})
            .recordedAs("edge_threshold"));
    t.push_back(O("--camera-steps", kPerMethod, K::Integer, &S::cameraSteps,
                  "reprojection: interpolated cameras per reprojection cycle")
                    .in(2, 1024)
                    .ofMethods({"reprojection"})
                    .recordedAs("camera_steps"));
    t.push_back(O("--motion-samples", kPerMethod, K::Integer, &S::motionSamples,
                  "tfragment: time samples per lens ray (the paper's 4 and 32)")
                    .in(1, 256)
                    .ofMethods({"tfragment"})
                    .recordedAs("motion_samples"));
    t.push_back(O("--tfragment-limit", kPerMethod, K::Integer, &S::tfragmentLimit,
                  "tfragment: t-fragments a lens ray keeps; those beyond it are dropped (the "
                  "paper's 128)")
                    .in(1, 1 << 20)
                    .ofMethods({"tfragment"})
                    .recordedAs("tfragment_limit"));
    t.push_back(O("--time-sampled", kRender, K::Flag, &S::timeSampled,
                  "tfragment: trace once per motion sample instead of once per lens ray (the "
                  "paper's comparison)")
                    .recordedAs("time_sampled"));
    t.push_back(O("--no-time-refinement", kRender, K::Flag, &S::noTimeRefinement,
                  "Same as --time-refinement false"));
    t.push_back(O("--no-z-culling", kRender, K::Flag, &S::noZCulling, "Same as --z-culling false"));
    t.push_back(O("--filter", kRender, K::Name, &S::filter, "Resolve filter")
                    .oneOf({"box", "gaussian"})
                    .recordedAs("filter"));
    t.push_back(O("--shading-rate", kRender, K::Name, &S::shadingRate,
                  "per-fragment (every t-fragment) or per-pixel-primitive (MSAA-style reuse)")
                    .oneOf({"per-fragment", "per-pixel-primitive"})
                    .recordedAs("shading_rate"));
    t.push_back(O("--max-layers", kRender, K::Integer, &S::maxLayers,
                  "Transparent t-fragments kept per sample")
                    .in(1, 255)
                    .recordedAs("max_layers"));
    t.push_back(O("--heatmaps", kRender, K::Flag, &S::heatMaps,
                  "Also write per-pixel and per-tile heat maps of the rasterizer's work (the "
                  "methods that count per pixel)")
                    .recordedAs("heatmaps"));
    t.push_back(O("--no-motion", kInfo | kRender | kSweep, K::Flag, &S::noMotion,
                  "Do not simulate motion blur")
                    .recordedAs("no_motion"));
    t.push_back(O("--no-defocus", kInfo | kRender | kSweep, K::Flag, &S::noDefocus,
                  "Do not simulate defocus blur")
                    .recordedAs("no_defocus"));
    t.push_back(O("--no-transparency", kInfo | kRender | kSweep, K::Flag, &S::noTransparency,
                  "Treat every surface as opaque")
                    .recordedAs("no_transparency"));
    t.push_back(O("-t,--time", kTess, K::Real, &S::time, "Shutter time of the written positions")
                    .in(0, 1)
                    .recordedAs("time"));
    t.push_back(
        O("--stats", kTess, K::OutputFile, &S::stats, "Also write the counters as stats JSON"));
    t.push_back(O("--hw", kRender | kSweep | kExplore, K::InputPath, &S::hardware,
                  "Hardware configuration JSON for the timing model (default: the built-in "
                  "pipeline/hw/default.json)"));
    t.push_back(O("--trace", kRender, K::OutputFile, &S::trace,
                  "Write the per-patch timeline as Chrome trace-event JSON"));
    t.push_back(O("--cases", kVerify, K::Integer, &S::cases, "Random cases per model")
                    .in(1, double(std::int64_t(1) << 40)));
    t.push_back(
        O("--seed", kVerify, K::Integer, &S::seed, "Seed of the random cases").in(0, kMaxSeed));
    t.push_back(O("--witness-every", kVerify, K::Integer, &S::witnessEvery,
                  "Check the exact truth with sampled rays on every Nth case (0: never)")
                    .in(0, 1 << 30));
    t.push_back(O("--format", kVerify, K::Text, &S::formats,
                  "Also verify every site's variants in these number formats, conservative "
                  "(rounded outward or error-bounded) and naive (comma-separated: fp16, bf16, "
                  "fixedI.F; all: fp16,bf16,fixed16.8)"));
    t.push_back(O("--csv", kVerify, K::OutputFile, &S::csv, "Write one row per case and variant"));
    t.push_back(O("--summary", kVerify, K::OutputFile, &S::summary,
                  "Write one row per variant (for scripts/plot_tile_tests.py)"));
    t.push_back(O("--family", kVerify, K::Text, &S::family,
                  "The box cases' family: mixed (the random mix), or one hard case pushed to its "
                  "extreme: near-plane, far-depth, huge-motion, tiny, huge, wide-lens"));
    t.push_back(O("--replay", kVerify, K::Text, &S::replay,
                  "Print one case (e.g. lens:1234) in full and every variant's answer"));
    t.push_back(O("--threads", kScenes | kVerify, K::Integer, &S::threads,
                  "Worker threads (0: all cores; under mpirun, this rank's share of them)")
                    .in(0, 4096));
    t.push_back(O("--memory-budget-mib", kFilms, K::Integer, &S::memoryBudgetMiB,
                  "MiB the film's samples and the rasterizer's tile scratch may take")
                    .in(1, double(std::int64_t(1) << 30))
                    .recordedAs("memory_budget_mib"));
    t.push_back(
        O("-q,--quiet", kTess | kRender, K::Flag, &S::quiet, "Do not print the counter table"));
    t.push_back(O("--no-progress", kRender | kSweep | kExplore, K::Flag, &S::noProgress,
                  "No progress bar"));
    return t;
}

std::string rangeText(const JobOption& o) {
    char text[96];
    std::snprintf(text, sizeof text, "%c%.10g, %.10g%c", o.loOpen ? '(' : '[', o.lo, o.hi,
                  o.hiOpen ? ')' : ']');
    return text;
}

std::string inQuotes(const std::string& s) {
    return "'" + s + "'";
}

std::string joined(const std::vector<std::string>& items) {
    std::string text;
    for (const std::string& item : items) text += (text.empty() ? "" : ", ") + item;
    return text;
}

// One value of a row's element kind, or an error message.
std::string parseInteger(const JobOption& o, const std::string& text, std::int64_t& out) {
    const char* end = text.data() + text.size();
    const auto [ptr, ec] = std::from_chars(text.data(), end, out);
    if (ec != std::errc() || ptr != end)
        return "expected a whole number in " + rangeText(o) + ", found " + inQuotes(text);
    if (double(out) < o.lo || double(out) > o.hi)
        return std::to_string(out) + " is outside " + rangeText(o);
    if (o.odd && out % 2 == 0) return std::to_string(out) + " is even; it must be odd";
    return {};
}

std::string parseReal(const JobOption& o, const std::string& text, double& out) {
    const char* end = text.data() + text.size();
    const auto [ptr, ec] = std::from_chars(text.data(), end, out);
    if (ec != std::errc() || ptr != end || !std::isfinite(out))
        return "expected a finite number in " + rangeText(o) + ", found " + inQuotes(text);
    // Every real option is held as a float: the range must hold for the value it becomes.
    const double held = double(float(out));
    const bool below = o.loOpen ? !(held > o.lo) : !(held >= o.lo);
    const bool above = o.hiOpen ? !(held < o.hi) : !(held <= o.hi);
    if (below || above)
        return inQuotes(text) + " is outside " + rangeText(o) +
               (held != out ? " as a single-precision number" : "");
    out = held;
    return {};
}

std::string parseName(const JobOption& o, const std::string& text) {
    for (const std::string& c : o.choices)
        if (c == text) return {};
    return inQuotes(text) + " is not one of " + joined(o.choices);
}

// Items of a comma-separated list; an empty item (",,", a leading or trailing comma) is an error.
std::string splitList(const std::string& text, std::vector<std::string>& items) {
    std::string item;
    std::istringstream in(text);
    while (std::getline(in, item, ',')) items.push_back(item);
    if (!text.empty() && text.back() == ',') items.push_back({});
    for (const std::string& i : items)
        if (i.empty()) return "empty item in the list " + inQuotes(text);
    if (items.empty()) return "needs at least one value";
    return {};
}

// "4,4" and "2,2.0" alike: a repeated value would give two runs the same name.
template <class T>
std::string checkDistinct(const std::vector<T>& values, const std::string& text) {
    const std::set<T> distinct(values.begin(), values.end());
    if (distinct.size() != values.size()) return "the list " + inQuotes(text) + " repeats an item";
    return {};
}

std::string checkPath(const JobOption& o, const std::string& text) {
    // A name of only blanks is as good as none: it would make a file nobody can see is there.
    if (text.find_first_not_of(" \t\n\r") == std::string::npos)
        return o.kind == K::OutputFolder ? "empty folder name"
               : o.kind == K::InputPath  ? "empty file name"
                                         : "empty output file name";
    return {};
}

std::string applyList(const JobOption& o, const std::string& text, JobSettings& s);
std::string checkSweepAxis(const std::string& text, SweepAxis* out = nullptr);

// Parses `text` into the row's field of `s`; returns an error message, empty when accepted.
std::string apply(const JobOption& o, const std::string& text, JobSettings& s) {
    std::string error;
    switch (o.kind) {
        case K::Flag:
            s.*std::get<bool S::*>(o.field) = true;
            return {};
        case K::Integer: {
            std::int64_t v = 0;
            if (!(error = parseInteger(o, text, v)).empty()) return error;
            if (auto* f = std::get_if<int S::*>(&o.field))
                s.*(*f) = int(v);
            else
                s.*std::get<std::int64_t S::*>(o.field) = v;
            return {};
        }
        case K::Real: {
            double v = 0;
            if (!(error = parseReal(o, text, v)).empty()) return error;
            s.*std::get<float S::*>(o.field) = float(v);
            return {};
        }
        case K::Name:
            if (!(error = parseName(o, text)).empty()) return error;
            s.*std::get<std::string S::*>(o.field) = text;
            return {};
        case K::Text:
            if (text.empty()) return "empty value";
            s.*std::get<std::string S::*>(o.field) = text;
            return {};
        case K::Variation:
            if (!(error = checkSweepAxis(text)).empty()) return error;
            for (const std::string& given : s.*std::get<std::vector<std::string> S::*>(o.field))
                if (given.substr(0, given.find('=')) == text.substr(0, text.find('=')))
                    return "varies " + inQuotes(text.substr(0, text.find('='))) + " twice";
            (s.*std::get<std::vector<std::string> S::*>(o.field)).push_back(text);
            return {};
        case K::InputPath:
        case K::OutputFile:
        case K::OutputFolder:
            if (!(error = checkPath(o, text)).empty()) return error;
            if (auto* list = std::get_if<std::vector<std::string> S::*>(&o.field))
                (s.*(*list)).push_back(text);
            else
                s.*std::get<std::string S::*>(o.field) = text;
            return {};
        default:
            return applyList(o, text, s);
    }
}

// Parses a comma-separated list into the row's field of `s`; returns an error message.
std::string applyList(const JobOption& o, const std::string& text, JobSettings& s) {
    std::string error;
    std::vector<std::string> items;
    if (!(error = splitList(text, items)).empty()) return error;
    if (o.kind == K::NameList) {
        for (const std::string& item : items)
            if (!(error = parseName(o, item)).empty()) return error;
        if (!(error = checkDistinct(items, text)).empty()) return error;
        s.*std::get<std::vector<std::string> S::*>(o.field) = items;
    } else if (o.kind == K::IntegerList) {
        std::vector<int>& out = s.*std::get<std::vector<int> S::*>(o.field);
        out.clear();
        for (const std::string& item : items) {
            std::int64_t v = 0;
            if (!(error = parseInteger(o, item, v)).empty()) return error;
            out.push_back(int(v));
        }
        return checkDistinct(out, text);
    } else {
        std::vector<float>& out = s.*std::get<std::vector<float> S::*>(o.field);
        out.clear();
        for (const std::string& item : items) {
            double v = 0;
            if (!(error = parseReal(o, item, v)).empty()) return error;
            out.push_back(float(v));
        }
        return checkDistinct(out, text);
    }
    return {};
}

template <class T>
std::string listText(const std::vector<T>& v) {
    std::ostringstream out;
    for (std::size_t i = 0; i < v.size(); ++i) out << (i ? "," : "") << v[i];
    return out.str();
}

}  // namespace

const char* commandName(Command c) {
    static const char* const kNames[] = {"info",         "tessellate", "render",
                                         "verify-tiles", "sweep",      "explore"};
    return kNames[int(c)];
}

SceneLimits JobSettings::limits() const {
    SceneLimits l;
    l.memoryBudgetBytes = std::uint64_t(memoryBudgetMiB) << 20;
    return l;
}

JobSettings defaultJobSettings(Command c) {
    JobSettings s;
    switch (c) {
        case Command::Render:
            s.output = "out";
            break;
        case Command::Tessellate:
            s.output = "tessellation.obj";
            break;
        case Command::Sweep:
            s.output = "sweep";
            s.methods = {"patch",       "triangle-bbox", "interval",     "interleaved",
                         "postprocess", "hybrid",        "reprojection", "tfragment"};
            s.sppList = {1, 4, 16, 64};
            s.blurList = {1.0f};
            break;
        case Command::Explore:
            s.output = "explore.csv";
            break;
        default:
            break;
    }
    return s;
}

const std::vector<JobOption>& jobOptions() {
    static const std::vector<JobOption> table = makeTable();
    return table;
}

std::string JobOption::longName() const {
    const std::string f = flag;
    const std::size_t comma = f.rfind(',');
    return comma == std::string::npos ? f : f.substr(comma + 1);
}

namespace {

// The names --vary takes: every per-method option's and every rasterizer option's.
std::string sweepAxisNames() {
    std::string names;
    for (const JobOption& o : jobOptions())
        if (!o.methods.empty() && o.takes(Command::Sweep))
            names += (names.empty() ? "" : ", ") + o.longName().substr(2);
    for (const RasterizerOptionField& f : rasterizerOptionFields())
        names += ", " + std::string(f.flag).substr(2);
    return names;
}

// Checks one value of an axis by its option's own rule and gives it as that option reads it back
// ("04" as "4", "0.90" as "0.9"), so two texts of one value are found; returns an error
// message.
std::string checkAxisValue(const SweepAxis& axis, const std::string& value, std::string& held) {
    // A blank would go into file names and CSV fields; the rasterizer's JSON reading skips it.
    if (value.find_first_of(" \t\n\r") != std::string::npos) return inQuotes(value) + " has blanks";
    std::string error;
    if (axis.option) {
        JobSettings scratch;
        if ((error = apply(*axis.option, value, scratch)).empty())
            held = jobOptionValue(*axis.option, scratch);
        return error;
    }
    RasterizerOptions scratch;
    if ((error = axis.field->set(scratch, optionValueFromText(value))).empty())
        held = axis.field->get(scratch);
    return error;
}

std::string checkSweepAxis(const std::string& text, SweepAxis* out) {
    const std::size_t eq = text.find('=');
    if (eq == std::string::npos || eq == 0)
        return "expected NAME=V1,V2,..., found " + inQuotes(text);
    SweepAxis axis;
    axis.name = text.substr(0, eq);
    for (const JobOption& o : jobOptions())
        if (!o.methods.empty() && o.takes(Command::Sweep) && o.longName() == "--" + axis.name)
            axis.option = &o;
    for (const RasterizerOptionField& f : rasterizerOptionFields())
        if (f.flag == "--" + axis.name) axis.field = &f;
    if (axis.option) {
        axis.methods = axis.option->methods;
    } else if (axis.field) {
        for (const VisibilityMethod* m : visibilityMethods())  // the patent's design options
            if (m->rasterizesPatches()) axis.methods.push_back(m->name());
    } else {
        return inQuotes(axis.name) + " is not a method parameter; one of " + sweepAxisNames();
    }
    std::string error = splitList(text.substr(eq + 1), axis.values);
    if (!error.empty()) return axis.name + ": " + error;
    std::vector<std::string> held(axis.values.size());
    for (std::size_t i = 0; i < axis.values.size(); ++i)
        if (!(error = checkAxisValue(axis, axis.values[i], held[i])).empty())
            return axis.name + ": " + error;
    if (!(error = checkDistinct(held, text.substr(eq + 1))).empty())
        return axis.name + ": " + error;
    if (out) *out = std::move(axis);
    return {};
}

}  // namespace

SweepAxis parseSweepAxis(const std::string& text) {
    SweepAxis axis;
    const std::string error = checkSweepAxis(text, &axis);
    if (!error.empty()) throw InputError("command line", "--vary", error);
    return axis;
}

void applyJobOption(const JobOption& option, const std::string& text, JobSettings& settings) {
    const std::string error = apply(option, text, settings);
    if (!error.empty()) throw InputError("command line", option.longName(), error);
}

std::string jobOptionValue(const JobOption& o, const JobSettings& s) {
    return std::visit(
        [&s](auto field) -> std::string {
            const auto& v = s.*field;
            using T = std::decay_t<decltype(v)>;
            if constexpr (std::is_same_v<T, bool>) {
                return v ? "true" : "false";
            } else if constexpr (std::is_same_v<T, std::string>) {
                return v;
            } else if constexpr (std::is_same_v<T, float>) {
                // The shortest text that reads back as this float: 0.9f shows as "0.9".
                char text[32];
                const auto end = std::to_chars(text, text + sizeof text, v).ptr;
                return std::string(text, end);
            } else if constexpr (std::is_arithmetic_v<T>) {
                return std::to_string(v);
            } else {
                return listText(v);
            }
        },
        o.field);
}

namespace {

// What a row takes, in words, for the docs.
std::string valueDescription(const JobOption& o) {
    std::string value;
    switch (o.kind) {
        case K::Flag:
            value = "flag";
            break;
        case K::Integer:
            value = "whole number in " + rangeText(o);
            break;
        case K::Real:
            value = "number in " + rangeText(o);
            break;
        case K::Name:
            value = "one of " + joined(o.choices);
            break;
        case K::InputPath:
            value = "file to read";
            break;
        case K::OutputFile:
            value = "file to write";
            break;
        case K::OutputFolder:
            value = "folder to write into";
            break;
        case K::Text:
            value = "text";
            break;
        case K::Variation:
            value = "NAME=V1,V2,...";
            break;
        case K::IntegerList:
            value = "list of whole numbers in " + rangeText(o);
            break;
        case K::RealList:
            value = "list of numbers in " + rangeText(o);
            break;
        case K::NameList:
            value = "list of " + joined(o.choices);
            break;
    }
    return o.odd ? value + ", odd" : value;
}

}  // namespace

std::string jobOptionsMarkdown() {
    std::ostringstream out;
    out << "# Command-line options\n\n"
           "Generated from the options table (`pipeline/app/job_options.cpp`) by `patchsim "
           "options`; a test keeps this page equal to it. Every value is checked by its row's "
           "rule: numbers must be finite and in range, paths must not be empty, lists must not "
           "have empty or repeated items. A refused value is one error line naming the option, "
           "and exit code 2.\n";
    for (int c = 0; c < kCommandCount; ++c) {
        const Command command = Command(c);
        const JobSettings defaults = defaultJobSettings(command);
        out << "\n## patchsim " << commandName(command)
            << "\n\n| option | value | default | stats.json | meaning |\n|---|---|---|---|---|\n";
        for (const JobOption& o : jobOptions()) {
            if (!o.takes(command)) continue;
            const std::string value = valueDescription(o);
            const std::string def = o.kind == K::Flag ? "" : jobOptionValue(o, defaults);
            out << "| `" << o.flag << "` | " << value << " | "
                << (def.empty() ? "" : "`" + def + "`") << " | "
                << (o.statsKey ? std::string("`") + o.statsKey + "`" : "") << " | " << o.help
                << " |\n";
        }
        if (command == Command::Render) {
            for (const RasterizerOptionField& f : rasterizerOptionFields())
                out << "| `" << f.flag << "` | (rasterizer option) | the scene's | `rasterizer."
                    << f.key << "` | " << f.help << " |\n";
        }
    }
    return out.str();
}

}  // namespace patchsim
