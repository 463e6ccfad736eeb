#pragma once
// A progress bar on stderr: percent, elapsed time, ETA and throughput. Thread-safe; redraws at
// most a few times per second and only when enabled (the caller checks for a terminal).

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace candela {

class ProgressReporter {
public:
    ProgressReporter(std::string label, uint64_t total_work, bool enabled, std::string unit = "samples");
    void add(uint64_t work);  // called from any thread
    void finish();            // final redraw and newline
    double elapsed_seconds() const;

private:
    void draw(uint64_t done, bool final);
    std::string label_, unit_;
    uint64_t total_;
    bool enabled_;
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
