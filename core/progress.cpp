#include "core/progress.h"

#include <unistd.h>

#include <cstdio>

namespace patchsim {

Progress::Progress(std::string label, std::int64_t total, std::int64_t unitsPerItem, bool enabled,
                   std::string items, ProgressShare* share)
    : label_(std::move(label)),
      total_(std::max<std::int64_t>(total, 1)),
      unitsPerItem_(std::max<std::int64_t>(unitsPerItem, 1)),
      items_(std::move(items)),
      style_(!enabled             ? Style::Silent
             : terminalAttached() ? Style::Bar
             : share != nullptr   ? Style::Lines
                                  : Style::Silent),
      share_(share),
      start_(std::chrono::steady_clock::now()),
      lastDraw_(start_) {}

Progress::~Progress() {
    if (style_ != Style::Silent) draw(true);
}

void Progress::describe(std::string detail) {
    std::lock_guard lock(mutex_);
    detail_ = std::move(detail);
    if (style_ == Style::Bar) draw(false);
}

void Progress::clear() {
    std::lock_guard lock(mutex_);
    if (style_ != Style::Bar) return;
    std::fputs("\r\033[K", stderr);
    std::fflush(stderr);
}

void Progress::finish() {
    if (share_) share_->finish(done_.load());
}

std::int64_t Progress::done() {
    return done_.load() + (share_ ? share_->others() : 0);
}

bool Progress::terminalAttached() {
    return ::isatty(STDERR_FILENO) != 0;
}

void Progress::advance(std::int64_t units) {
    done_ += units;
    if (style_ == Style::Silent && !share_) return;
    const auto now = std::chrono::steady_clock::now();
    const auto every =
        style_ == Style::Lines ? std::chrono::milliseconds(2000) : std::chrono::milliseconds(100);
    std::unique_lock lock(mutex_, std::try_to_lock);
    if (!lock.owns_lock() || now - lastDraw_ < every) return;
    lastDraw_ = now;
    if (share_) share_->publish(done_.load());
    if (style_ != Style::Silent) draw(false);
}

void Progress::draw(bool final) {
    const std::int64_t done = std::min(this->done(), total_);
    const double fraction = double(done) / double(total_);
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    const double left = fraction > 0 ? elapsed * (1.0 - fraction) / fraction : 0.0;
    constexpr int kWidth = 30;
    char bar[kWidth + 1];
    for (int i = 0; i < kWidth; ++i) bar[i] = i < int(fraction * kWidth) ? '#' : '.';
    bar[kWidth] = 0;
    const bool redraw = style_ == Style::Bar;
    std::fprintf(stderr, "%s%s [%s] %3d%%  %lld/%lld %s  %s %.1f s%s%s%s", redraw ? "\r\033[K" : "",
                 label_.c_str(), bar, int(fraction * 100.0),
                 static_cast<long long>(done / unitsPerItem_),
                 static_cast<long long>(total_ / unitsPerItem_), items_.c_str(),
                 final ? "took" : "left", final ? elapsed : left, detail_.empty() ? "" : "  ",
                 final ? "" : detail_.c_str(), final || !redraw ? "\n" : "");
    std::fflush(stderr);
}

}  // namespace patchsim
