#pragma once
// MPI for `patchsim explore` and `render`, when the build found OpenMPI and the process was
// started by mpirun: ranks, a gather of bytes to rank 0, an all-ranks success check, each rank's
// share of the machine's cores, and progress shared between ranks. Without MPI (or outside
// mpirun) there is one rank.

#include <memory>
#include <string>
#include <vector>

#include "core/progress.h"

namespace patchsim {

class MpiContext {
  public:
    MpiContext(int& argc, char**& argv);
    ~MpiContext();
    MpiContext(const MpiContext&) = delete;
    MpiContext& operator=(const MpiContext&) = delete;

    int rank() const { return rank_; }
    int size() const { return size_; }
    bool active() const { return active_; }
    // Every rank's text, in rank order, on rank 0 (empty elsewhere).
    std::vector<std::string> gather(const std::string& text) const;
    // True on every rank when `ok` is true on every rank (a collective: all ranks must call it).
    bool allSucceeded(bool ok) const;
    // Ranks started on this machine (OpenMPI's local size), to share its cores among them.
    int localRanks() const;
    // Worker threads for this rank: `requested`, or for 0 (all cores) this rank's share of them.
    int threadsPerRank(int requested) const;
    // Shares progress between ranks (collective: every rank makes one at the same point).
    std::unique_ptr<ProgressShare> makeProgressShare() const;

  private:
    int rank_ = 0, size_ = 1;
    bool active_ = false;
};

}  // namespace patchsim
