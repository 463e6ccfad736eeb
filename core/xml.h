#pragma once
// Loads Mitsuba 3 XML scene files (pugixml): <default> and $name substitution in any attribute,
// -D overrides, <include>, <ref> with and without name, ids, the property tags (integer, float,
// boolean, string, point, vector, rgb, spectrum with one value, transform) and the transform
// operations (translate, rotate, scale, matrix with 16 or 9 values, lookat) composed in document
// order. Every error is a SceneError naming the file and line.

#include "core/scene.h"

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace candela {

using SceneParameters = std::map<std::string, std::string>;

// Folders searched for the files a scene names after the scene's own folder and the working
// directory (Mitsuba's `mitsuba -a`): shared assets, such as mitsuba-data's common/ folder, that
// scenes name without a <path>. A folder that does not exist is a SceneError.
using SearchFolders = std::vector<std::filesystem::path>;

Ref<Scene> load_scene(const std::string& path, const SceneParameters& defines = {}, const SearchFolders& search_folders = {});
// Parses XML text as if it were the file `virtual_path` (relative paths resolve beside it).
Ref<Scene> load_scene_from_string(const std::string& xml, const std::string& virtual_path,
                                  const SceneParameters& defines = {}, const SearchFolders& search_folders = {});

}  // namespace candela
