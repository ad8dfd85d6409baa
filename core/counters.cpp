#include "core/counters.h"

#include <algorithm>
#include <deque>
#include <mutex>
#include <stdexcept>

namespace patchsim {

namespace {

// Every thread's counts, by counter index, in blocks that live as long as the process. The thread
// holds only a pointer to its block: a thread_local with a destructor registers with the C runtime
// on first use, and that registration waits for any dlopen under way (the image module loads
// beside the render; backend/images/image_io_module.h), stalling a worker for the whole load.
// Never destroyed: a parked worker may hold its pointer until the process ends.
struct ThreadCountBlocks {
    std::mutex mutex;
    std::deque<std::vector<std::int64_t>> blocks;
};
ThreadCountBlocks& threadCountBlocks() {
    static ThreadCountBlocks* const all = new ThreadCountBlocks;
    return *all;
}

thread_local std::vector<std::int64_t>* threadCounts = nullptr;

// Counters register during static initialisation, before any worker runs, but a thread may count
// before it has a slot for a later counter: grow on use.
std::vector<std::int64_t>& growThreadCounts(std::size_t index) {
    if (!threadCounts) {
        ThreadCountBlocks& all = threadCountBlocks();
        std::lock_guard lock(all.mutex);
        threadCounts = &all.blocks.emplace_back();
    }
    if (index >= threadCounts->size()) threadCounts->resize(index + 1, 0);
    return *threadCounts;
}

std::int64_t& threadSlot(std::size_t index) {
    std::vector<std::int64_t>* mine = threadCounts;
    if (!mine || index >= mine->size()) mine = &growThreadCounts(index);
    return (*mine)[index];
}

}  // namespace

Counter::Counter(const char* name, const char* unit, const char* definition, CounterKind kind)
    : index_(CounterRegistry::instance().add({name, unit, definition, kind})) {}

void Counter::operator+=(std::int64_t value) const {
    threadSlot(index_) += value;
}

void Counter::raiseTo(std::int64_t value) const {
    std::int64_t& slot = threadSlot(index_);
    slot = std::max(slot, value);
}

const CounterInfo& Counter::info() const {
    return CounterRegistry::instance().info(index_);
}

double CounterValues::ratio(const RatioCounter& r) const {
    const std::int64_t d = (*this)[r.denominator];
    return d ? double((*this)[r.numerator]) / double(d) : 0.0;
}

std::map<std::string, std::int64_t> CounterValues::byName() const {
    std::map<std::string, std::int64_t> named;
    const CounterRegistry& registry = CounterRegistry::instance();
    for (std::size_t i = 0; i < values_.size(); ++i) named[registry.info(i).name] += values_[i];
    return named;
}

std::int64_t CounterValues::byName(const std::string& name) const {
    const CounterRegistry& registry = CounterRegistry::instance();
    for (std::size_t i = 0; i < values_.size(); ++i)
        if (name == registry.info(i).name) return values_[i];
    throw std::out_of_range("no counter named " + name);
}

CounterValues CounterValues::since(const CounterValues& earlier) const {
    CounterValues delta = *this;
    const CounterRegistry& registry = CounterRegistry::instance();
    for (std::size_t i = 0; i < values_.size() && i < earlier.values_.size(); ++i)
        if (registry.info(i).kind == CounterKind::Sum) delta.values_[i] -= earlier.values_[i];
    return delta;
}

CounterValues CounterValues::fromRaw(std::vector<std::int64_t> values) {
    CounterValues v;
    v.values_ = std::move(values);
    return v;
}

CounterRegistry& CounterRegistry::instance() {
    static CounterRegistry registry;
    return registry;
}

std::size_t CounterRegistry::add(const CounterInfo& info) {
    std::lock_guard lock(mutex_);
    infos_.push_back(info);
    totals_.push_back(0);
    return infos_.size() - 1;
}

void CounterRegistry::flushThread() {
    if (!threadCounts) return;  // this thread never counted
    std::vector<std::int64_t>& counts = *threadCounts;
    std::lock_guard lock(mutex_);
    for (std::size_t i = 0; i < counts.size() && i < totals_.size(); ++i) {
        std::int64_t& total = totals_[i];
        total = infos_[i].kind == CounterKind::Max ? std::max(total, counts[i]) : total + counts[i];
        counts[i] = 0;
    }
}

CounterValues CounterRegistry::snapshot() {
    flushThread();
    std::lock_guard lock(mutex_);
    CounterValues values;
    values.values_ = totals_;
    return values;
}

void CounterRegistry::reset() {
    flushThread();
    std::lock_guard lock(mutex_);
    std::fill(totals_.begin(), totals_.end(), 0);
}

void CounterRegistry::merge(const CounterValues& other) {
    std::lock_guard lock(mutex_);
    const std::vector<std::int64_t>& v = other.raw();
    for (std::size_t i = 0; i < v.size() && i < totals_.size(); ++i)
        totals_[i] =
            infos_[i].kind == CounterKind::Max ? std::max(totals_[i], v[i]) : totals_[i] + v[i];
}

std::vector<CounterInfo> CounterRegistry::infos() const {
    std::lock_guard lock(mutex_);
    return infos_;
}

const CounterInfo& CounterRegistry::info(std::size_t index) const {
    std::lock_guard lock(mutex_);
    return infos_[index];
}

}  // namespace patchsim
