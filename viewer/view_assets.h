#pragma once
// The viewer's page (viewer/assets/: index.html, app.js, app.css), compiled into the program by
// CMakeLists.txt (view_assets.cpp is generated from the files), so that nothing is fetched and
// nothing is installed beside the binary.

#include <cstddef>
#include <vector>

namespace candela {

struct ViewAsset {
    const char* path;  // "/", "/app.js", "/app.css"
    const char* mime;
    const char* data;
    size_t size;
};

const std::vector<ViewAsset>& view_assets();

}  // namespace candela
