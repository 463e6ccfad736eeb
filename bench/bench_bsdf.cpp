// bench_bsdf: the cost of the microfacet BSDFs' hot calls, one thread, no rays.
//
//   bench_bsdf [--rounds N] [--n N]
//
// Times (1) MicrofacetDistribution::sample with visible normals, Beckmann and GGX, at two
// roughnesses, and (2) for roughconductor, roughdielectric and roughplastic with either
// distribution: sample(), eval() followed by pdf() (what next-event estimation asked for) and the
// fused eval_pdf() that replaces the pair. Inputs (incident directions, random numbers) are drawn
// once; each figure is the best of --rounds timed passes over them (default 7), in millions of
// calls per second, so that a neighbour's load spoils fewer of them. It prints figures and
// asserts nothing.

#include "bench/bench_args.h"
#include "core/bsdf.h"
#include "core/rng.h"
#include "core/scene.h"
#include "core/shape.h"
#include "core/warp.h"
#include "core/xml.h"
#include "materials/microfacet.h"

#include <unistd.h>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

using namespace candela;

namespace {

struct Input {
    Vec3 wi, wo;
    float u_lobe;
    Vec2 u;
};

std::vector<Input> make_inputs(int n, bool both_sides) {
    PCG32 rng(7, 11);
    std::vector<Input> in(size_t(n), Input{});
    for (Input& x : in) {
        float a = rng.next_float();
        x.wi = warp::square_to_uniform_hemisphere(Vec2(a, rng.next_float()));
        if (both_sides && rng.next_float() < 0.5f) x.wi.z = -x.wi.z;
        a = rng.next_float();
        x.wo = warp::square_to_uniform_sphere(Vec2(a, rng.next_float()));
        x.u_lobe = rng.next_float();
        a = rng.next_float();
        x.u = Vec2(a, rng.next_float());
    }
    return in;
}

// Best rate over `rounds` passes of `body` over `count` inputs, in millions of calls per second.
template <typename Body>
double best_rate(int rounds, size_t count, Body body) {
    double best = 0.0;
    for (int r = 0; r < rounds; ++r) {
        auto start = std::chrono::steady_clock::now();
        body();
        double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        best = std::max(best, double(count) / seconds * 1e-6);
    }
    return best;
}

volatile float sink;

SurfaceInteraction at(const Vec3& wi) {
    SurfaceInteraction si;
    si.n = Vec3(0, 0, 1);
    si.shading = Frame();
    si.dpdu = Vec3(1, 0, 0);
    si.dpdv = Vec3(0, 1, 0);
    si.uv = Vec2(0.3f, 0.6f);
    si.wi = wi;
    return si;
}

const char* const usage =
    "usage: bench_bsdf [--rounds N] [--n N]\n"
    "  --rounds N   timed passes over the inputs, the best one reported (default 7)\n"
    "  --n N        inputs (incident directions and random numbers) per pass (default 262144)\n";

int run(int argc, char** argv) {
    int rounds = 7, n = 1 << 18;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        if (a == "--rounds")
            rounds = bench::int_option(argc, argv, i, 1);
        else if (a == "--n")
            n = bench::int_option(argc, argv, i, 1);
        else
            bench::reject_argument(a);
    }
    std::printf("distribution sampling (visible normals), M samples/s, best of %d passes over %d inputs\n", rounds, n);
    const std::vector<Input> upper = make_inputs(n, false);
    for (MicrofacetType type : {MicrofacetType::Beckmann, MicrofacetType::GGX})
        for (float alpha : {0.1f, 0.5f}) {
            MicrofacetDistribution d(type, alpha, alpha, true);
            double rate = best_rate(rounds, upper.size(), [&] {
                float acc = 0.0f;
                for (const Input& x : upper) {
                    float pdf;
                    acc += d.sample(x.wi, x.u, pdf).z + pdf;
                }
                sink = acc;
            });
            std::printf("  %-9s alpha %.1f  %8.2f\n", type == MicrofacetType::GGX ? "ggx" : "beckmann", alpha, rate);
        }

    std::printf("BSDF calls, M calls/s (sample; eval then pdf; eval_pdf)\n");
    const std::string path = (std::filesystem::temp_directory_path() / ("bench_bsdf-" + std::to_string(::getpid()) + ".xml")).string();
    for (const char* plugin : {"roughconductor", "roughdielectric", "roughplastic"})
        for (const char* distribution : {"beckmann", "ggx"}) {
            std::string xml = std::string("<scene version=\"3.0.0\"><shape type=\"sphere\"><bsdf type=\"") + plugin +
                              "\"><string name=\"distribution\" value=\"" + distribution +
                              "\"/><float name=\"alpha\" value=\"0.3\"/></bsdf></shape></scene>";
            Ref<Scene> scene = load_scene_from_string(xml, path);
            const BSDF& bsdf = *scene->shapes()[0]->bsdf();
            const bool transmits = (bsdf.flags() & Transmission) != 0;
            std::vector<SurfaceInteraction> sis;
            const std::vector<Input> in = make_inputs(n, transmits);
            for (const Input& x : in) sis.push_back(at(x.wi));
            BSDFContext ctx;
            double sample_rate = best_rate(rounds, in.size(), [&] {
                float acc = 0.0f;
                for (size_t i = 0; i < in.size(); ++i) acc += bsdf.sample(ctx, sis[i], in[i].u_lobe, in[i].u).weight.x;
                sink = acc;
            });
            double pair_rate = best_rate(rounds, in.size(), [&] {
                float acc = 0.0f;
                for (size_t i = 0; i < in.size(); ++i) acc += bsdf.eval(ctx, sis[i], in[i].wo).x + bsdf.pdf(ctx, sis[i], in[i].wo);
                sink = acc;
            });
            double fused_rate = best_rate(rounds, in.size(), [&] {
                float acc = 0.0f;
                for (size_t i = 0; i < in.size(); ++i) {
                    BSDFEvalPdf e = bsdf.eval_pdf(ctx, sis[i], in[i].wo);
                    acc += e.value.x + e.pdf;
                }
                sink = acc;
            });
            std::printf("  %-15s %-9s  %8.2f  %8.2f  %8.2f\n", plugin, distribution, sample_rate, pair_rate, fused_rate);
        }
    std::filesystem::remove(path);
    return 0;
}

}  // namespace

int main(int argc, char** argv) { return bench::run_main(argc, argv, usage, run); }
