// Reconstruction filters: each integrates to one and has Mitsuba's default radius.

#include "core/filter.h"
#include "core/properties.h"
#include "core/registry.h"

#include <catch2/catch.hpp>

using namespace candela;

TEST_CASE("filters: each reconstruction filter integrates to one", "[film]") {
    for (const char* name : {"box", "tent", "gaussian"}) {
        for (float param : {0.0f, 0.3f, 0.75f}) {
            Properties props(name, SourceLocation{"test", 0});
            if (param > 0.0f && std::string(name) == "tent") props.set_float("radius", 2.0 * param);
            if (param > 0.0f && std::string(name) == "gaussian") props.set_float("stddev", param);
            if (param > 0.0f && std::string(name) == "box") continue;
            auto f = create_plugin_as<ReconstructionFilter>(ObjectKind::Filter, props);
            // Midpoint rule on a fine grid over the support.
            const int n = 200000;
            double r = f->radius(), h = 2.0 * r / n, sum = 0.0;
            for (int i = 0; i < n; ++i) sum += f->eval(float(-r + (i + 0.5) * h));
            INFO(name << " " << param);
            CHECK(sum * h == Approx(1.0).epsilon(1e-4));
            CHECK(f->eval(float(r) * 1.0001f) == 0.0f);
        }
    }
}

TEST_CASE("filters: Mitsuba's defaults (box 0.5, tent 1, gaussian stddev 0.5 radius 2)", "[film]") {
    auto make = [](const char* n) { return create_plugin_as<ReconstructionFilter>(ObjectKind::Filter, Properties(n, SourceLocation{})); };
    CHECK(make("box")->radius() == 0.5f);
    CHECK(make("tent")->radius() == 1.0f);
    CHECK(make("gaussian")->radius() == 2.0f);
}
