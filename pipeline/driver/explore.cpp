#include "pipeline/driver/explore.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "core/counters.h"
#include "core/json_fields.h"
#include "core/rasterizer_options.h"
#include "pipeline/driver/render.h"
#include "pipeline/timing/timing_model.h"
#include "rasterizer/patent/raster_work.h"

namespace patchsim {

namespace fs = std::filesystem;

namespace {

std::string jsonValueText(const Json& v) {
    if (v.is_string()) return v.get<std::string>();
    if (v.is_boolean()) return v.get<bool>() ? "true" : "false";
    if (v.is_number_integer()) return std::to_string(v.get<std::int64_t>());
    char text[32];
    std::snprintf(text, sizeof text, "%g", v.get<double>());
    return text;
}

std::string csvField(std::string text) {
    std::replace(text.begin(), text.end(), ',', ';');
    return text;
}

std::string formatNumber(double v) {
    char text[40];
    std::snprintf(text, sizeof text, "%.10g", v);
    return text;
}

// Mixed-radix enumeration of a cross product (last axis fastest).
std::vector<std::vector<std::size_t>> crossProduct(const std::vector<GridAxis>& axes) {
    std::vector<std::vector<std::size_t>> out{{}};
    for (const GridAxis& axis : axes) {
        std::vector<std::vector<std::size_t>> next;
        for (const auto& prefix : out)
            for (std::size_t v = 0; v < axis.values.size(); ++v) {
                next.push_back(prefix);
                next.back().push_back(v);
            }
        out = std::move(next);
    }
    return out;
}

}  // namespace

ExploreGrid parseExploreGrid(std::string_view text, const std::string& path) {
    const Json json = parseJson(text, path);
    ExploreGrid grid;
    grid.path = path;
    ObjectReader root(json, "", path);
    auto readAxis = [&](ObjectReader& section, const std::string& key, bool hardware) {
        const Json* values = section.find(key);
        const std::string field = section.fieldName(key);
        if (!values->is_array() || values->empty())
            section.fail(field, "expected a non-empty array of values");
        GridAxis axis{key, hardware, {}, {}};
        for (std::size_t i = 0; i < values->size(); ++i) {
            const Json& v = (*values)[i];
            if (!v.is_primitive() || v.is_null())
                section.fail(field + "[" + std::to_string(i) + "]",
                             "expected a number, a string or a boolean, found " + v.dump());
            axis.values.push_back(jsonValueText(v));
            axis.json.push_back(v);
        }
        return axis;
    };
    // A value given twice (8 and 8, 1 and 1.0) would make every point of it twice: duplicate
    // rows, as sweep refuses for its lists. `same(i, j)` compares the values as their reader
    // takes them.
    auto refuseRepeats = [&](const ObjectReader& section, const GridAxis& axis, auto same) {
        for (std::size_t i = 0; i < axis.json.size(); ++i)
            for (std::size_t j = 0; j < i; ++j)
                if (same(i, j))
                    section.fail(section.fieldName(axis.name) + "[" + std::to_string(i) + "]",
                                 "the value " + axis.values[i] + " repeats " +
                                     section.fieldName(axis.name) + "[" + std::to_string(j) +
                                     "]: every point would come out twice");
    };
    if (const Json* raster = root.find("rasterizer")) {
        ObjectReader section(*raster, "rasterizer", path);
        for (const RasterizerOptionField& option : rasterizerOptionFields()) {  // table order
            if (!raster->contains(option.key)) continue;
            GridAxis axis = readAxis(section, option.key, false);
            std::vector<std::string> taken;  // each value as the option holds it
            for (std::size_t i = 0; i < axis.json.size(); ++i) {
                RasterizerOptions probe;
                const std::string error = option.set(probe, axis.json[i]);
                if (!error.empty())
                    section.fail(section.fieldName(option.key) + "[" + std::to_string(i) + "]",
                                 error);
                taken.push_back(option.get(probe));
            }
            refuseRepeats(section, axis,
                          [&](std::size_t i, std::size_t j) { return taken[i] == taken[j]; });
            grid.rasterAxes.push_back(std::move(axis));
        }
        section.finish();
    }
    if (const Json* hw = root.find("hardware")) {
        ObjectReader section(*hw, "hardware", path);
        for (auto it = hw->begin(); it != hw->end(); ++it) {
            GridAxis axis = readAxis(section, it.key(), true);
            // The stages' fields are checked here; a memory field depends on the other fields of
            // the job's memory section, so every point is checked against the job's hardware
            // file by checkGridHardware.
            if (!it.key().starts_with("memory.")) {
                HardwareConfig probe = defaultHardwareConfig();
                for (std::size_t i = 0; i < axis.json.size(); ++i)
                    setHardwareParameter(
                        probe, it.key(), axis.json[i], path,
                        section.fieldName(it.key()) + "[" + std::to_string(i) + "]");
            }
            // Hardware values are numbers, and nlohmann compares 1 and 1.0 as numbers.
            refuseRepeats(section, axis, [&](std::size_t i, std::size_t j) {
                return axis.json[i] == axis.json[j];
            });
            grid.hardwareAxes.push_back(std::move(axis));
        }
    }
    if (auto film = root.object("film")) {
        grid.width = int(film->integer("width", 0, 1, 16384));
        grid.height = int(film->integer("height", 0, 1, 16384));
        grid.samplesPerPixel = int(film->integer("spp", 0, 1, 4096));
        film->finish();
    }
    root.finish();
    return grid;
}

SceneDesc jobScene(const std::vector<SceneDesc>& scenes, const ExploreGrid& grid,
                   const ExploreJob& job, const SceneLimits& limits) {
    SceneDesc scene = scenes[job.scene];
    for (std::size_t a = 0; a < grid.rasterAxes.size(); ++a) {
        const GridAxis& axis = grid.rasterAxes[a];
        findRasterizerOptionField(axis.name)->set(scene.rasterizer, axis.json[job.rasterChoice[a]]);
    }
    scene.rasterizer.validate(grid.path);
    if (grid.width) scene.film.width = grid.width;
    if (grid.height) scene.film.height = grid.height;
    if (grid.samplesPerPixel) scene.film.samplesPerPixel = grid.samplesPerPixel;
    checkMemoryBudget(scene.film, limits, grid.path, "film");
    return scene;
}

namespace {

RenderOptions jobRenderOptions(int threads, const SceneLimits& limits) {
    RenderOptions options;
    options.threads = threads;
    options.memoryBudgetBytes = limits.memoryBudgetBytes;
    return options;
}

}  // namespace

namespace {

// The hardware of one grid point: the job's file with the point's values.
HardwareConfig gridPointHardware(const ExploreGrid& grid, const HardwareConfig& hardware,
                                 const std::vector<std::size_t>& choice) {
    std::vector<HardwareParameter> parameters;
    std::string point;
    for (std::size_t a = 0; a < grid.hardwareAxes.size(); ++a) {
        const GridAxis& axis = grid.hardwareAxes[a];
        parameters.push_back({axis.name, axis.json[choice[a]],
                              "hardware." + axis.name + "[" + std::to_string(choice[a]) + "]"});
        const nlohmann::json& value = axis.json[choice[a]];
        point += (a ? ", " : "") + axis.name + " = " +
                 (value.is_string() ? value.dump() : axis.values[choice[a]]);
    }
    HardwareConfig hw = hardware;
    try {
        setHardwareParameters(hw, parameters, grid.path);
    } catch (const InputError& e) {
        // The point's other values may be what makes this one wrong: name the point.
        throw InputError(grid.path, e.field(), e.message() + " (at the grid point " + point + ")");
    }
    return hw;
}

}  // namespace

void checkGridHardware(const ExploreGrid& grid, const HardwareConfig& hardware) {
    for (const auto& choice : crossProduct(grid.hardwareAxes))
        gridPointHardware(grid, hardware, choice);
}

std::vector<ExploreJob> exploreJobs(std::size_t sceneCount, const ExploreGrid& grid) {
    std::vector<ExploreJob> jobs;
    const auto raster = crossProduct(grid.rasterAxes);
    for (std::size_t s = 0; s < sceneCount; ++s)
        for (const auto& choice : raster) jobs.push_back({s, choice});
    return jobs;
}

std::string exploreCsvHeader(const ExploreGrid& grid) {
    std::string header = "scene";
    for (const GridAxis& a : grid.rasterAxes) header.append(",").append(a.name);
    for (const GridAxis& a : grid.hardwareAxes) header.append(",").append(a.name);
    header +=
        ",total_cycles,microseconds,bottleneck,bottleneck_utilisation,sample_test_efficiency,"
        "patches_over_scratch_budget,dram_bytes,dram_row_hit_rate,energy_nj";
    for (const auto& [name, value] : CounterRegistry::instance().snapshot().byName())
        header.append(",").append(name);
    return header;
}

std::vector<ExploreRow> runExploreJob(const std::vector<SceneDesc>& scenes, const ExploreGrid& grid,
                                      const HardwareConfig& baseHardware, std::size_t jobIndex,
                                      int threads, const SceneLimits& limits) {
    const ExploreJob job = exploreJobs(scenes.size(), grid)[jobIndex];
    const SceneDesc scene = jobScene(scenes, grid, job, limits);
    RenderOptions options = jobRenderOptions(threads, limits);
    options.memoryTrace = baseHardware.memory.has_value();
    CounterRegistry::instance().reset();
    const RenderResult result = renderScene(scene, options);
    const CounterValues counters = CounterRegistry::instance().snapshot();
    const double ste = counters.ratio(sampleTestEfficiency());
    std::string prefix = csvField(scene.path);
    for (std::size_t a = 0; a < grid.rasterAxes.size(); ++a)
        prefix.append(",").append(grid.rasterAxes[a].values[job.rasterChoice[a]]);
    std::vector<ExploreRow> rows;
    for (const auto& choice : crossProduct(grid.hardwareAxes)) {
        const HardwareConfig hw = gridPointHardware(grid, baseHardware, choice);
        ExploreRow row{jobIndex, job.rasterChoice, 0, prefix};
        for (std::size_t a = 0; a < grid.hardwareAxes.size(); ++a) {
            row.csv.append(",").append(grid.hardwareAxes[a].values[choice[a]]);
            row.choice.push_back(choice[a]);
        }
        const FrameTiming frame = timeFrame(result, hw);
        const TimingReport& t = frame.timing;
        row.totalCycles = t.totalCycles;
        for (const std::string& field :
             {formatNumber(t.totalCycles), formatNumber(t.microseconds()),
              std::string(t.bottleneckName()), formatNumber(t.bottleneckUtilisation()),
              formatNumber(ste), std::to_string(t.patchesOverBudget),
              frame.memory ? std::to_string(frame.memory->dramBytes()) : std::string(),
              frame.memory && frame.memory->config.dramBanks.modelled()
                  ? formatNumber(frame.memory->dramBanks.rowHitRate())
                  : std::string(),
              formatNumber(frame.energy.totalPicojoules() / 1e3)})
            row.csv.append(",").append(field);
        for (const auto& [name, value] : counters.byName())
            row.csv.append(",").append(std::to_string(value));
        rows.push_back(std::move(row));
    }
    return rows;
}

std::string packExploreRows(const std::vector<ExploreRow>& rows) {
    constexpr char kUnit = '\x1f';
    std::string text;
    for (const ExploreRow& r : rows) {
        text += std::to_string(r.job) + kUnit + formatNumber(r.totalCycles) + kUnit;
        for (std::size_t c : r.choice) text += std::to_string(c) + ' ';
        text += kUnit + r.csv + '\n';
    }
    return text;
}

std::vector<ExploreRow> unpackExploreRows(const std::string& text) {
    std::vector<ExploreRow> rows;
    std::istringstream lines(text);
    std::string line;
    while (std::getline(lines, line)) {
        std::istringstream fields(line);
        std::string job, cycles, choice, csv;
        std::getline(fields, job, '\x1f');
        std::getline(fields, cycles, '\x1f');
        std::getline(fields, choice, '\x1f');
        std::getline(fields, csv);
        ExploreRow row{std::stoul(job), {}, std::strtod(cycles.c_str(), nullptr), csv};
        std::istringstream indices(choice);
        for (std::size_t c; indices >> c;) row.choice.push_back(c);
        rows.push_back(std::move(row));
    }
    return rows;
}

void checkDistinctScenes(const std::vector<std::string>& paths) {
    // One file spelt two ways ("m.json", "./m.json", its absolute path, a link to it) is the
    // same scene: compared by normalised absolute path, and by identity where both exist.
    const auto normal = [](const std::string& p) {
        std::error_code error;
        const fs::path absolute = fs::absolute(p, error);
        return (error ? fs::path(p) : absolute).lexically_normal();
    };
    const auto sameFile = [&](const std::string& a, const std::string& b) {
        if (normal(a) == normal(b)) return true;
        std::error_code error;  // false when either is not a file (the built-in scene)
        return fs::equivalent(a, b, error);
    };
    for (std::size_t i = 0; i < paths.size(); ++i)
        for (std::size_t j = 0; j < i; ++j) {
            if (!sameFile(paths[j], paths[i])) continue;
            throw InputError("command line", "scenes",
                             paths[i] == paths[j]
                                 ? "names '" + paths[i] + "' twice"
                                 : "'" + paths[j] + "' and '" + paths[i] + "' are the same file");
        }
}

void runExploreJobs(const std::vector<SceneDesc>& scenes, const ExploreGrid& grid,
                    const HardwareConfig& baseHardware, int threads, const SceneLimits& limits,
                    const std::function<bool(std::size_t)>& mine,
                    const std::function<void(std::size_t, const std::vector<ExploreRow>&)>& emit) {
    std::vector<std::string> paths;
    for (const SceneDesc& scene : scenes) paths.push_back(scene.path);
    checkDistinctScenes(paths);
    const std::vector<ExploreJob> jobs = exploreJobs(scenes.size(), grid);
    // Every job's tiles and memory before the first render.
    for (const ExploreJob& job : jobs) {
        SceneDesc scene = jobScene(scenes, grid, job, limits);
        scene.path = grid.path;  // the grid chose the refused combination
        checkRender(scene, jobRenderOptions(threads, limits));
    }
    for (std::size_t j = 0; j < jobs.size(); ++j)
        if (mine(j)) emit(j, runExploreJob(scenes, grid, baseHardware, j, threads, limits));
}

}  // namespace patchsim
