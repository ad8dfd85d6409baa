#pragma once
// Plots of a command's results. One matplotlib script, scripts/plot_results.py, is built into the
// binary and draws them for `sweep` and `explore` alike. A copy of it goes into the plots folder
// with the results, so a user can rerun (or change) it on the CSV; once the results are written
// it runs under the first Python that has matplotlib, its output kept in the folder's plots.log.
// Without such a Python the command still succeeds and says how to draw the plots later.

#include <ostream>
#include <string>

namespace patchsim {

class OutputSet;

struct PlotJob {
    std::string mode;    // the script's mode: "sweep" or "explore"
    std::string csv;     // the results it reads
    std::string folder;  // where the plots, the script's copy and plots.log go
};

// Reserves the folder (made if missing) and the script's copy in `outputs`, so both are checked
// before the work and appear only when the results do. `field` names the option of the folder.
void addPlotScript(OutputSet& outputs, const PlotJob& job, const std::string& field);

// After the outputs are committed: runs the script and tells `log` where the plots are, or why
// there are none. Returns whether the script ran and succeeded.
bool drawPlots(const PlotJob& job, std::ostream& log);

}  // namespace patchsim
