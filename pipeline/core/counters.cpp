#include "pipeline/core/counters.h"

#include <algorithm>

namespace patchsim {

void CounterTotals::merge(const CounterInfo& info, std::int64_t value) {
    std::int64_t& total = values_[info.name];
    total = info.kind == CounterKind::Max ? std::max(total, value) : total + value;
}

CounterRegistry& CounterRegistry::instance() {
    static CounterRegistry registry;
    return registry;
}

void CounterRegistry::add(const CounterInfo& info, FlushFunction flush) {
    std::lock_guard lock(mutex_);
    infos_.push_back(info);
    flushes_.push_back(flush);
    totals_.values_.emplace(info.name, 0);
}

void CounterRegistry::flushThread() {
    std::lock_guard lock(mutex_);
    for (FlushFunction flush : flushes_) flush(totals_);
}

CounterValues CounterRegistry::snapshot() {
    flushThread();
    std::lock_guard lock(mutex_);
    return totals_.values_;
}

void CounterRegistry::reset() {
    flushThread();
    std::lock_guard lock(mutex_);
    for (auto& [name, value] : totals_.values_) value = 0;
}

std::vector<CounterInfo> CounterRegistry::infos() const {
    std::lock_guard lock(mutex_);
    return infos_;
}

}  // namespace patchsim
