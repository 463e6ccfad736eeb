#include "tests/tensor_writer.h"

#include <fstream>

namespace candela::test {

namespace {

void put(std::string& out, uint64_t value, int bytes) {
    for (int i = 0; i < bytes; ++i) out.push_back(char((value >> (8 * i)) & 0xff));
}

}  // namespace

std::string float_bytes(const std::vector<float>& v) {
    return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(float));
}

std::string uint16_bytes(const std::vector<uint16_t>& v) {
    std::string out;
    for (uint16_t x : v) put(out, x, 2);
    return out;
}

std::string tensor_bytes(const std::vector<OutField>& fields) {
    size_t header = 18;
    for (const OutField& f : fields) header += 2 + f.name.size() + 2 + 1 + 8 + 8 * f.shape.size();
    std::string out("tensor_file", 12);  // with its terminating zero
    out.push_back(1);
    out.push_back(0);
    put(out, fields.size(), 4);
    std::vector<uint64_t> offsets;
    uint64_t offset = (header + 7) / 8 * 8;
    for (const OutField& f : fields) {
        put(out, f.name.size(), 2);
        out += f.name;
        put(out, f.shape.size(), 2);
        put(out, uint64_t(f.dtype), 1);
        put(out, offset, 8);
        for (uint64_t s : f.shape) put(out, s, 8);
        offsets.push_back(offset);
        offset = (offset + f.data.size() + 7) / 8 * 8;
    }
    for (size_t i = 0; i < fields.size(); ++i) {
        out.resize(size_t(offsets[i]), '\0');
        out += fields[i].data;
    }
    return out;
}

void write_bytes(const std::filesystem::path& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

}  // namespace candela::test
