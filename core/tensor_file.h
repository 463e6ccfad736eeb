#pragma once
// Mitsuba's tensor file (Mitsuba 3's TensorFile, src/core/tensor.cpp; the format of RGL's
// measured `.bsdf` files, Dupuy & Jakob 2018): named n-dimensional arrays in one binary file,
// little endian.
//
//   bytes 0-11   "tensor_file\0"
//   bytes 12-13  version: major, minor (1, 0)
//   bytes 14-17  uint32 field count
//   per field    uint16 name length, the name, uint16 ndim, uint8 dtype, uint64 offset of the
//                data from the start of the file, ndim x uint64 shape (row-major, last fastest)
//
// dtype codes: 1 uint8, 2 int8, 3 uint16, 4 int16, 5 uint32, 6 int32, 7 uint64, 8 int64,
// 9 float16, 10 float32, 11 float64 (0 is invalid).
//
// A malformed, truncated or inconsistent file is an InputError "<path>: <what is wrong>". Sizes
// from the header are checked against the file's length before anything is allocated by them.

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace candela {

enum class TensorType : uint8_t { Invalid = 0, UInt8, Int8, UInt16, Int16, UInt32, Int32, UInt64, Int64, Float16, Float32, Float64 };

// Bytes per element (0 for Invalid).
size_t tensor_type_size(TensorType type);
const char* tensor_type_name(TensorType type);

struct TensorField {
    TensorType dtype = TensorType::Invalid;
    uint64_t offset = 0;          // of the data, from the start of the file
    std::vector<uint64_t> shape;  // row-major, the last dimension fastest
    uint64_t count() const;       // product of the shape (1 for ndim 0)
};

class TensorFile {
public:
    // Reads the whole file (its size checked against the memory budget first).
    explicit TensorFile(const std::string& path);
    // The same from bytes already in memory (data compiled into the program); `name` stands for
    // the path in error messages.
    TensorFile(std::string name, std::vector<uint8_t> bytes);

    const std::string& path() const { return path_; }
    bool has_field(const std::string& name) const { return fields_.count(name) != 0; }
    // The field's description; InputError naming the file when it is missing.
    const TensorField& field(const std::string& name) const;
    // A float32 field's values; InputError when the field is missing or of another type.
    std::vector<float> floats(const std::string& name) const;
    // A float64 field's values; InputError when the field is missing or of another type.
    std::vector<double> doubles(const std::string& name) const;
    // A uint8 field's bytes; InputError when the field is missing or of another type.
    std::vector<uint8_t> bytes(const std::string& name) const;
    // A uint16 field's values; InputError when the field is missing or of another type.
    std::vector<uint16_t> uint16s(const std::string& name) const;
    // "name: float32 [2, 3], ..." for error messages.
    std::string describe() const;

    // InputError "<path>: <message>".
    [[noreturn]] void fail(const std::string& message) const;

private:
    // Reads the header from data_ and checks every field against the data's size.
    void parse();
    // The values of field `name`, which must be of type `type` (T its C++ type).
    template <typename T>
    std::vector<T> values(const std::string& name, TensorType type) const;

    std::string path_;
    std::vector<uint8_t> data_;
    std::map<std::string, TensorField> fields_;
};

}  // namespace candela
