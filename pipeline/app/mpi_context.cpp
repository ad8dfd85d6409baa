#include "pipeline/app/mpi_context.h"

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <thread>

#ifdef PATCHSIM_HAVE_MPI
#include <mpi.h>
#endif

namespace patchsim {

namespace {
bool startedByMpirun() {
    return std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMI_SIZE") ||
           std::getenv("PMIX_RANK");
}
}  // namespace

MpiContext::MpiContext(int& argc, char**& argv) {
#ifdef PATCHSIM_HAVE_MPI
    if (!startedByMpirun()) return;
    // Progress is published from worker threads, one at a time (core/progress.h).
    int provided = 0;
    MPI_Init_thread(&argc, &argv, MPI_THREAD_SERIALIZED, &provided);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
    active_ = true;
#else
    (void)argc;
    (void)argv;
    (void)startedByMpirun;
#endif
}

MpiContext::~MpiContext() {
#ifdef PATCHSIM_HAVE_MPI
    if (active_) MPI_Finalize();
#endif
}

bool MpiContext::allSucceeded(bool ok) const {
    if (!active_) return ok;
#ifdef PATCHSIM_HAVE_MPI
    int mine = ok ? 1 : 0, all = 0;
    MPI_Allreduce(&mine, &all, 1, MPI_INT, MPI_LAND, MPI_COMM_WORLD);
    return all != 0;
#else
    return ok;
#endif
}

int MpiContext::localRanks() const {
    if (!active_) return 1;
    if (const char* local = std::getenv("OMPI_COMM_WORLD_LOCAL_SIZE")) {
        const int n = std::atoi(local);
        if (n > 0) return n;
    }
    return size_;
}

#ifdef PATCHSIM_HAVE_MPI
namespace {

// Every rank's units in one slot each of a window on rank 0; the others put theirs there with
// passive-target RMA, rank 0 reads them when it draws.
class MpiProgressShare : public ProgressShare {
  public:
    MpiProgressShare(int rank, int size)
        : rank_(rank), slots_(rank == 0 ? std::size_t(size) : 0, 0) {
        MPI_Win_create(slots_.data(), MPI_Aint(slots_.size() * sizeof(std::int64_t)),
                       sizeof(std::int64_t), MPI_INFO_NULL, MPI_COMM_WORLD, &window_);
    }
    ~MpiProgressShare() override { MPI_Win_free(&window_); }

    void publish(std::int64_t done) override {
        if (rank_ == 0) return;
        MPI_Win_lock(MPI_LOCK_SHARED, 0, 0, window_);
        MPI_Put(&done, 1, MPI_INT64_T, 0, rank_, 1, MPI_INT64_T, window_);
        MPI_Win_unlock(0, window_);
    }
    std::int64_t others() override {
        if (rank_ != 0) return 0;
        MPI_Win_lock(MPI_LOCK_SHARED, 0, 0, window_);
        std::int64_t sum = 0;
        for (std::size_t r = 1; r < slots_.size(); ++r) sum += slots_[r];
        MPI_Win_unlock(0, window_);
        return sum;
    }
    void finish(std::int64_t done) override {
        publish(done);
        MPI_Barrier(MPI_COMM_WORLD);
    }

  private:
    int rank_;
    std::vector<std::int64_t> slots_;
    MPI_Win window_;
};

}  // namespace
#endif

std::unique_ptr<ProgressShare> MpiContext::makeProgressShare() const {
#ifdef PATCHSIM_HAVE_MPI
    if (active_) return std::make_unique<MpiProgressShare>(rank_, size_);
#endif
    return nullptr;
}

int MpiContext::threadsPerRank(int requested) const {
    if (requested > 0) return requested;
    const int cores = std::max(1, int(std::thread::hardware_concurrency()));
    return std::max(1, cores / localRanks());
}

std::vector<std::string> MpiContext::gather(const std::string& text) const {
    if (!active_) return {text};
#ifdef PATCHSIM_HAVE_MPI
    int length = int(text.size());
    std::vector<int> lengths(static_cast<std::size_t>(size_)),
        offsets(static_cast<std::size_t>(size_));
    MPI_Gather(&length, 1, MPI_INT, lengths.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
    std::vector<char> all;
    if (rank_ == 0) {
        int total = 0;
        for (int r = 0; r < size_; ++r) {
            offsets[std::size_t(r)] = total;
            total += lengths[std::size_t(r)];
        }
        all.resize(std::size_t(total));
    }
    MPI_Gatherv(text.data(), length, MPI_CHAR, all.data(), lengths.data(), offsets.data(), MPI_CHAR,
                0, MPI_COMM_WORLD);
    std::vector<std::string> parts;
    if (rank_ == 0)
        for (int r = 0; r < size_; ++r)
            parts.emplace_back(all.data() + offsets[std::size_t(r)],
                               std::size_t(lengths[std::size_t(r)]));
    return parts;
#else
    return {text};
#endif
}

}  // namespace patchsim
