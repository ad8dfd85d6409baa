#pragma once
// Every option of every subcommand, in one table (docs/OPTIONS.md is generated from it).
//
// Representation
// --------------
// `JobSettings` is one flat struct of everything a command line can set, with the defaults a
// command starts from. Each `JobOption` row names its flag, the commands that take it, its help,
// the kind of value (a count, a finite real, a name from a list, a path to read, a file or folder
// to write, a comma-separated list), the range, the key under which stats.json records it, and the
// `JobSettings` field it sets, as a member pointer. The command line hands every text it is given
// to `applyJobOption`, which checks it by the row's one rule and sets the field, so a value is
// refused the same way wherever it comes from: NaN and infinities never pass a range, an empty
// path is never taken for ".", a list never has an empty or repeated item. stats.json writes the
// rows' values back through `jobOptionValue`. The patch rasterizer's own options keep their table
// (core/rasterizer_options.h); `render` takes them as flags too.

#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "backend/image_space/hybrid_motion_blur.h"
#include "backend/image_space/motion_blur_postprocess.h"
#include "backend/image_space/sample_reprojection.h"
#include "backend/tfragment/tfragment_generation.h"
#include "core/scene_reader.h"

namespace patchsim {

enum class Command : std::uint8_t { Info, Tessellate, Render, VerifyTiles, Sweep, Explore };
inline constexpr int kCommandCount = 6;
const char* commandName(Command c);
constexpr unsigned commandBit(Command c) {
    return 1u << unsigned(c);
}

struct JobSettings {
    std::vector<std::string> scenes;  // the positional scene files (empty: the built-in scene)
    std::string output;
    int threads = 0;
    std::int64_t memoryBudgetMiB = 4096;
    bool noMotion = false, noDefocus = false, noTransparency = false;
    bool quiet = false, noProgress = false;
    std::string hardware;
    // render (and the per-method options sweep shares)
    std::string method = "patch";
    int spp = 0, width = 0, height = 0;  // 0: the scene's own film
    int timeStrata = 0;
    std::string bboxBound = "hull";
    int ppTileSize = PostprocessOptions{}.tileSize, ppSamples = PostprocessOptions{}.samples;
    float softZExtent = PostprocessOptions{}.softZExtent;
    float edgeThreshold = HybridOptions{}.edgeThreshold;
    int cameraSteps = ReprojectionOptions{}.cameraSteps;
    int motionSamples = TFragmentOptions{}.motionSamples;
    int tfragmentLimit = TFragmentOptions{}.maxCollected;
    bool timeSampled = false;
    bool noTimeRefinement = false, noZCulling = false;
    std::string filter = "box", shadingRate = "per-fragment";
    int maxLayers = 16;
    bool heatMaps = false;
    std::string trace;
    std::map<std::string, std::string> rasterizer;  // rasterizer option key -> given text
    // tessellate
    float time = 0.0f;
    std::string stats;
    // verify-tiles
    std::int64_t cases = 2000, seed = 1;
    int witnessEvery = 64;
    std::string csv, summary, replay;
    std::string formats;           // --format: number formats whose variants join the run
    std::string family = "mixed";  // --family: the box cases' family
    // sweep
    std::vector<std::string> methods;
    std::vector<int> sppList;
    std::vector<float> blurList;
    std::vector<std::string> vary;  // --vary texts, each checked by parseSweepAxis
    int repeats = 3, convergedSpp = 0;
    // explore
    std::string grid, plots;

    SceneLimits limits() const;
};

// The settings a command starts from (its own default output name, method list, ...).
JobSettings defaultJobSettings(Command c);

enum class ValueKind : std::uint8_t {
    Flag,
    Integer,
    Real,
    Name,  // one of `choices`
    InputPath,
    OutputFile,
    OutputFolder,
    Text,
    Variation,  // "NAME=V1,V2,...": a method parameter's values (sweep --vary), repeatable
    IntegerList,
    RealList,
    NameList,
};

using JobField = std::variant<bool JobSettings::*, int JobSettings::*, std::int64_t JobSettings::*,
                              float JobSettings::*, std::string JobSettings::*,
                              std::vector<std::string> JobSettings::*,
                              std::vector<int> JobSettings::*, std::vector<float> JobSettings::*>;

struct JobOption {
    const char* flag;   // "--soft-z-extent" (CLI11 form: "-o,--output"; "scene" for positionals)
    unsigned commands;  // commandBit()s
    ValueKind kind;
    JobField field;
    const char* help;
    double lo = 0, hi = 0;  // numeric range, closed unless an end is marked open
    bool loOpen = false, hiOpen = false;
    bool odd = false;                  // integers: odd only
    std::vector<std::string> choices;  // names
    const char* statsKey = nullptr;    // key in stats.json's "options" (null: not recorded)
    std::vector<std::string> methods;  // the visibility methods whose parameter it is (sweep axes)

    JobOption(const char* flag_, unsigned commands_, ValueKind kind_, JobField field_,
              const char* help_)
        : flag(flag_), commands(commands_), kind(kind_), field(field_), help(help_) {}
    // The table's rows are written as JobOption(...).in(lo, hi).recordedAs("key") and so on.
    JobOption in(double lo_, double hi_) && {
        lo = lo_;
        hi = hi_;
        return std::move(*this);
    }
    JobOption openBelow() && {
        loOpen = true;
        return std::move(*this);
    }
    JobOption openAbove() && {
        hiOpen = true;
        return std::move(*this);
    }
    JobOption oddOnly() && {
        odd = true;
        return std::move(*this);
    }
    JobOption oneOf(std::vector<std::string> names) && {
        choices = std::move(names);
        return std::move(*this);
    }
    JobOption ofMethods(std::vector<std::string> names) && {
        methods = std::move(names);
        return std::move(*this);
    }
    JobOption recordedAs(const char* key) && {
        statsKey = key;
        return std::move(*this);
    }

    bool takes(Command c) const { return commands & commandBit(c); }
    bool positional() const { return flag[0] != '-'; }
    std::string longName() const;  // "--output" of "-o,--output"
};

const std::vector<JobOption>& jobOptions();

// Checks `text` by the row's rule and sets its field; throws InputError("command line", flag, ...).
void applyJobOption(const JobOption& option, const std::string& text, JobSettings& settings);

// The field's value as text (lists comma-separated), for stats.json and the help's defaults.
std::string jobOptionValue(const JobOption& option, const JobSettings& settings);

// One axis of a sweep (--vary NAME=V1,V2,...): a method parameter and the values it takes. NAME is
// a per-method option's long name without the dashes ("time-strata") or a rasterizer option's
// ("leaf-size", the patch method's design); every value is checked by that option's own rule.
struct SweepAxis {
    std::string name;
    std::vector<std::string> values;
    const JobOption* option = nullptr;                    // a per-method option, or
    const struct RasterizerOptionField* field = nullptr;  // a rasterizer option
    std::vector<std::string> methods;                     // the methods it is a parameter of
};

// Throws InputError("command line", "--vary", ...) when `text` is not a valid axis.
SweepAxis parseSweepAxis(const std::string& text);

// A Markdown page of every command's options (docs/OPTIONS.md).
std::string jobOptionsMarkdown();

}  // namespace patchsim
