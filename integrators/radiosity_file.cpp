// The radiosity solution file (format in radiosity_solver.h). Written whole or not at all.

#include "core/file_output.h"
#include "integrators/radiosity_solver.h"

#include <cstring>
#include <fstream>
#include <sstream>

namespace candela {

namespace {

const char Magic[18] = "CANDELA-RADIOSITY";  // with its terminating zero: 18 bytes
constexpr uint32_t Version = 1;
constexpr size_t HeaderSize = sizeof Magic + 4 + 8 + 8 + 4 + 4;

template <typename T>
void put(std::string& out, const T& value) {
    out.append(reinterpret_cast<const char*>(&value), sizeof value);
}
template <typename T>
T take(const std::string& in, size_t& offset) {
    T value;
    std::memcpy(&value, in.data() + offset, sizeof value);
    offset += sizeof value;
    return value;
}

}  // namespace

void write_radiosity_file(const std::string& path, uint64_t key, const std::vector<Spectrum>& irradiance, const RadiosityStats& stats) {
    std::string out(Magic, sizeof Magic);
    put(out, Version);
    put(out, key);
    put(out, uint64_t(irradiance.size()));
    put(out, uint32_t(stats.shots));
    put(out, float(stats.unshot_fraction));
    for (const Spectrum& e : irradiance)
        for (int c = 0; c < 3; ++c) put(out, float(e[c]));
    write_file_atomically(path, out);
}

bool read_radiosity_file(const std::string& path, uint64_t key, size_t elements, std::vector<Spectrum>& irradiance, RadiosityStats& stats,
                         std::string& reason) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream buffer;
    buffer << in.rdbuf();
    std::string data = buffer.str();
    if (!in || data.size() < HeaderSize || std::memcmp(data.data(), Magic, sizeof Magic) != 0) {
        reason = "not a radiosity solution file";
        return false;
    }
    size_t offset = sizeof Magic;
    if (take<uint32_t>(data, offset) != Version) {
        reason = "unknown version";
        return false;
    }
    if (take<uint64_t>(data, offset) != key) {
        reason = "made for other geometry, materials, lights or settings";
        return false;
    }
    uint64_t count = take<uint64_t>(data, offset);
    if (count != elements || data.size() != HeaderSize + count * 3 * sizeof(float)) {
        reason = "damaged: wrong size";
        return false;
    }
    int shots = int(take<uint32_t>(data, offset));
    float unshot = take<float>(data, offset);
    std::vector<Spectrum> values(count);
    for (auto& e : values)
        for (int c = 0; c < 3; ++c) e[c] = take<float>(data, offset);
    for (const auto& e : values)
        if (!all_finite(e) || min_component(e) < 0.0f) {
            reason = "damaged: values that are not irradiances";
            return false;
        }
    irradiance = std::move(values);
    stats.shots = shots;
    stats.unshot_fraction = unshot;
    return true;
}

}  // namespace candela
