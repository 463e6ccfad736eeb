// Reconstruction filters: each integrates to one and has Mitsuba's default radius.

#include "core/filter.h"
#include "core/properties.h"
#include "core/registry.h"

#include <catch2/catch.hpp>

using namespace candela;

TEST_CASE("filters: each reconstruction filter integrates to one", "[film]") {
    for (const char* name : {"box", "tent", "gaussian", "mitchell", "catmullrom", "lanczos"}) {
        for (float param : {0.0f, 0.3f, 0.75f}) {
            Properties props(name, SourceLocation{"test", 0});
            const std::string type = name;
            if (param > 0.0f && type == "tent") props.set_float("radius", 2.0 * param);
            if (param > 0.0f && type == "gaussian") props.set_float("stddev", param);
            if (param > 0.0f && type == "mitchell") {  // B = 0.3 or 0.75 with C = 1 - B, and the reverse
                props.set_float("B", param);
                props.set_float("C", 1.0f - param);
            }
            if (param > 0.0f && type == "lanczos") props.set_int("lobes", param < 0.5f ? 2 : 4);
            if (param > 0.0f && (type == "box" || type == "catmullrom")) continue;
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

TEST_CASE("filters: Mitsuba's defaults (box 0.5, tent 1, gaussian stddev 0.5 radius 2, mitchell and catmullrom 2, lanczos 3)", "[film]") {
    auto make = [](const char* n) { return create_plugin_as<ReconstructionFilter>(ObjectKind::Filter, Properties(n, SourceLocation{})); };
    CHECK(make("box")->radius() == 0.5f);
    CHECK(make("tent")->radius() == 1.0f);
    CHECK(make("gaussian")->radius() == 2.0f);
    CHECK(make("mitchell")->radius() == 2.0f);
    CHECK(make("catmullrom")->radius() == 2.0f);
    CHECK(make("lanczos")->radius() == 3.0f);
}

TEST_CASE("filters: the cubic and windowed-sinc filters have their closed forms' values", "[film]") {
    auto make = [](const char* n) { return create_plugin_as<ReconstructionFilter>(ObjectKind::Filter, Properties(n, SourceLocation{})); };
    // Mitchell-Netravali with B = C = 1/3: (6 - 2B) / 6 = 8/9 at 0, (8B + 24C) / 6 - ... = B / 6
    // = 1/18 at 1 (both pieces agree there), 0 at 2; negative lobe between 1 and 2.
    auto mitchell = make("mitchell");
    CHECK(mitchell->eval(0.0f) == Approx(8.0 / 9.0).epsilon(1e-6));
    CHECK(mitchell->eval(1.0f) == Approx(1.0 / 18.0).epsilon(1e-5));
    CHECK(mitchell->eval(-1.0f) == mitchell->eval(1.0f));
    CHECK(mitchell->eval(1.5f) < 0.0f);
    CHECK(mitchell->eval(2.0f) == 0.0f);
    // Catmull-Rom interpolates: 1 at the centre, 0 at the neighbours; at 1.5 it is -1/16.
    auto catmullrom = make("catmullrom");
    CHECK(catmullrom->eval(0.0f) == Approx(1.0).epsilon(1e-6));
    CHECK(catmullrom->eval(1.0f) == Approx(0.0).margin(1e-6));
    CHECK(catmullrom->eval(1.5f) == Approx(-1.0 / 16.0).epsilon(1e-5));
    // Lanczos, 3 lobes: relative to the centre, sinc(pi x) sinc(pi x / 3); zero at whole x.
    auto lanczos = make("lanczos");
    const double pi = 3.14159265358979323846;
    for (double x : {0.25, 0.5, 1.5, 2.5}) {
        double expected = std::sin(pi * x) / (pi * x) * std::sin(pi * x / 3.0) / (pi * x / 3.0);
        INFO("x = " << x);
        CHECK(lanczos->eval(float(x)) / lanczos->eval(0.0f) == Approx(expected).epsilon(1e-5).margin(1e-6));
    }
    CHECK(lanczos->eval(1.0f) / lanczos->eval(0.0f) == Approx(0.0).margin(1e-6));
    CHECK(lanczos->eval(3.0f) == 0.0f);
}

TEST_CASE("filters: parameters out of range are errors at their property", "[film][errors]") {
    auto fails = [](const char* type, const char* name, double value, const char* message) {
        Properties props(type, SourceLocation{"scene.xml", 7});
        if (std::string(name) == "lobes")
            props.set_int(name, int(value));
        else
            props.set_float(name, value);
        INFO(type << " " << name << " = " << value);
        CHECK_THROWS_WITH(create_plugin_as<ReconstructionFilter>(ObjectKind::Filter, props),
                          Catch::Contains("scene.xml") && Catch::Contains(message));
    };
    fails("lanczos", "lobes", 0, "lanczos lobes must be 1 to 4");
    fails("lanczos", "lobes", 5, "lanczos lobes must be 1 to 4");
    fails("mitchell", "B", 3.0, "mitchell B must be below 3");
}
