#pragma once
// Loads Mitsuba 3 XML scene files (pugixml): <default> and $name substitution in any attribute,
// -D overrides, <include>, <ref> with and without name, ids, the property tags (integer, float,
// boolean, string, point, vector, rgb, spectrum with one value, transform) and the transform
// operations (translate, rotate, scale, matrix with 16 or 9 values, lookat) composed in document
// order. Every error is a SceneError naming the file and line.

#include "core/scene.h"

#include <map>
#include <string>

namespace candela {

using SceneParameters = std::map<std::string, std::string>;

// `variant`: what the scene is loaded for (core/variant.h); plugins that cannot render in it stop
// at their element, and in the spectral variant measured spectra are kept for use per wavelength.
// `sensor_index`: which of the file's sensors the scene renders (Scene's constructor).
Ref<Scene> load_scene(const std::string& path, const SceneParameters& defines = {}, Variant variant = Variant::ScalarRGB,
                      int sensor_index = 0);
// Parses XML text as if it were the file `virtual_path` (relative paths resolve beside it).
Ref<Scene> load_scene_from_string(const std::string& xml, const std::string& virtual_path, const SceneParameters& defines = {},
                                  Variant variant = Variant::ScalarRGB, int sensor_index = 0);

}  // namespace candela
