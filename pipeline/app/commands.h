#pragma once
// The subcommands of `patchsim`, each run from checked settings (job_options.h). Each returns the
// process's exit code; bad input throws InputError, which main prints as one line (exit 2).

#include "pipeline/app/job_options.h"
#include "pipeline/app/mpi_context.h"

namespace patchsim {

int runInfo(const JobSettings& s);
int runTessellate(const JobSettings& s);
int runRender(const JobSettings& s, const MpiContext& mpi);
int runVerifyTiles(const JobSettings& s);
int runSweepCommand(const JobSettings& s);
int runExplore(const JobSettings& s, const MpiContext& mpi);

}  // namespace patchsim
