#pragma once
// A writer of Mitsuba's binary .vol grids (see media/gridvolume.cpp for the format), for tests
// that need grids with known answers and for the media benchmark.

#include "core/math.h"

#include <filesystem>
#include <string>
#include <vector>

namespace candela {

// Writes `values` (x fastest, then y, then z, `channels` per voxel) with the given bounding box.
void write_vol(const std::filesystem::path& path, const glm::ivec3& resolution, int channels, const std::vector<float>& values,
               const BoundingBox& bbox = BoundingBox{Vec3(0.0f), Vec3(1.0f)});

}  // namespace candela
