#pragma once
// Progress of long jobs on standard error: work done, the items behind it (patches, rows, runs),
// and an estimate of the time left. On a terminal, a bar redrawn at most ten times a second. A job
// shared with other processes (MPI ranks) counts their work too, through a ProgressShare; there,
// where standard error is not a terminal (mpirun forwards it through a pipe), the process that
// reports prints a line every few seconds instead. Silent otherwise. Safe to advance from several
// threads: one at a time draws and publishes.

#include <atomic>
#include <chrono>
#include <mutex>
#include <string>

namespace patchsim {

// The units of a job other processes have done. `publish` and `others` are called by one thread
// at a time; `finish` is collective: every process calls it once, after its last unit.
class ProgressShare {
  public:
    virtual ~ProgressShare() = default;
    virtual void publish(std::int64_t done) = 0;
    virtual std::int64_t others() = 0;
    virtual void finish(std::int64_t done) = 0;
};

class Progress {
  public:
    // `total` units of work (of all processes sharing the job); `unitsPerItem` converts units to
    // the items the bar counts (`items`, e.g. "patches" or "rows"). `enabled`: this process
    // reports (others only publish to `share`).
    Progress(std::string label, std::int64_t total, std::int64_t unitsPerItem, bool enabled,
             std::string items = "patches", ProgressShare* share = nullptr);
    ~Progress();
    void advance(std::int64_t units = 1);
    // What is being worked on now (e.g. the run of a sweep), shown after the bar.
    void describe(std::string detail);
    // Clears the bar from the terminal so a message can take its line; the next advance or
    // describe draws it again below the message.
    void clear();
    // Collective when shared: after this process's last unit, waits for the others' last ones.
    void finish();
    static bool terminalAttached();

  private:
    enum class Style : std::uint8_t { Silent, Bar, Lines };
    void draw(bool final);
    std::int64_t done();

    std::string label_;
    std::int64_t total_, unitsPerItem_;
    std::string items_;
    std::string detail_;
    Style style_;
    ProgressShare* share_;
    std::atomic<std::int64_t> done_{0};
    std::chrono::steady_clock::time_point start_, lastDraw_;
    std::mutex mutex_;
};

}  // namespace patchsim
