#pragma once
// A progress bar on standard error for long jobs: work done, the items behind it (patches, rows,
// runs), and an estimate of the time left. Silent unless standard error is a terminal, and never
// printed more than ten times a second; safe to advance from several threads.

#include <atomic>
#include <chrono>
#include <mutex>
#include <string>

namespace patchsim {

class Progress {
  public:
    // `total` units of work; `unitsPerItem` converts units to the items the bar counts
    // (`items`, e.g. "patches" or "rows").
    Progress(std::string label, std::int64_t total, std::int64_t unitsPerItem, bool enabled,
             std::string items = "patches");
    ~Progress();
    void advance(std::int64_t units = 1);
    static bool terminalAttached();

  private:
    void draw(bool final);

    std::string label_;
    std::int64_t total_, unitsPerItem_;
    std::string items_;
    bool enabled_;
    std::atomic<std::int64_t> done_{0};
    std::chrono::steady_clock::time_point start_, lastDraw_;
    std::mutex mutex_;
};

}  // namespace patchsim
