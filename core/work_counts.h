#pragma once
// The work a component counts, defined once per component: its fields, counters, flush and
// timing charges (DESIGN.md section 8).
//
// Representation
// --------------
// A component lists its counts as an X-macro, one row per count:
//
//     X(field, "Stage/Name", "unit", Sum|Max, "definition", charges...)
//
// where `charges` are the operation kinds (core/stage_ops.h) one unit of the count costs the
// modelled hardware, kScratchPeak for a size held against the on-chip scratch budget, Refund{op}
// for a cost another component already charged, or nothing. From that one list come, through the
// macros below:
//
// - the plain struct the hot loops count into (one int64 per count, no allocation):
//       struct MyWork { MY_LIST(PATCHSIM_WORK_FIELD) PATCHSIM_WORK_METHODS(MyWork) };
// - a struct of handles to the registered counters (`values[myCounters().field]`):
//       struct MyCounters { MY_LIST(PATCHSIM_WORK_HANDLE) };
// - in one .cpp, PATCHSIM_WORK_DEFINE(MyWork, MyCounters, myCounters, MY_LIST): the registered
//   counters (docs/COUNTERS.md lists them; a test checks it), `add` (Max counts keep the larger),
//   `flush` into the calling thread's counters, `charge` into a patch's operations, and the
//   accessor of the handles.
//
// So adding a count is one row: it is counted, reported, documented and charged from there.

#include <algorithm>
#include <cstdint>

#include "core/counters.h"
#include "core/stage_ops.h"

namespace patchsim {

// A count that is a size in bytes, held against the scratch budget (the largest is kept).
struct ScratchPeak {};
inline constexpr ScratchPeak kScratchPeak{};

// A count whose cost another component already charged (one unit of `op` each): given back.
struct Refund {
    Op op;
};

inline void chargeOne(PatchOps& ops, std::int64_t count, Refund refund) {
    ops[refund.op] -= double(count);
}
inline void chargeOne(PatchOps& ops, std::int64_t count, Op op) {
    ops[op] += double(count);
}
inline void chargeOne(PatchOps& ops, std::int64_t count, ScratchPeak) {
    ops.hierarchyBytes = std::max(ops.hierarchyBytes, std::uint64_t(count));
}
template <class... Charges>
void chargeTo([[maybe_unused]] PatchOps& ops, [[maybe_unused]] std::int64_t count,
              Charges... charges) {
    (chargeOne(ops, count, charges), ...);
}

constexpr bool isMaxCount(CounterKind kind) {
    return kind == CounterKind::Max;
}

}  // namespace patchsim

#define PATCHSIM_WORK_FIELD(field, name, unit, kind, definition, ...) std::int64_t field = 0;
#define PATCHSIM_WORK_HANDLE(field, name, unit, kind, definition, ...) const Counter& field;

// Inside the work struct: what PATCHSIM_WORK_DEFINE defines.
#define PATCHSIM_WORK_METHODS(Work)                           \
    /* Adds another's counts (Max counts keep the larger). */ \
    void add(const Work& other);                              \
    /* Adds the counts to the calling thread's counters. */   \
    void flush() const;                                       \
    /* Adds what the counts cost to a patch's operations. */  \
    void charge(PatchOps& ops) const;

#define PATCHSIM_WORK_COUNTER(field, name, unit, kind, definition, ...) \
    const Counter field##Counter{name, unit, definition, CounterKind::kind};
#define PATCHSIM_WORK_ADD(field, name, unit, kind, definition, ...) \
    field = isMaxCount(CounterKind::kind) ? std::max(field, other.field) : field + other.field;
#define PATCHSIM_WORK_FLUSH(field, name, unit, kind, definition, ...) \
    if (isMaxCount(CounterKind::kind))                                \
        field##Counter.raiseTo(field);                                \
    else                                                              \
        field##Counter += field;
#define PATCHSIM_WORK_CHARGE(field, name, unit, kind, definition, ...) \
    chargeTo(ops, field __VA_OPT__(, ) __VA_ARGS__);
#define PATCHSIM_WORK_REF(field, name, unit, kind, definition, ...) field##Counter,

// In one .cpp, inside namespace patchsim.
#define PATCHSIM_WORK_DEFINE(Work, Counters, countersFunction, LIST) \
    namespace {                                                      \
    LIST(PATCHSIM_WORK_COUNTER)                                      \
    }                                                                \
    void Work::add(const Work& other) {                              \
        LIST(PATCHSIM_WORK_ADD)                                      \
    }                                                                \
    void Work::flush() const {                                       \
        LIST(PATCHSIM_WORK_FLUSH)                                    \
    }                                                                \
    void Work::charge([[maybe_unused]] PatchOps& ops) const {        \
        LIST(PATCHSIM_WORK_CHARGE)                                   \
    }                                                                \
    const Counters& countersFunction() {                             \
        static const Counters counters{LIST(PATCHSIM_WORK_REF)};     \
        return counters;                                             \
    }
