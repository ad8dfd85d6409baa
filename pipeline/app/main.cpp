// The patchsim command: one binary, one subcommand per job (docs/OPTIONS.md lists every option).
// Each subcommand's options come from one table (job_options.h): CLI11 only collects the texts;
// the table's rules check them, so every error is one line naming the option, exit code 2.

#include <CLI/CLI.hpp>
#include <iostream>

#include "core/error.h"
#include "core/output_set.h"
#include "core/rasterizer_options.h"
#include "pipeline/app/commands.h"

namespace {

using namespace patchsim;

struct GivenText {
    const JobOption* option;
    std::string text;
};

// One subcommand: its CLI11 app, its settings, and the texts given for its options.
struct Subcommand {
    Command command = Command::Render;
    CLI::App* app = nullptr;
    JobSettings settings;
    std::vector<GivenText> given;
    std::vector<std::pair<std::string, std::string>> rasterizer;  // key, text
};

void addTableOptions(Subcommand& sub) {
    const JobSettings defaults = defaultJobSettings(sub.command);
    for (const JobOption& o : jobOptions()) {
        if (!o.takes(sub.command)) continue;
        std::vector<GivenText>& given = sub.given;
        CLI::Option* added = nullptr;
        if (o.kind == ValueKind::Flag) {
            added = sub.app->add_flag_callback(
                o.flag,
                [&given, &o] {
                    given.push_back({&o, "true"});
                },
                o.help);
        } else if (o.kind == ValueKind::Variation) {
            // Repeatable, one value each time: a list would take the scenes after it.
            added = sub.app->add_option_function<std::vector<std::string>>(
                o.flag,
                [&given, &o](const std::vector<std::string>& texts) {
                    for (const std::string& t : texts) given.push_back({&o, t});
                },
                o.help);
            added->allow_extra_args(false);
        } else if (o.positional() && std::string(o.flag) == "scenes") {
            added = sub.app->add_option_function<std::vector<std::string>>(
                o.flag,
                [&given, &o](const std::vector<std::string>& texts) {
                    for (const std::string& t : texts) given.push_back({&o, t});
                },
                o.help);
        } else {
            added = sub.app->add_option_function<std::string>(
                o.flag,
                [&given, &o](const std::string& t) {
                    given.push_back({&o, t});
                },
                o.help);
            const std::string shown = jobOptionValue(o, defaults);
            if (!shown.empty() && !o.positional()) added->default_str(shown);
        }
        if (std::string(o.flag) == "--grid") added->required();
    }
}

void addRasterizerOptions(Subcommand& sub) {
    for (const RasterizerOptionField& field : rasterizerOptionFields()) {
        auto& texts = sub.rasterizer;
        sub.app->add_option_function<std::string>(
            field.flag,
            [&texts, key = field.key](const std::string& v) {
                texts.push_back({key, v});
            },
            field.help);
    }
}

// Checks every given text by its row's rule, in the order given (a repeated option: the last).
JobSettings settingsOf(const Subcommand& sub) {
    JobSettings s = defaultJobSettings(sub.command);
    bool scenesGiven = false;
    for (const GivenText& g : sub.given) {
        const bool sceneList = std::string(g.option->flag) == "scenes";
        if (sceneList && !scenesGiven) s.scenes.clear();
        scenesGiven = scenesGiven || sceneList;
        applyJobOption(*g.option, g.text, s);
    }
    for (const auto& [key, text] : sub.rasterizer) s.rasterizer[key] = text;
    return s;
}

// Commands that do not split their work over MPI ranks would run whole in every rank, racing on
// the same output files: refused under mpirun (rank 0 says why).
int refuseUnderMpi(Command c, const MpiContext& mpi) {
    if (mpi.rank() == 0)
        std::cerr << "patchsim: error: command line: " << commandName(c)
                  << ": does not run under mpirun (" << mpi.size()
                  << " ranks); only render (not --method tfragment) and explore split their work "
                     "over ranks (docs/EXPLORE.md). Run it as one process.\n";
    return 2;
}

int run(const Subcommand& sub, const MpiContext& mpi) {
    const bool splitsOverRanks = sub.command == Command::Render || sub.command == Command::Explore;
    if (mpi.size() > 1 && !splitsOverRanks) return refuseUnderMpi(sub.command, mpi);
    JobSettings s;
    try {
        s = settingsOf(sub);
    } catch (const InputError& e) {
        // Every rank has the same command line: one says what is wrong with it.
        if (mpi.rank() == 0) std::cerr << "patchsim: error: " << e.what() << "\n";
        return 2;
    }
    switch (sub.command) {
        case Command::Info:
            return runInfo(s);
        case Command::Tessellate:
            return runTessellate(s);
        case Command::Render:
            return runRender(s, mpi);
        case Command::VerifyTiles:
            return runVerifyTiles(s);
        case Command::Sweep:
            return runSweepCommand(s);
        case Command::Explore:
            return runExplore(s, mpi);
    }
    return 3;
}

// "--trace=" would make CLI11 take the next argument as the value: an empty value is refused,
// as it is when written "--trace ''".
void refuseEmptyAssignments(int argc, char** argv) {
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        if (arg.rfind("--", 0) == 0 && arg.size() > 3 && arg.back() == '=' &&
            arg.find('=') == arg.size() - 1)
            throw CLI::ValidationError(arg.substr(0, arg.size() - 1), "empty value");
    }
}

// The arguments nothing took, each quoted (an empty one shows as '').
std::string extrasText(const CLI::App& app) {
    const std::vector<std::string> extras = app.remaining(/*recurse=*/true);
    std::string text =
        extras.size() == 1 ? "an argument nothing takes:" : "arguments nothing takes:";
    for (const std::string& e : extras) text += " '" + e + "'";
    return text;
}

const char* describe(Command c) {
    switch (c) {
        case Command::Info:
            return "Print a scene's patches, triangles, effects and mode";
        case Command::Tessellate:
            return "Run IA, VS, HS, TS and DS; write the mesh as OBJ";
        case Command::Render:
            return "Render a frame: image.exr, image.png and stats.json";
        case Command::VerifyTiles:
            return "Check the tile tests against exact ground truth (docs/TILE_TESTS.md)";
        case Command::Sweep:
            return "Accuracy against time: every method at every sample count (docs/ACCURACY.md)";
        case Command::Explore:
            return "Design-space sweep: one CSV row per grid point";
    }
    return "";
}

}  // namespace

int main(int argc, char** argv) {
    const MpiContext mpi(argc, argv);
    installInterruptCleanup();
    CLI::App app{
        "patchsim: a cycle-approximate D3D11-style pipeline with a patch rasterizer for "
        "motion and defocus blur (US 8,791,945)"};
    app.require_subcommand(0, 1);
    std::vector<Subcommand> subs(kCommandCount);
    for (int c = 0; c < kCommandCount; ++c) {
        Subcommand& sub = subs[std::size_t(c)];
        sub.command = Command(c);
        sub.app = app.add_subcommand(commandName(sub.command), describe(sub.command));
        addTableOptions(sub);
        if (sub.command == Command::Render) addRasterizerOptions(sub);
    }
    CLI::App* options = app.add_subcommand(
        "options", "Print every subcommand's options as Markdown (docs/OPTIONS.md)");
    // Set after the subcommands, which would otherwise inherit it.
    app.footer(
        "With no subcommand, patchsim renders the built-in default scene (motion blur and "
        "defocus) into out/ (out/image.exr, out/image.png, out/stats.json), as "
        "`patchsim render -o out` would.");
    try {
        refuseEmptyAssignments(argc, argv);
        app.parse(argc, argv);
    } catch (const CLI::ExtrasError& e) {
        if (mpi.rank() == 0)
            std::cerr << "patchsim: error: command line: " << extrasText(app) << "\n";
        return 2;
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        // One line, like every other error; a bad command line is bad input (exit 2).
        if (mpi.rank() == 0) std::cerr << "patchsim: error: command line: " << e.what() << "\n";
        return 2;
    }
    try {
        if (*options) {
            std::cout << jobOptionsMarkdown();
            return 0;
        }
        for (const Subcommand& sub : subs)
            if (*sub.app) return run(sub, mpi);
        // No subcommand: the main job, a render of the built-in default scene into out/.
        Subcommand render;
        render.command = Command::Render;
        return run(render, mpi);
    } catch (const InputError& e) {
        std::cerr << "patchsim: error: " << e.what() << "\n";
        return 2;
    } catch (const std::exception& e) {
        std::cerr << "patchsim: internal error: " << e.what() << "\n";
        return 3;
    }
}
