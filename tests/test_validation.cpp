// Validation against Mitsuba 3: each scene of scenes/validation rendered by Candela agrees with
// Mitsuba 3.9's reference (refs/NAME.exr, 2048 spp) by the criteria of the validation README:
// whole-image channel means within 1% and 16x16 block luminance within 2% mean absolute
// relative difference. Rendered at 256 spp, where the metrics' own noise is far below both.

#include "core/image_metrics.h"
#include "core/xml.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

using namespace candela;
using namespace candela::test;

namespace {
void validate(const std::string& name, int spp = 256) {
    Ref<Scene> scene = load_scene(source_path("scenes/validation/" + name + ".xml"), {{"spp", std::to_string(spp)}});
    RenderOptions options;
    RenderResult r = scene->integrator().render(*scene, options);
    Image ref = read_image(source_path("scenes/validation/refs/" + name + ".exr"));
    ImageComparison c = compare_images(r.image, ref);
    std::string reason;
    bool ok = images_agree(c, AgreementThresholds{}, &reason);
    INFO(name << ": channel means " << 100 * c.mean_relative_difference.x << "% " << 100 * c.mean_relative_difference.y << "% "
              << 100 * c.mean_relative_difference.z << "%, block MARE " << 100 * c.block_mare << "% " << reason);
    CHECK(ok);
    CHECK(r.stats.nonfinite == 0);
}
}  // namespace

TEST_CASE("validation: cbox agrees with Mitsuba 3", "[validation]") { validate("cbox"); }
TEST_CASE("validation: glass agrees with Mitsuba 3", "[validation]") { validate("glass"); }
TEST_CASE("validation: plastics agrees with Mitsuba 3", "[validation]") { validate("plastics"); }
TEST_CASE("validation: roughglass agrees with Mitsuba 3", "[validation]") { validate("roughglass"); }
TEST_CASE("validation: textured agrees with Mitsuba 3", "[validation]") { validate("textured"); }
TEST_CASE("validation: lights agrees with Mitsuba 3", "[validation]") { validate("lights"); }
TEST_CASE("validation: envmap agrees with Mitsuba 3", "[validation]") { validate("envmap"); }
TEST_CASE("validation: conductors agrees with Mitsuba 3", "[validation]") { validate("conductors"); }
