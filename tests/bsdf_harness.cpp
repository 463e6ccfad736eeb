#include "tests/bsdf_harness.h"

#include "core/rng.h"
#include "core/warp.h"
#include "core/xml.h"
#include "tests/util.h"

#include <unistd.h>
#include <sstream>

namespace candela::test {

BSDFUnderTest make_bsdf(const std::string& bsdf_xml) {
    BSDFUnderTest t;
    std::string path = (std::filesystem::path(CANDELA_BINARY_DIR) / ("bsdf-" + std::to_string(::getpid()) + ".xml")).string();
    t.keep_alive = load_scene_from_string(scene_xml("<shape type=\"sphere\">" + bsdf_xml + "</shape>"), path);
    t.bsdf = t.keep_alive->shapes()[0]->bsdf();
    return t;
}

std::string lit_sphere_scene(const std::string& integrator_xml, const std::string& bsdf_xml) {
    return scene_xml(integrator_xml + R"(
        <sensor type="perspective"><float name="fov" value="40"/>
            <transform name="to_world"><lookat origin="0, -4, 1" target="0, 0, 0" up="0, 0, 1"/></transform>
            <sampler type="independent"><integer name="sample_count" value="4"/></sampler>
            <film type="hdrfilm"><integer name="width" value="24"/><integer name="height" value="24"/><rfilter type="box"/></film></sensor>
        <emitter type="constant"><rgb name="radiance" value="0.5"/></emitter>
        <emitter type="point"><point name="position" x="2" y="-3" z="3"/><rgb name="intensity" value="20"/></emitter>
        <shape type="sphere">)" +
                     bsdf_xml + "</shape>");
}

SurfaceInteraction local_interaction(const Vec3& wi) {
    SurfaceInteraction si;
    si.p = Vec3(0.0f);
    si.n = Vec3(0, 0, 1);
    si.shading = Frame();
    si.dpdu = Vec3(1, 0, 0);
    si.dpdv = Vec3(0, 1, 0);
    si.uv = Vec2(0.3f, 0.6f);
    si.wi = glm::normalize(wi);
    return si;
}

Vec3 direction(float cos_theta, float phi) {
    float s = safe_sqrt(1.0f - cos_theta * cos_theta);
    return Vec3(s * std::cos(phi), s * std::sin(phi), cos_theta);
}

SamplingCheck check_sampling(const BSDF& bsdf, const SurfaceInteraction& si, const BSDFContext& ctx, int n,
                             const std::vector<DeltaExpectation>& deltas, uint64_t seed) {
    SamplingCheck out;
    PCG32 rng(seed, 17);
    SphericalHistogram hist(10, 20);
    std::vector<double> delta_counts(deltas.size(), 0.0);
    double failed = 0.0, sum_w = 0.0, sum_w2 = 0.0;
    auto fail = [&](const std::string& what) {
        if (out.failures.size() < 5) out.failures.push_back(what);
    };
    for (int i = 0; i < n; ++i) {
        float u_lobe = rng.next_float();
        float a = rng.next_float();
        Vec2 u(a, rng.next_float());
        BSDFSample bs = bsdf.sample(ctx, si, u_lobe, u);
        if (!bs.valid()) {
            failed += 1.0;
            continue;
        }
        double w = average(bs.weight);
        sum_w += w;
        sum_w2 += w * w;
        if (!all_finite(bs.weight) || min_component(bs.weight) < 0.0f) fail("non-finite or negative weight");
        if (std::abs(glm::length(bs.wo) - 1.0f) > 1e-3f) fail("sampled direction not unit length");
        if (is_delta(bs.lobe)) {
            size_t k = 0;
            while (k < deltas.size() && deltas[k].lobe != bs.lobe) ++k;
            if (k == deltas.size()) {
                fail("sampled a delta lobe that was not expected");
                continue;
            }
            delta_counts[k] += 1.0;
            continue;
        }
        hist.add(bs.wo);
        // The sample must agree with eval and pdf (float rounding aside).
        float pdf = bsdf.pdf(ctx, si, bs.wo);
        Spectrum f = bsdf.eval(ctx, si, bs.wo);
        // eval_pdf is the two calls, bit for bit.
        const BSDFEvalPdf both = bsdf.eval_pdf(ctx, si, bs.wo);
        if (both.pdf != pdf || both.value != f) {
            std::ostringstream s;
            s << "eval_pdf (" << both.value.x << ", " << both.pdf << ") != eval, pdf (" << f.x << ", " << pdf << ")";
            fail(s.str());
        }
        if (std::abs(pdf - bs.pdf) > 1e-3f * std::max(pdf, bs.pdf)) {
            std::ostringstream s;
            s << "sample pdf " << bs.pdf << " != pdf() " << pdf;
            fail(s.str());
        }
        Spectrum expect = pdf > 0.0f ? f / pdf : Spectrum(0.0f);
        if (glm::length(expect - bs.weight) > 1e-3f * std::max(glm::length(expect), 1e-3f)) {
            std::ostringstream s;
            s << "weight (" << bs.weight.x << ") != eval/pdf (" << expect.x << ")";
            fail(s.str());
        }
    }
    std::vector<double> observed = hist.counts;
    std::vector<double> expected = hist.expected([&](const Vec3& wo) { return double(bsdf.pdf(ctx, si, wo)); }, double(n));
    double smooth_expected = 0.0;
    for (double e : expected) smooth_expected += e;
    double delta_expected = 0.0;
    for (size_t k = 0; k < deltas.size(); ++k) {
        observed.push_back(delta_counts[k]);
        expected.push_back(deltas[k].probability * n);
        delta_expected += deltas[k].probability * n;
    }
    // What neither the smooth pdf nor the delta lobes account for must be failed samples.
    observed.push_back(failed);
    expected.push_back(std::max(0.0, double(n) - smooth_expected - delta_expected));
    out.chi2 = chi_square(observed, expected);
    double mean = sum_w / n;
    out.albedo.mean = mean;
    out.albedo.std_error = std::sqrt(std::max(0.0, sum_w2 / n - mean * mean) / (n - 1));
    return out;
}

MeanAndError pdf_integral(const BSDF& bsdf, const SurfaceInteraction& si, const BSDFContext& ctx, int n, uint64_t seed) {
    PCG32 rng(seed, 23);
    std::vector<double> values(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) {
        float a = rng.next_float();
        Vec3 wo = warp::square_to_uniform_sphere(Vec2(a, rng.next_float()));
        values[size_t(i)] = double(bsdf.pdf(ctx, si, wo)) / double(warp::square_to_uniform_sphere_pdf());
    }
    return mean_and_error(values);
}

PointwiseDifference compare_pointwise(const BSDF& a, const BSDF& b, const BSDFContext& ctx, int pairs, uint64_t seed, bool both_sides) {
    PCG32 rng(seed, 31);
    PointwiseDifference d;
    auto relative = [](double x, double y) { return std::abs(x - y) / std::max({std::abs(x), std::abs(y), 1e-3}); };
    for (int i = 0; i < pairs; ++i) {
        float u1 = rng.next_float(), u2 = rng.next_float(), u3 = rng.next_float(), u4 = rng.next_float();
        Vec3 wi = both_sides ? warp::square_to_uniform_sphere(Vec2(u1, u2)) : warp::square_to_uniform_hemisphere(Vec2(u1, u2));
        Vec3 wo = warp::square_to_uniform_sphere(Vec2(u3, u4));
        SurfaceInteraction si = local_interaction(wi);
        Spectrum fa = a.eval(ctx, si, wo), fb = b.eval(ctx, si, wo);
        float pa = a.pdf(ctx, si, wo), pb = b.pdf(ctx, si, wo);
        if (max_component(fa) > 0.0f || max_component(fb) > 0.0f || pa > 0.0f || pb > 0.0f) ++d.nonzero;
        for (int c = 0; c < 3; ++c) d.eval = std::max(d.eval, relative(fa[c], fb[c]));
        d.pdf = std::max(d.pdf, relative(pa, pb));
    }
    return d;
}

double reciprocity_error(const BSDF& bsdf, int pairs, uint64_t seed) {
    PCG32 rng(seed, 29);
    BSDFContext ctx;
    double worst = 0.0;
    for (int i = 0; i < pairs; ++i) {
        float a = rng.next_float(), b = rng.next_float(), c = rng.next_float(), d = rng.next_float();
        Vec3 w1 = warp::square_to_uniform_hemisphere(Vec2(a, b)), w2 = warp::square_to_uniform_hemisphere(Vec2(c, d));
        if (w1.z < 0.01f || w2.z < 0.01f) continue;
        Spectrum f12 = bsdf.eval(ctx, local_interaction(w1), w2) / w2.z;
        Spectrum f21 = bsdf.eval(ctx, local_interaction(w2), w1) / w1.z;
        float scale = std::max(max_component(f12), max_component(f21));
        if (scale > 1e-6f) worst = std::max(worst, double(max_component(glm::abs(f12 - f21)) / scale));
    }
    return worst;
}

}  // namespace candela::test
