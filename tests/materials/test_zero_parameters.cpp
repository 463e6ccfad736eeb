// Every BSDF with its parameters at zero (black reflectances and transmittances, zero weights
// and roughness where the plugin accepts it): eval, pdf and sampling stay finite, a black BSDF
// reflects nothing, and a render of it drops no sample as non-finite. Before issue 28,
// plastic, roughplastic and pplastic with both reflectances black chose their lobe with
// s / (d + s) = 0 / 0 and returned NaN.

#include "core/integrator.h"
#include "core/scene.h"
#include "tests/bsdf_harness.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

using namespace candela;
using namespace candela::test;

namespace {

struct ZeroCase {
    std::string name, xml;
    bool black = true;  // reflects and transmits nothing (false: what passes a Null lobe, or a lossless fibre)
};

const std::vector<ZeroCase>& zero_cases() {
    static const std::string black_diffuse = R"(<bsdf type="diffuse"><rgb name="reflectance" value="0"/></bsdf>)";
    static const std::vector<ZeroCase> cases = {
        {"diffuse", black_diffuse},
        {"phong", R"(<bsdf type="phong"><rgb name="kd" value="0"/><rgb name="ks" value="0"/><float name="exponent" value="0"/></bsdf>)"},
        {"blinnphong",
         R"(<bsdf type="blinnphong"><rgb name="kd" value="0"/><rgb name="ks" value="0"/><float name="exponent" value="0"/></bsdf>)"},
        {"conductor", R"(<bsdf type="conductor"><rgb name="specular_reflectance" value="0"/></bsdf>)"},
        {"conductor eta k 0", R"(<bsdf type="conductor"><rgb name="eta" value="0"/><rgb name="k" value="0"/></bsdf>)", false},
        {"roughconductor",
         R"(<bsdf type="roughconductor"><rgb name="specular_reflectance" value="0"/><float name="alpha" value="0"/></bsdf>)"},
        {"dielectric",
         R"(<bsdf type="dielectric"><rgb name="specular_reflectance" value="0"/><rgb name="specular_transmittance" value="0"/></bsdf>)"},
        {"thindielectric",
         R"(<bsdf type="thindielectric"><rgb name="specular_reflectance" value="0"/><rgb name="specular_transmittance" value="0"/></bsdf>)"},
        {"roughdielectric", R"(<bsdf type="roughdielectric"><rgb name="specular_reflectance" value="0"/>
            <rgb name="specular_transmittance" value="0"/><float name="alpha" value="0"/></bsdf>)"},
        {"plastic",
         R"(<bsdf type="plastic"><rgb name="diffuse_reflectance" value="0"/><rgb name="specular_reflectance" value="0"/></bsdf>)"},
        {"plastic nonlinear",
         R"(<bsdf type="plastic"><rgb name="diffuse_reflectance" value="0"/><rgb name="specular_reflectance" value="0"/>
            <boolean name="nonlinear" value="true"/></bsdf>)"},
        {"roughplastic", R"(<bsdf type="roughplastic"><rgb name="diffuse_reflectance" value="0"/>
            <rgb name="specular_reflectance" value="0"/><float name="alpha" value="0"/></bsdf>)"},
        {"pplastic",
         R"(<bsdf type="pplastic"><rgb name="diffuse_reflectance" value="0"/><rgb name="specular_reflectance" value="0"/></bsdf>)"},
        {"principled", R"(<bsdf type="principled"><rgb name="base_color" value="0"/><float name="roughness" value="0"/>
            <float name="specular" value="0"/><float name="spec_trans" value="0"/><float name="metallic" value="0"/>
            <float name="clearcoat" value="0"/><float name="sheen" value="0"/></bsdf>)"},
        {"principledthin", R"(<bsdf type="principledthin"><rgb name="base_color" value="0"/><float name="roughness" value="0"/>
            <float name="spec_trans" value="0"/><float name="diff_trans" value="0"/><float name="sheen" value="0"/></bsdf>)",
         false},
        {"hair", R"(<bsdf type="hair"><float name="eumelanin" value="0"/><float name="pheomelanin" value="0"/>
            <float name="longitudinal_roughness" value="0"/><float name="azimuthal_roughness" value="0"/></bsdf>)",
         false},
        {"twosided", "<bsdf type=\"twosided\">" + black_diffuse + "</bsdf>"},
        {"blendbsdf", "<bsdf type=\"blendbsdf\"><float name=\"weight\" value=\"0\"/>" + black_diffuse + black_diffuse + "</bsdf>"},
        {"mask", "<bsdf type=\"mask\"><float name=\"opacity\" value=\"0\"/>" + black_diffuse + "</bsdf>", false},
        {"mask opaque", "<bsdf type=\"mask\"><float name=\"opacity\" value=\"1\"/>" + black_diffuse + "</bsdf>"},
        {"bumpmap",
         "<bsdf type=\"bumpmap\"><texture type=\"checkerboard\"/><float name=\"scale\" value=\"0\"/>" + black_diffuse + "</bsdf>"},
        {"normalmap",
         "<bsdf type=\"normalmap\"><texture type=\"checkerboard\" name=\"normalmap\"><rgb name=\"color0\" value=\"0.5, 0.5, 1\"/>"
         "<rgb name=\"color1\" value=\"0.5, 0.5, 1\"/></texture>" +
             black_diffuse + "</bsdf>"},
        {"polarizer", R"(<bsdf type="polarizer"><rgb name="transmittance" value="0"/></bsdf>)"},
        {"circular", R"(<bsdf type="circular"><rgb name="transmittance" value="0"/></bsdf>)"},
        {"null", R"(<bsdf type="null"/>)", false},
    };
    return cases;
}

bool finite(const Spectrum& s) { return std::isfinite(s.x) && std::isfinite(s.y) && std::isfinite(s.z); }

}  // namespace

TEST_CASE("bsdf: every BSDF with zero parameters is finite, and black when its reflectances are", "[bsdf]") {
    for (const ZeroCase& c : zero_cases()) {
        INFO(c.name << ": " << c.xml);
        BSDFUnderTest t = make_bsdf(c.xml);
        REQUIRE(t.bsdf);
        PCG32 rng(17, 3);
        int checked = 0;
        for (int i = 0; i < 2000; ++i) {
            // Incidence from both sides, grazing included.
            const float cos_i = i % 50 == 0 ? 0.0f : 2.0f * rng.next_float() - 1.0f;
            const SurfaceInteraction si = local_interaction(direction(cos_i, 6.2831853f * rng.next_float()));
            const Vec3 wo = direction(2.0f * rng.next_float() - 1.0f, 6.2831853f * rng.next_float());
            const BSDFContext ctx;
            const Spectrum f = t.bsdf->eval(ctx, si, wo);
            const float pdf = t.bsdf->pdf(ctx, si, wo);
            const float u_lobe = rng.next_float();
            const Vec2 u(rng.next_float(), rng.next_float());
            const BSDFSample bs = t.bsdf->sample(ctx, si, u_lobe, u);
            CHECK(finite(f));
            CHECK(std::isfinite(pdf));
            CHECK(pdf >= 0.0f);
            CHECK(finite(t.bsdf->albedo(si)));
            if (bs.valid()) {
                CHECK(finite(bs.weight));
                CHECK(std::isfinite(bs.pdf));
                CHECK(std::isfinite(bs.wo.x + bs.wo.y + bs.wo.z));
            }
            if (c.black) {
                CHECK(max_component(f) == 0.0f);
                if (bs.valid()) CHECK(max_component(bs.weight) == 0.0f);
            }
            ++checked;
        }
        CHECK(checked == 2000);
    }
}

TEST_CASE("bsdf: a render of every BSDF with zero parameters drops no sample as non-finite", "[bsdf][integrator]") {
    const auto dir = scratch_dir("zero-bsdfs");
    for (const ZeroCase& c : zero_cases()) {
        INFO(c.name);
        // A sphere of it lit by an area light and an environment, seen by the path tracer.
        const std::string body = pinhole_camera("0, 0, 4", "0, 0, 0", 12, 12, 40) + R"(
            <integrator type="path"><integer name="max_depth" value="8"/></integrator>
            <emitter type="constant"><rgb name="radiance" value="0.5"/></emitter>
            <shape type="rectangle"><transform name="to_world"><translate z="3"/><rotate x="1" angle="180"/></transform>
                <emitter type="area"><rgb name="radiance" value="2"/></emitter></shape>
            <shape type="sphere">)" +
                                 c.xml + "</shape>";
        write_text(dir / "scene.xml", scene_xml(body));
        Ref<Scene> scene = load_scene((dir / "scene.xml").string());
        RenderOptions options;
        options.spp = 16;
        const RenderResult r = scene->integrator().render(*scene, options);
        CHECK(r.stats.nonfinite == 0);
        for (float v : r.image.data()) CHECK(std::isfinite(v));
    }
}
