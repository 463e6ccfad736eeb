#pragma once
// A test-only writer of Mitsuba's tensor files (core/tensor_file.h has the layout): the measured
// and measured_polarized tests write their tables with it.

#include "core/tensor_file.h"

#include <filesystem>
#include <string>
#include <vector>

namespace candela::test {

struct OutField {
    std::string name;
    TensorType dtype;
    std::vector<uint64_t> shape;
    std::string data;  // the raw little-endian values
};

std::string float_bytes(const std::vector<float>& v);
std::string uint16_bytes(const std::vector<uint16_t>& v);
// The whole file: header, then each field's data at an offset aligned to 8 bytes.
std::string tensor_bytes(const std::vector<OutField>& fields);
void write_bytes(const std::filesystem::path& path, const std::string& bytes);

}  // namespace candela::test
