// libFuzzer target for part files (farm/part_file.h), the files `candela merge` adds up and
// `candela render --resume` continues: untrusted input, since parts travel between machines.
//
// An input is either an OpenEXR file as it is (it starts with OpenEXR's magic number; the seeds
// include real parts of fuzz/scenes/part.xml, the target's TEMPLATE), or a part described as text, which reaches the
// pixel values that mutations of a ZIP-compressed EXR rarely decode to:
//   size WIDTH HEIGHT            (each clamped to [1, 64])
//   channels NAME,NAME,...       (the EXR's channels, in order)
//   KEY=VALUE                    (string metadata, e.g. candela.origin=3,2), any number
//   values                       (the rest of the input: float32 values, little-endian, filling
//                                 the pixels channel by channel, repeated as needed)
// The file is written, then merged on its own (check_parts, merge_image, merge_into_part) and
// resumed into a render of fuzz/scenes/part.xml at the seeds' settings (8 x 8, 4 spp, seed 3,
// AOVs variance and samples). The contract under test: each either succeeds with finite pixels
// or throws InputError naming the file. Anything else (another exception, a sanitizer report, a
// non-finite pixel) is a crash for libFuzzer.

#include "core/error.h"
#include "core/image.h"
#include "core/integrator.h"
#include "core/scene.h"
#include "core/xml.h"
#include "farm/merge.h"
#include "farm/resumable_render.h"
#include "tests/support/raw_exr.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace candela;

namespace {

constexpr int MaxSide = 64;

[[noreturn]] void crash(const std::string& why) {
    std::fprintf(stderr, "candela fuzz: %s\n", why.c_str());
    std::abort();
}

void require_finite(const Image& image, const char* what) {
    for (float v : image.data())
        if (!std::isfinite(v)) crash(std::string(what) + " holds a non-finite pixel");
}

struct Setup {
    fs::path dir;
    Ref<Scene> scene;
    std::string scene_path;
};

Setup& setup();

void remove_dir() {
    std::error_code ec;
    fs::remove_all(setup().dir, ec);
}

Setup& setup() {
    static Setup s = [] {
        Setup t;
        std::string pattern = (fs::temp_directory_path() / "candela-fuzz-part-XXXXXX").string();
        if (!mkdtemp(pattern.data())) crash("mkdtemp failed");
        t.dir = pattern;
        t.scene_path = CANDELA_FUZZ_TEMPLATE;
        t.scene = load_scene(t.scene_path);
        return t;
    }();
    static const bool cleanup = std::atexit(remove_dir) == 0;
    (void)cleanup;
    return s;
}

// The text form of a part (above) written as an EXR; false when it is not that form.
bool write_described_part(const std::string& text, const std::string& path) {
    const size_t values_at = text.find("\nvalues\n");
    std::istringstream head(text.substr(0, values_at == std::string::npos ? text.size() : values_at));
    int width = 1, height = 1;
    std::vector<std::string> channels;
    std::map<std::string, std::string> metadata;
    for (std::string line; std::getline(head, line);) {
        if (line.rfind("size ", 0) == 0) {
            std::sscanf(line.c_str() + 5, "%d %d", &width, &height);
        } else if (line.rfind("channels ", 0) == 0) {
            std::stringstream names(line.substr(9));
            for (std::string name; std::getline(names, name, ',');)
                if (!name.empty() && channels.size() < 64) channels.push_back(name);
        } else if (size_t eq = line.find('='); eq != std::string::npos && eq > 0) {
            metadata[line.substr(0, eq)] = line.substr(eq + 1);
        }
    }
    if (channels.empty()) return false;
    width = std::clamp(width, 1, MaxSide);
    height = std::clamp(height, 1, MaxSide);
    std::vector<float> floats;
    if (values_at != std::string::npos) {
        const std::string bytes = text.substr(values_at + 8);
        floats.resize(bytes.size() / sizeof(float));
        // An empty vector's data() may be null, and memcpy's arguments must never be.
        if (!floats.empty()) std::memcpy(floats.data(), bytes.data(), floats.size() * sizeof(float));
    }
    Image image(width, height, channels);
    std::vector<float>& data = image.data();
    for (size_t i = 0; i < data.size(); ++i) data[i] = floats.empty() ? 0.0f : floats[i % floats.size()];
    image.metadata = metadata;
    // As the values are, NaN included (candela's own write_exr would sanitise them).
    try {
        write_exr_as_is(image, path);
    } catch (const std::exception&) {
        return false;  // OpenEXR refuses it (e.g. two channels of one name)
    }
    return true;
}

void merge_alone(const std::string& path) {
    try {
        MergeSet set = check_parts({path});
        Image merged = merge_image(set);
        require_finite(merged, "the merged image");
        merge_into_part(set, (setup().dir / "merged.exr").string());
    } catch (const InputError& e) {
        if (std::string(e.what()).find(path) == std::string::npos) crash(std::string("merge: an error that names no file: ") + e.what());
    }
}

void resume_from(const std::string& path) {
    const Setup& s = setup();
    RenderOptions options;
    options.spp = 4;
    options.seed = 3;
    options.threads = 1;
    options.aovs = {"variance", "samples"};
    ResumableRequest request;
    request.scene_path = s.scene_path;
    request.command = "candela render part.xml";
    request.target = CoverageBox{ImageRect{Vec2i(0), s.scene->sensor().film().crop_size()}, SampleRange{0, 4}};
    request.resume = path;
    try {
        ResumableResult r = render_resumable(*s.scene, options, request);
        require_finite(r.sums.develop(), "the resumed render");
    } catch (const InputError& e) {
        if (std::string(e.what()).find(path) == std::string::npos) crash(std::string("resume: an error that names no file: ") + e.what());
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const Setup& s = setup();
    const std::string path = (s.dir / "part.exr").string();
    std::error_code ec;
    fs::remove(path, ec);
    const std::string input(reinterpret_cast<const char*>(data), size);
    static const char exr_magic[4] = {0x76, 0x2f, 0x31, 0x01};
    if (size >= 4 && std::memcmp(data, exr_magic, 4) == 0) {
        std::ofstream(path, std::ios::binary).write(input.data(), std::streamsize(input.size()));
    } else if (!write_described_part(input, path)) {
        return 0;
    }
    merge_alone(path);
    resume_from(path);
    return 0;
}
