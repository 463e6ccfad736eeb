// The raster mode keeps its frame buffers from frame to frame (issue: "no per-frame
// allocation"): a second frame of the same scene and size allocates no storage per camera sample,
// per triangle or per vertex. What it may allocate is its output (the image handed back) and a
// fixed handful of small objects: the sample pattern, the light list, the options.

#include "core/integrator.h"
#include "core/xml.h"
#include "integrators/raster/raster.h"
#include "tests/allocation_counter.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

using namespace candela;
using namespace candela::test;

TEST_CASE("raster: a repeated frame allocates nothing per sample, triangle or vertex", "[raster][memory]") {
    if (!allocations_counted()) {
        WARN("allocation counting is not available in sanitizer builds: not checked");
        return;
    }
    // 256 x 256 samples: one float per sample is 256 KiB, one byte per pixel 64 KiB, both far
    // above the fixed allowance below.
    Ref<Scene> scene = load_scene(source_path("scenes/validation/cbox.xml"), {{"res", "256"}});
    // The fixed objects of a frame get 16 KiB and 32 allocations, whatever the image size or the
    // triangle count: the sample pattern, the light list and the options (well under 100 bytes
    // each), and the stream buffer (8 KiB) of the memory check's read of /proc/meminfo.
    const size_t fixed_bytes = 16384, fixed_calls = 32;
    for (const auto& [shading, shadows] : {std::pair{"phong", "map"}, std::pair{"gouraud", "map"}, std::pair{"flat", "none"}}) {
        INFO(shading << " shading, shadows " << shadows);
        RasterSettings settings;
        std::string error;
        REQUIRE(settings.set("shading", shading, error));
        REQUIRE(settings.set("shadows", shadows, error));
        RasterIntegrator raster(settings);
        RenderOptions options;
        options.threads = 2;
        RenderResult first = raster.render(*scene, options);  // builds geometry and buffers
        size_t calls = 0, bytes = 0;
        RenderResult second;
        {
            AllocationCount count;
            second = raster.render(*scene, options);
            calls = count.calls();
            bytes = count.bytes();
        }
        const size_t output_bytes = second.image.data().size() * sizeof(float);
        INFO("allocations " << calls << ", bytes " << bytes << ", of which the output image " << output_bytes);
        CHECK(bytes <= output_bytes + fixed_bytes);
        CHECK(calls <= fixed_calls);
        // The same frame again: the reused buffers hold nothing of the last one.
        CHECK(second.image.data() == first.image.data());
    }
}
