#include "pipeline/driver/plots.h"

#include <sys/wait.h>

#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <vector>

#include "core/output_set.h"
#include "core/text_file.h"

namespace patchsim {

namespace {

constexpr const char* kScript = "plot_results.py";

// `text` as one shell word, whatever it holds.
std::string shellQuoted(const std::string& text) {
    std::string quoted = "'";
    for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return quoted + "'";
}

// The Python with matplotlib: PATCHSIM_PYTHON when set, else Debian's (the one install-deps.sh
// gives matplotlib to; a python3 earlier on the path, such as pyenv's, often lacks it), else the
// one on the path.
std::string pythonWithMatplotlib() {
    std::vector<std::string> candidates = {"/usr/bin/python3", "python3"};
    if (const char* chosen = std::getenv("PATCHSIM_PYTHON")) candidates = {chosen};
    for (const std::string& python : candidates) {
        const std::string probe =
            shellQuoted(python) + " -c 'import matplotlib, numpy' > /dev/null 2>&1";
        if (std::system(probe.c_str()) == 0) return python;
    }
    return {};
}

}  // namespace

void addPlotScript(OutputSet& outputs, const PlotJob& job, const std::string& field) {
    outputs.folder(job.folder, field);
    outputs.writeText(job.folder + "/" + kScript, field,
                      [](std::ostream& out) { out << *builtinAsset(kScript); });
}

bool drawPlots(const PlotJob& job, std::ostream& log) {
    // Absolute paths: a folder named "-plots" must not reach Python as an option.
    const auto path = [](const std::string& p) {
        return shellQuoted(std::filesystem::absolute(p).string());
    };
    const std::string script = path(job.folder + "/" + kScript) + " " + job.mode + " " +
                               path(job.csv) + " " + path(job.folder);
    const std::string python = pythonWithMatplotlib();
    if (python.empty()) {
        log << "plots skipped: no Python with matplotlib and numpy (Debian: apt-get install "
               "python3-matplotlib); run `python3 "
            << script << "` once it is there\n";
        return false;
    }
    const std::string plotsLog = job.folder + "/plots.log";
    const std::string command =
        shellQuoted(python) + " " + script + " > " + shellQuoted(plotsLog) + " 2>&1";
    const int status = std::system(command.c_str());
    // The shell ignores an interrupt while Python runs; Python dies of it, and so do we, as an
    // interrupted command should (the results are already in place).
    if (WIFSIGNALED(status) && (WTERMSIG(status) == SIGINT || WTERMSIG(status) == SIGTERM)) {
        log << std::flush;
        std::raise(WTERMSIG(status));
    }
    const bool interrupted = WIFEXITED(status) && WEXITSTATUS(status) == 128 + SIGINT;
    if (interrupted) std::raise(SIGINT);
    if (status != 0) {
        log << "plotting failed; see " << plotsLog << "\n";
        return false;
    }
    log << "wrote the plots in " << job.folder << " (see " << plotsLog << ")\n";
    return true;
}

}  // namespace patchsim
