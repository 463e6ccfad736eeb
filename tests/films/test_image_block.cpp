// ImageBlock::put: where a sample's weight lands. The box filter's one-pixel footprint takes a
// shortcut (core/film.cpp); it must give what the general weight loops give: the whole weight to
// the pixel whose square (x, x + 1] holds the sample (the box's support is half-open, so a sample
// exactly on an edge counts once, for the pixel to its left or above), and the tent filter's
// weights over its 2 x 2 pixels.

#include "core/film.h"
#include "core/filter.h"
#include "core/properties.h"
#include "core/registry.h"

#include <catch2/catch.hpp>

using namespace candela;

namespace {

Ref<ReconstructionFilter> make_filter(const char* name) {
    return create_plugin_as<ReconstructionFilter>(ObjectKind::Filter, Properties(name, SourceLocation{"test", 0}));
}

// The block's sums over a 4 x 4 film (RGB, then weight, per pixel), after one put.
std::vector<double> splat(const ReconstructionFilter& filter, const Vec2& pos, const Spectrum& value) {
    const Vec2i size(4, 4);
    ImageBlock block(Vec2i(0), size, &filter);
    block.put(pos, value);
    std::vector<double> sums(size_t(size.x) * size.y * 4, 0.0);
    block.accumulate_into(sums, size);
    return sums;
}

double weight_at(const std::vector<double>& sums, int x, int y) { return sums[(size_t(y) * 4 + x) * 4 + 3]; }

}  // namespace

TEST_CASE("image block: a box-filtered sample lands whole in the pixel holding it", "[film]") {
    auto box = make_filter("box");
    const Spectrum value(0.25f, 0.5f, 2.0f);
    struct Case {
        Vec2 pos;
        Vec2i pixel;
    };
    // Inside a pixel; on an edge (owned by the pixel left of or above it); just short of the next
    // pixel; on the film's far edge (the last pixel's); on its first corner (nobody's).
    for (const Case& c : {Case{{1.3f, 2.7f}, {1, 2}}, Case{{2.0f, 1.0f}, {1, 0}}, Case{{std::nextafter(3.0f, 0.0f), 0.5f}, {2, 0}},
                          Case{{4.0f, 4.0f}, {3, 3}}, Case{{0.0f, 0.0f}, {0, 0}}}) {
        INFO("sample at " << c.pos.x << ", " << c.pos.y);
        std::vector<double> sums = splat(*box, c.pos, value);
        double total = 0.0;
        for (int y = 0; y < 4; ++y)
            for (int x = 0; x < 4; ++x) total += weight_at(sums, x, y);
        const size_t at = (size_t(c.pixel.y) * 4 + c.pixel.x) * 4;
        if (c.pos == Vec2(0.0f)) {
            // The film's first edge belongs to the pixel before it, which is not stored.
            CHECK(total == 0.0);
            continue;
        }
        CHECK(total == 1.0);
        CHECK(sums[at + 3] == 1.0);
        CHECK(sums[at + 0] == 0.25);
        CHECK(sums[at + 1] == 0.5);
        CHECK(sums[at + 2] == 2.0);
    }
}

TEST_CASE("image block: a tent-filtered sample spreads the filter's weights over its pixels", "[film]") {
    auto tent = make_filter("tent");
    const Vec2 pos(1.3f, 2.6f);
    std::vector<double> sums = splat(*tent, pos, Spectrum(1.0f));
    double total = 0.0;
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) {
            const double expected = tent->eval(float(x) + 0.5f - pos.x) * tent->eval(float(y) + 0.5f - pos.y);
            INFO("pixel " << x << ", " << y);
            CHECK(weight_at(sums, x, y) == Approx(expected).margin(1e-7));
            total += weight_at(sums, x, y);
        }
    CHECK(total > 0.0);
}
