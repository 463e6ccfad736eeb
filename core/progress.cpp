#include "core/progress.h"

#include <unistd.h>
#include <cmath>
#include <cstdio>

namespace candela {

bool stderr_is_terminal() { return ::isatty(STDERR_FILENO) != 0; }

std::string format_duration(double s) {
    char buf[64];
    if (!std::isfinite(s) || s < 0) return "--";
    if (s < 60.0)
        std::snprintf(buf, sizeof buf, "%.1fs", s);
    else if (s < 3600.0)
        std::snprintf(buf, sizeof buf, "%dm%02ds", int(s / 60), int(s) % 60);
    else
        std::snprintf(buf, sizeof buf, "%dh%02dm%02ds", int(s / 3600), (int(s) / 60) % 60, int(s) % 60);
    return buf;
}

std::string format_count(double v) {
    char buf[64];
    if (v >= 1e9)
        std::snprintf(buf, sizeof buf, "%.2fG", v / 1e9);
    else if (v >= 1e6)
        std::snprintf(buf, sizeof buf, "%.2fM", v / 1e6);
    else if (v >= 1e3)
        std::snprintf(buf, sizeof buf, "%.1fk", v / 1e3);
    else
        std::snprintf(buf, sizeof buf, "%.0f", v);
    return buf;
}

ProgressReporter::ProgressReporter(std::string label, uint64_t total, bool enabled, std::string unit, ProgressSink* sink)
    : label_(std::move(label)), unit_(std::move(unit)), total_(total), enabled_(enabled), sink_(sink) {
    start_ = last_draw_ = std::chrono::steady_clock::now();
    if (sink_) {
        sink_->done = 0;
        sink_->total = total;
    }
}

double ProgressReporter::elapsed_seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void ProgressReporter::add(uint64_t work) {
    uint64_t done = done_.fetch_add(work) + work;
    if (sink_) sink_->done.fetch_add(work, std::memory_order_relaxed);
    if (!enabled_) return;
    std::unique_lock<std::mutex> lock(draw_mutex_, std::try_to_lock);
    if (!lock.owns_lock()) return;
    auto now = std::chrono::steady_clock::now();
    if (std::chrono::duration<double>(now - last_draw_).count() < 0.25) return;
    last_draw_ = now;
    draw(done, false);
}

void ProgressReporter::finish() {
    if (!enabled_) return;
    std::lock_guard<std::mutex> lock(draw_mutex_);
    draw(done_.load(), true);
    std::fputc('\n', stderr);
    std::fflush(stderr);
}

void ProgressReporter::draw(uint64_t done, bool final) {
    double fraction = total_ ? std::min(1.0, double(done) / double(total_)) : 1.0;
    double elapsed = elapsed_seconds();
    double eta = fraction > 0.0 ? elapsed * (1.0 - fraction) / fraction : NAN;
    const int width = 30;
    int filled = int(fraction * width);
    std::string bar(size_t(filled), '=');
    if (filled < width) bar += '>', bar += std::string(size_t(width - filled - 1), ' ');
    std::fprintf(stderr, "\r%s [%s] %5.1f%%  %s elapsed, ETA %s, %s %s/s   ", label_.c_str(), bar.c_str(), fraction * 100.0,
                 format_duration(elapsed).c_str(), final ? "0s" : format_duration(eta).c_str(),
                 format_count(elapsed > 0 ? double(done) / elapsed : 0.0).c_str(), unit_.c_str());
    std::fflush(stderr);
}

}  // namespace candela
