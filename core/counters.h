#pragma once
// Self-registering, thread-local work counters (after pbrt-v4's STAT_COUNTER and STAT_RATIO).
//
// Representation
// --------------
// A Counter is declared once, where it is counted, as a namespace-scope constant:
//
//     const Counter rsRaysCast{"RS/Rays cast", "rays", "Per-sample rays traversed ..."};
//
// Constructing it registers its name ("Stage/Name"), unit and one-line definition and gives it an
// index. Adding to it adds to the calling thread's slot for that index: no lock, no atomic. Hot
// loops count into plain locals and add them once per tile or patch (pbrt's
// `bvhNodesVisited += nodesVisited`); each worker calls `flushThreadCounters()` once when it is
// done, so the totals are exact integer sums that do not depend on the number of threads or the
// order in which they finish. A Max counter keeps the largest value any thread saw.
//
// A RatioCounter is the quotient of two counters (sample test efficiency = visibility samples /
// samples tested); it has no storage of its own. Reports read counters by handle
// (`values[rsRaysCast]`), and list every counter by name in a fixed (sorted) order.

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

class Counter {
  public:
    Counter(const char* name, const char* unit, const char* definition,
            CounterKind kind = CounterKind::Sum);
    Counter(const Counter&) = delete;
    Counter& operator=(const Counter&) = delete;

    // Adds to the calling thread's count (Sum), or raises it to `value` (Max: keep the largest).
    void operator+=(std::int64_t value) const;
    void operator++() const { *this += 1; }
    void raiseTo(std::int64_t value) const;

    std::size_t index() const { return index_; }
    const CounterInfo& info() const;

  private:
    std::size_t index_;
};

struct RatioCounter {
    const char* name;  // e.g. "RS/Sample test efficiency"
    const char* definition;
    const Counter& numerator;
    const Counter& denominator;
};

// Totals of every registered counter at one moment.
class CounterValues {
  public:
    std::int64_t operator[](const Counter& c) const { return values_[c.index()]; }
    double ratio(const RatioCounter& r) const;  // 0 when the denominator is 0
    // Every counter as (name, value), sorted by name.
    std::map<std::string, std::int64_t> byName() const;
    std::int64_t byName(const std::string& name) const;  // for tools and tests; throws if unknown
    // The counts since `earlier` (Sum counters; Max counters keep their value), e.g. one
    // process's share of a frame, to merge into another process's totals.
    CounterValues since(const CounterValues& earlier) const;
    const std::vector<std::int64_t>& raw() const { return values_; }
    static CounterValues fromRaw(std::vector<std::int64_t> values);

  private:
    friend class CounterRegistry;
    std::vector<std::int64_t> values_;
};

class CounterRegistry {
  public:
    static CounterRegistry& instance();

    std::size_t add(const CounterInfo& info);
    // Adds the calling thread's counts to the totals and zeroes them.
    void flushThread();
    // All registered counters (zero when never counted), after flushing the calling thread.
    CounterValues snapshot();
    // Zeroes the totals and the calling thread's counts.
    void reset();
    // Adds another process's counts (same binary: same counters in the same order).
    void merge(const CounterValues& other);
    std::vector<CounterInfo> infos() const;
    const CounterInfo& info(std::size_t index) const;

  private:
    mutable std::mutex mutex_;
    std::vector<CounterInfo> infos_;
    std::vector<std::int64_t> totals_;
};

inline void flushThreadCounters() {
    CounterRegistry::instance().flushThread();
}

}  // namespace patchsim
