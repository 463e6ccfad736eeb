#pragma once
// A progress bar on stderr: percent, elapsed time, ETA and throughput. Thread-safe; redraws at
// most a few times per second and only when enabled (the caller checks for a terminal).

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace candela {

// Where a render reports how far it has come besides the bar (RenderOptions::progress_sink): an
// embedding program (the Python API's progress callback) reads it from another thread.
struct ProgressSink {
    std::atomic<uint64_t> done{0}, total{0};
    double fraction() const {
        const uint64_t t = total.load();
        return t > 0 ? std::min(1.0, double(done.load()) / double(t)) : 0.0;
    }
};

class ProgressReporter {
public:
    // `sink`, when given, learns the total now and the work done as it is added.
    ProgressReporter(std::string label, uint64_t total_work, bool enabled, std::string unit = "samples", ProgressSink* sink = nullptr);
    void add(uint64_t work);  // called from any thread
    void finish();            // final redraw and newline
    double elapsed_seconds() const;

private:
    void draw(uint64_t done, bool final);
    std::string label_, unit_;
    uint64_t total_;
    bool enabled_;
    ProgressSink* sink_;
    std::atomic<uint64_t> done_{0};
    std::chrono::steady_clock::time_point start_, last_draw_;
    std::mutex draw_mutex_;
};

// True when stderr is an interactive terminal.
bool stderr_is_terminal();
// "1h02m03s" / "4m05s" / "6.7s"
std::string format_duration(double seconds);
// "12.3M" style with k/M/G suffixes.
std::string format_count(double value);

}  // namespace candela
