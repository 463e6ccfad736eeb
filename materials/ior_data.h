#pragma once
// The text of the measured index-of-refraction files in materials/data/ior (NAME.eta.spd and
// NAME.k.spd, from Mitsuba's data), compiled into the program by CMakeLists.txt.

#include <vector>

namespace candela {

struct EmbeddedFile {
    const char* name;  // e.g. "Au.eta.spd"
    const char* text;
};

const std::vector<EmbeddedFile>& ior_data_files();

}  // namespace candela
