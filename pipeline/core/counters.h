#pragma once
// Self-registering, thread-local work counters (after pbrt-v4's STAT_COUNTER).
//
// Representation
// --------------
// Each counter is a `static thread_local std::int64_t` owned by the file that counts with it, plus
// one registration object made at static-initialisation time. The registration holds the
// counter's name ("Stage/Name"), unit and one-line definition, and a captureless function that
// adds the calling thread's value into the process-wide totals and zeroes it. Hot loops count into
// plain locals and add them to the thread-local once per patch or tile; each worker calls
// `flushThreadCounters()` once when it finishes, so the totals are exact integer sums and do not
// depend on the number of threads or the order in which they finish.

#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace patchsim {

enum class CounterKind : std::uint8_t { Sum, Max };

struct CounterInfo {
    const char* name;        // "Stage/Name"
    const char* unit;        // e.g. "patches", "tests", "bytes"
    const char* definition;  // one line
    CounterKind kind = CounterKind::Sum;
};

// Totals by counter name; std::map so that every report lists them in the same order.
using CounterValues = std::map<std::string, std::int64_t>;

class CounterTotals {
  public:
    void merge(const CounterInfo& info, std::int64_t value);

  private:
    friend class CounterRegistry;
    CounterValues values_;
};

class CounterRegistry {
  public:
    using FlushFunction = void (*)(CounterTotals&);

    static CounterRegistry& instance();

    void add(const CounterInfo& info, FlushFunction flush);
    // Adds the calling thread's counts to the totals and zeroes them.
    void flushThread();
    // All registered counters (zero when never counted), after flushing the calling thread.
    CounterValues snapshot();
    // Zeroes the totals and the calling thread's counts.
    void reset();
    std::vector<CounterInfo> infos() const;

  private:
    mutable std::mutex mutex_;
    std::vector<CounterInfo> infos_;
    std::vector<FlushFunction> flushes_;
    CounterTotals totals_;
};

struct CounterRegistration {
    CounterRegistration(const CounterInfo& info, CounterRegistry::FlushFunction flush) {
        CounterRegistry::instance().add(info, flush);
    }
};

inline void flushThreadCounters() {
    CounterRegistry::instance().flushThread();
}

}  // namespace patchsim

#define PATCHSIM_COUNTER_IMPL(NAME, UNIT, DEFINITION, KIND, VAR)                      \
    static thread_local std::int64_t VAR = 0;                                         \
    static ::patchsim::CounterRegistration VAR##Registration(                         \
        ::patchsim::CounterInfo{NAME, UNIT, DEFINITION, KIND},                        \
        [](::patchsim::CounterTotals& totals) {                                       \
            totals.merge(::patchsim::CounterInfo{NAME, UNIT, DEFINITION, KIND}, VAR); \
            VAR = 0;                                                                  \
        })

// A counter summed over threads.
#define PATCHSIM_COUNTER(NAME, UNIT, DEFINITION, VAR) \
    PATCHSIM_COUNTER_IMPL(NAME, UNIT, DEFINITION, ::patchsim::CounterKind::Sum, VAR)
// A counter that keeps the largest value seen on any thread.
#define PATCHSIM_COUNTER_MAX(NAME, UNIT, DEFINITION, VAR) \
    PATCHSIM_COUNTER_IMPL(NAME, UNIT, DEFINITION, ::patchsim::CounterKind::Max, VAR)
