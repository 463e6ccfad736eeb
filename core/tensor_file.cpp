#include "core/tensor_file.h"

#include "core/byte_order.h"
#include "core/error.h"
#include "core/memory_budget.h"

#include <algorithm>
#include <cstring>
#include <fstream>
#include <tuple>

namespace candela {

namespace {

// Reads little-endian integers from the file's bytes, failing past its end.
class HeaderReader {
public:
    HeaderReader(const TensorFile& file, const std::vector<uint8_t>& data) : file_(file), data_(data) {}

    uint64_t unsigned_int(size_t bytes, const char* what) {
        need(bytes, what);
        const uint64_t v = read_little_endian(data_.data() + pos_, bytes);
        pos_ += bytes;
        return v;
    }
    std::string text(size_t bytes, const char* what) {
        need(bytes, what);
        std::string s(reinterpret_cast<const char*>(data_.data() + pos_), bytes);
        pos_ += bytes;
        return s;
    }
    size_t remaining() const { return data_.size() - pos_; }
    size_t position() const { return pos_; }

private:
    void need(size_t bytes, const char* what) {
        if (bytes > remaining())
            file_.fail(std::string("truncated: the file ends inside ") + what + " (at byte " + std::to_string(pos_) + " of " +
                       std::to_string(data_.size()) + ")");
    }
    const TensorFile& file_;
    const std::vector<uint8_t>& data_;
    size_t pos_ = 0;
};

// Smallest header entry of a field: name length, ndim, dtype, offset (an empty name, ndim 0).
constexpr size_t MinFieldHeader = 2 + 2 + 1 + 8;
constexpr size_t FileHeader = 12 + 2 + 4;

}  // namespace

size_t tensor_type_size(TensorType type) {
    switch (type) {
        case TensorType::UInt8:
        case TensorType::Int8: return 1;
        case TensorType::UInt16:
        case TensorType::Int16:
        case TensorType::Float16: return 2;
        case TensorType::UInt32:
        case TensorType::Int32:
        case TensorType::Float32: return 4;
        case TensorType::UInt64:
        case TensorType::Int64:
        case TensorType::Float64: return 8;
        default: return 0;
    }
}

const char* tensor_type_name(TensorType type) {
    static const char* names[] = {"invalid", "uint8",  "int8",  "uint16",  "int16",   "uint32",
                                  "int32",   "uint64", "int64", "float16", "float32", "float64"};
    size_t i = size_t(type);
    return i < sizeof(names) / sizeof(names[0]) ? names[i] : "invalid";
}

uint64_t TensorField::count() const {
    uint64_t n = 1;
    for (uint64_t s : shape) n = saturating_mul(n, s);
    return n;
}

void TensorFile::fail(const std::string& message) const { throw InputError(path_ + ": " + message); }

TensorFile::TensorFile(const std::string& path) : path_(path) {
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    if (!in) fail("cannot open the file");
    std::streamoff end = in.tellg();
    if (end < 0) fail("cannot read the file's size");
    uint64_t size = uint64_t(end);
    check_memory(size, "the tensor file \"" + path + "\"");
    data_.resize(size_t(size));
    in.seekg(0);
    if (!in.read(reinterpret_cast<char*>(data_.data()), std::streamsize(size))) fail("cannot read the file");
    parse();
}

TensorFile::TensorFile(std::string name, std::vector<uint8_t> bytes) : path_(std::move(name)), data_(std::move(bytes)) { parse(); }

void TensorFile::parse() {
    const uint64_t size = data_.size();
    if (size < FileHeader) fail("truncated: " + std::to_string(size) + " bytes, shorter than the 18-byte header of a tensor file");
    HeaderReader r(*this, data_);
    if (r.text(12, "the magic") != std::string("tensor_file", 12)) fail("not a tensor file (it does not start with \"tensor_file\")");
    unsigned major = unsigned(r.unsigned_int(1, "the version")), minor = unsigned(r.unsigned_int(1, "the version"));
    if (major != 1 || minor != 0) fail("version " + std::to_string(major) + "." + std::to_string(minor) + " is not supported (only 1.0)");
    uint64_t n_fields = r.unsigned_int(4, "the field count");
    // Each field needs at least MinFieldHeader bytes: a count the file cannot hold is an error
    // before anything is read or allocated for it.
    if (n_fields > r.remaining() / MinFieldHeader)
        fail("the header declares " + std::to_string(n_fields) + " fields, more than its " + std::to_string(size) + " bytes can hold");
    for (uint64_t i = 0; i < n_fields; ++i) {
        size_t name_length = size_t(r.unsigned_int(2, "a field's name length"));
        std::string name = r.text(name_length, "a field's name");
        size_t ndim = size_t(r.unsigned_int(2, "a field's dimension count"));
        uint64_t dtype = r.unsigned_int(1, "a field's type");
        TensorField f;
        f.offset = r.unsigned_int(8, "a field's offset");
        if (dtype == 0 || dtype > uint64_t(TensorType::Float64))
            fail("field \"" + name + "\" has the unknown type code " + std::to_string(dtype));
        f.dtype = TensorType(dtype);
        if (ndim > r.remaining() / 8) fail("truncated: the file ends inside the shape of field \"" + name + "\"");
        f.shape.resize(ndim);
        for (size_t j = 0; j < ndim; ++j) f.shape[j] = r.unsigned_int(8, "a field's shape");
        uint64_t bytes = saturating_mul(f.count(), tensor_type_size(f.dtype));
        if (f.offset > size || bytes > size - f.offset) {
            std::string shape;
            for (uint64_t s : f.shape) shape += (shape.empty() ? "" : ", ") + std::to_string(s);
            fail("field \"" + name + "\" (" + tensor_type_name(f.dtype) + " [" + shape + "] at offset " + std::to_string(f.offset) +
                 ") reaches past the end of the file (" + std::to_string(size) + " bytes)");
        }
        if (!fields_.emplace(name, std::move(f)).second) fail("field \"" + name + "\" appears twice");
    }
    // The data of each field lies after the header and apart from the others': a shape larger
    // than its data would read another field's values.
    std::vector<std::tuple<uint64_t, uint64_t, std::string>> extents;
    for (const auto& [name, f] : fields_) {
        uint64_t bytes = f.count() * tensor_type_size(f.dtype);
        if (bytes == 0) continue;
        if (f.offset < r.position()) fail("field \"" + name + "\" starts at offset " + std::to_string(f.offset) + ", inside the header");
        extents.emplace_back(f.offset, f.offset + bytes, name);
    }
    std::sort(extents.begin(), extents.end());
    for (size_t i = 1; i < extents.size(); ++i)
        if (std::get<0>(extents[i]) < std::get<1>(extents[i - 1]))
            fail("field \"" + std::get<2>(extents[i - 1]) + "\" (" +
                 std::to_string(std::get<1>(extents[i - 1]) - std::get<0>(extents[i - 1])) + " bytes at offset " +
                 std::to_string(std::get<0>(extents[i - 1])) + ") overlaps field \"" + std::get<2>(extents[i]) + "\"");
}

const TensorField& TensorFile::field(const std::string& name) const {
    auto it = fields_.find(name);
    if (it == fields_.end()) fail("no field \"" + name + "\" (the file has: " + describe() + ")");
    return it->second;
}

template <typename T>
std::vector<T> TensorFile::values(const std::string& name, TensorType type) const {
    const TensorField& f = field(name);
    if (f.dtype != type) fail("field \"" + name + "\" is " + tensor_type_name(f.dtype) + ", expected " + tensor_type_name(type));
    std::vector<T> out(size_t(f.count()));
    // The format is little-endian, as is every machine Candela builds for (core/byte_order.h).
    if (!out.empty()) std::memcpy(out.data(), data_.data() + f.offset, out.size() * sizeof(T));
    return out;
}

std::vector<float> TensorFile::floats(const std::string& name) const { return values<float>(name, TensorType::Float32); }
std::vector<double> TensorFile::doubles(const std::string& name) const { return values<double>(name, TensorType::Float64); }
std::vector<uint8_t> TensorFile::bytes(const std::string& name) const { return values<uint8_t>(name, TensorType::UInt8); }
std::vector<uint16_t> TensorFile::uint16s(const std::string& name) const { return values<uint16_t>(name, TensorType::UInt16); }

std::string TensorFile::describe() const {
    std::string out;
    for (const auto& [name, f] : fields_) {
        std::string shape;
        for (uint64_t s : f.shape) shape += (shape.empty() ? "" : ", ") + std::to_string(s);
        out += (out.empty() ? "" : "; ") + name + ": " + tensor_type_name(f.dtype) + " [" + shape + "]";
    }
    return out.empty() ? "no fields" : out;
}

}  // namespace candela
