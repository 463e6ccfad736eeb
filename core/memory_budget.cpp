#include "core/memory_budget.h"

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>

#include <unistd.h>

namespace candela {

namespace {

std::atomic<uint64_t> g_limit{0};

// MemAvailable from /proc/meminfo (the kernel's estimate of what can be allocated without
// swapping), or nothing when the file is missing (not Linux).
bool meminfo_available(uint64_t& bytes) {
    std::ifstream in("/proc/meminfo");
    std::string key;
    uint64_t kb = 0;
    std::string unit;
    while (in >> key >> kb) {
        std::getline(in, unit);
        if (key == "MemAvailable:") {
            bytes = saturating_mul(kb, 1024);
            return true;
        }
    }
    return false;
}

}  // namespace

// The second field of /proc/self/statm, in pages.
uint64_t resident_memory() {
    std::ifstream in("/proc/self/statm");
    uint64_t size = 0, resident = 0;
    if (!(in >> size >> resident)) return 0;
    long page = sysconf(_SC_PAGESIZE);
    return saturating_mul(resident, page > 0 ? uint64_t(page) : 4096);
}

void set_memory_limit(uint64_t bytes) { g_limit = bytes; }
uint64_t memory_limit() { return g_limit; }

uint64_t saturating_mul(uint64_t a, uint64_t b) {
    if (a != 0 && b > std::numeric_limits<uint64_t>::max() / a) return std::numeric_limits<uint64_t>::max();
    return a * b;
}

uint64_t saturating_add(uint64_t a, uint64_t b) {
    return b > std::numeric_limits<uint64_t>::max() - a ? std::numeric_limits<uint64_t>::max() : a + b;
}

uint64_t memory_available() {
    uint64_t available = std::numeric_limits<uint64_t>::max();
    meminfo_available(available);
    if (uint64_t limit = g_limit) {
        uint64_t held = resident_memory();
        available = std::min(available, limit > held ? limit - held : 0);
    }
    return available;
}

void check_memory(uint64_t bytes, const std::string& what, const SourceLocation& where) {
    uint64_t available = memory_available();
    if (bytes <= available) return;
    std::string message = what + " needs " + format_bytes(bytes) + "; " + format_bytes(available) + " available";
    uint64_t system = std::numeric_limits<uint64_t>::max();
    meminfo_available(system);
    if (g_limit && available < system) message += " under --max-memory " + format_bytes(g_limit);
    if (where.file.empty()) throw InputError(message);
    throw SceneError(where, message);
}

std::string format_bytes(uint64_t bytes) {
    const char* units[] = {"B", "kB", "MB", "GB", "TB", "PB", "EB"};
    double v = double(bytes);
    int u = 0;
    while (v >= 1024.0 && u < 6) {
        v /= 1024.0;
        ++u;
    }
    char buf[32];
    if (u == 0 || v >= 10.0)
        std::snprintf(buf, sizeof buf, "%.0f %s", std::floor(v + 0.5), units[u]);
    else
        std::snprintf(buf, sizeof buf, "%.1f %s", v, units[u]);
    return buf;
}

uint64_t parse_memory_size(const std::string& text) {
    auto bad = [&] { return InputError("--max-memory expects a size such as 4G, 512M or 1.5G, got \"" + text + "\""); };
    char* end = nullptr;
    double value = std::strtod(text.c_str(), &end);
    if (end == text.c_str() || !std::isfinite(value) || value <= 0.0) throw bad();
    std::string suffix(end);
    double scale = 1.0;
    if (!suffix.empty()) {
        const std::string letters = "kMGT";
        size_t k = letters.find(char(suffix[0] == 'K' ? 'k' : suffix[0]));
        if (k == std::string::npos) {
            if (suffix != "B") throw bad();
        } else {
            scale = std::pow(1024.0, double(k + 1));
            std::string rest = suffix.substr(1);
            if (!rest.empty() && rest != "B" && rest != "iB") throw bad();
        }
    }
    double bytes = value * scale;
    if (bytes < 1.0 || bytes >= 1.8e19) throw bad();
    return uint64_t(bytes);
}

}  // namespace candela
