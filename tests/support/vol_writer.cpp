#include "tests/support/vol_writer.h"

#include <cstring>
#include <fstream>
#include <stdexcept>

namespace candela {

void write_vol(const std::filesystem::path& path, const glm::ivec3& resolution, int channels, const std::vector<float>& values,
               const BoundingBox& bbox) {
    if (values.size() != size_t(resolution.x) * size_t(resolution.y) * size_t(resolution.z) * size_t(channels))
        throw std::invalid_argument("write_vol: the value count does not match the resolution");
    std::ofstream out(path, std::ios::binary);
    out.write("VOL", 3);
    out.put(char(3));
    int32_t header[5] = {1, resolution.x, resolution.y, resolution.z, channels};
    out.write(reinterpret_cast<const char*>(header), sizeof header);
    float box[6] = {bbox.min.x, bbox.min.y, bbox.min.z, bbox.max.x, bbox.max.y, bbox.max.z};
    out.write(reinterpret_cast<const char*>(box), sizeof box);
    out.write(reinterpret_cast<const char*>(values.data()), std::streamsize(values.size() * sizeof(float)));
}

}  // namespace candela
