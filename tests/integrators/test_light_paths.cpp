// The light-path integrators end to end: sppm against Mitsuba 3's references of the validation
// cbox and glass scenes (the validation criteria: whole-image channel means within 1%, 16x16
// block luminance MARE within 2%) and its error falling with passes; photonmapper's whole-image
// mean on the Cornell box within 2%; ptracer, sppm and photonmapper bit-identical across thread
// counts; an interrupted render returns a partial, finite image.
//
// These are deterministic renders (fixed seeds) compared against fixed thresholds of the
// validation README, not statistical tests: noise at the settings used is an order of magnitude
// below the thresholds (sppm cbox at 16 passes: block MARE 0.9%, of which the Monte Carlo part
// shrinks as 1/sqrt(passes)), so a convention error of 1% in the mean or 2% in the blocks shows.

#include "analysis/image_metrics.h"
#include "core/image.h"
#include "core/integrator.h"
#include "core/sampler.h"
#include "core/scene.h"
#include "core/sensor.h"
#include "core/xml.h"
#include "samplers/sequences.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <atomic>
#include <regex>

using namespace candela;
using namespace candela::test;

namespace {

// A validation scene with its integrator replaced.
Ref<Scene> validation_scene(const std::string& name, const std::string& integrator, const SceneParameters& params = {}) {
    std::string xml = read_text(source_path("scenes/validation/" + name + ".xml"));
    xml = std::regex_replace(xml, std::regex("<integrator type=\"path\">[\\s\\S]*?</integrator>"), integrator);
    return load_scene_from_string(xml, source_path("scenes/validation/" + name + ".xml"), params);
}

RenderResult render(const Scene& scene, int threads = 0, int spp = 0, const std::atomic<bool>* interrupt = nullptr) {
    RenderOptions options;
    options.threads = threads;
    options.spp = spp;
    options.interrupt = interrupt;
    return scene.integrator().render(scene, options);
}

std::string sppm(int photons, int passes) {
    return "<integrator type=\"sppm\"><integer name=\"photon_count\" value=\"" + std::to_string(photons) +
           "\"/><integer name=\"max_passes\" value=\"" + std::to_string(passes) + "\"/></integrator>";
}

const std::string PhotonMapper =
    "<integrator type=\"photonmapper\"><integer name=\"global_photons\" value=\"200000\"/>"
    "<integer name=\"caustic_photons\" value=\"0\"/><integer name=\"glossy_samples\" value=\"16\"/>"
    "<integer name=\"direct_samples\" value=\"4\"/></integrator>";

ImageComparison against_reference(const Image& img, const std::string& name) {
    return compare_images(img, read_image(source_path("scenes/validation/refs/" + name + ".exr")));
}

}  // namespace

TEST_CASE("sppm: agrees with Mitsuba 3 on the validation cbox and glass, and its error falls with passes", "[render][sppm][validation]") {
    std::vector<double> relmse;
    for (int passes : {1, 4, 16}) {
        Ref<Scene> scene = validation_scene("cbox", sppm(100000, passes));
        ImageComparison c = against_reference(render(*scene).image, "cbox");
        relmse.push_back(c.relmse);
        if (passes == 16) {
            std::string reason;
            INFO("cbox: mean rel. diff " << c.mean_relative_difference[0] << " " << c.mean_relative_difference[1] << " "
                                         << c.mean_relative_difference[2] << ", block MARE " << c.block_mare << ": " << reason);
            CHECK(images_agree(c, AgreementThresholds(), &reason));
        }
    }
    INFO("cbox relMSE at 1, 4, 16 passes: " << relmse[0] << " " << relmse[1] << " " << relmse[2]);
    CHECK(relmse[1] < relmse[0]);
    CHECK(relmse[2] < relmse[1]);

    Ref<Scene> glass = validation_scene("glass", sppm(100000, 16));
    RenderResult r = render(*glass);
    ImageComparison c = against_reference(r.image, "glass");
    std::string reason;
    bool agree = images_agree(c, AgreementThresholds(), &reason);
    INFO("glass: mean rel. diff " << c.mean_relative_difference[0] << " " << c.mean_relative_difference[1] << " "
                                  << c.mean_relative_difference[2] << ", block MARE " << c.block_mare << ": " << reason);
    CHECK(agree);
    CHECK(all_finite_pixels(r.image));
}

TEST_CASE("photonmapper: the Cornell box's whole-image mean is within 2% of Mitsuba's", "[render][photonmapper][validation]") {
    Ref<Scene> scene = validation_scene("cbox", PhotonMapper);
    ImageComparison c = against_reference(render(*scene, 0, 4).image, "cbox");
    INFO("mean rel. diff " << c.mean_relative_difference[0] << " " << c.mean_relative_difference[1] << " " << c.mean_relative_difference[2]
                           << ", block MARE " << c.block_mare);
    for (int k = 0; k < 3; ++k) CHECK(std::abs(c.mean_relative_difference[k]) < 0.02);
}

TEST_CASE("light paths: ptracer, sppm and photonmapper give the same image with 1 and 2 threads", "[render][sppm][photonmapper][ptracer]") {
    const SceneParameters small = {{"res", "24"}};
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"ptracer", "<integrator type=\"ptracer\"/>"},
        {"sppm", sppm(20000, 3)},
        {"photonmapper",
         "<integrator type=\"photonmapper\"><integer name=\"global_photons\" value=\"20000\"/><integer name=\"caustic_photons\" value=\"5000\"/>"
         "<integer name=\"glossy_samples\" value=\"4\"/><integer name=\"granularity\" value=\"1000\"/></integrator>"}};
    for (const std::string scene_name : {"cbox", "glass"}) {
        for (const auto& [name, integrator] : cases) {
            INFO(name << " on " << scene_name);
            Ref<Scene> scene = validation_scene(scene_name, integrator, small);
            Image one = render(*scene, 1, 2).image, two = render(*scene, 2, 2).image;
            CHECK(one.data() == two.data());
            CHECK(all_finite_pixels(one));
            float sum = 0.0f;
            for (float v : one.data()) sum += v;
            CHECK(sum > 0.0f);
        }
    }
}

TEST_CASE("light paths: an interrupted render returns a partial, finite image", "[render][sppm][photonmapper][ptracer][interrupt]") {
    const std::atomic<bool> stop{true};
    for (const std::string& integrator :
         {std::string("<integrator type=\"ptracer\"/>"), sppm(20000, 3),
          std::string("<integrator type=\"photonmapper\"><integer name=\"global_photons\" value=\"20000\"/></integrator>")}) {
        INFO(integrator);
        Ref<Scene> scene = validation_scene("cbox", integrator, {{"res", "16"}});
        RenderResult r = render(*scene, 0, 2, &stop);
        CHECK(r.stats.partial);
        CHECK(all_finite_pixels(r.image));
        CHECK(r.image.width() == 16);
    }
}

namespace {

// A dimension-addressed sampler (as stratified, ldsampler, sobol... are) that notes every
// dimension drawn since the sample started: its numbers are a hash of (pixel, index, dimension).
class DimensionLog final : public Sampler {
public:
    std::vector<uint32_t> drawn;

    Ref<Sampler> clone() const override { return std::make_shared<DimensionLog>(*this); }
    float next_1d() override {
        drawn.push_back(dimension_);
        return number(dimension_++);
    }
    Vec2 next_2d() override {
        drawn.push_back(dimension_);
        drawn.push_back(dimension_ + 1);
        const Vec2 u(number(dimension_), number(dimension_ + 1));
        dimension_ += 2;
        return u;
    }

protected:
    void start_sample(const Vec2i& pixel, uint32_t index) override {
        key_ = hash_combine(pixel_key(pixel), index);
        dimension_ = 0;
        drawn.clear();
    }

private:
    uint64_t key_ = 0;
    float number(uint32_t dimension) const { return bits_to_unit(hash_bits(key_, dimension)); }
};

}  // namespace

TEST_CASE("integrators: no number of a sample is drawn twice (so photonmapper's direct_samples estimates differ under every sampler)",
          "[integrator][sampler]") {
    // Reusing a dimension repeats a number: with a dimension-addressed sampler the direct_samples
    // next-event estimates of a visible point were one estimate repeated (they all started at
    // the first bounce's dimensions), and after a specular walk they reused the walk's numbers
    // (a refraction decided by the number that then picked the light). The other sampling
    // integrators are checked the same way, but for `aov` and `moment`, which give each nested
    // integrator the numbers of its own render on purpose. The glass scene: a glass sphere (the
    // walk draws), an area light and an environment (the light pick is drawn). `least`: numbers
    // some sample must draw, so that the check has something to check.
    struct Case {
        std::string xml;
        size_t least;
    };
    const std::vector<Case> integrators = {
        {"<integrator type=\"photonmapper\"><integer name=\"global_photons\" value=\"2000\"/><integer name=\"caustic_photons\" "
         "value=\"2000\"/><integer name=\"direct_samples\" value=\"4\"/><integer name=\"glossy_samples\" value=\"2\"/></integrator>",
         20},
        {"<integrator type=\"path\"/>", 20},
        {"<integrator type=\"volpath\"/>", 20},
        {"<integrator type=\"volpathmis\"/>", 20},
        {"<integrator type=\"irradiance\"/>", 20},
        // 3 light samples (pick and position), 2 BSDF samples (lobe and direction): 15 numbers.
        {"<integrator type=\"direct\"><integer name=\"emitter_samples\" value=\"3\"/><integer name=\"bsdf_samples\" "
         "value=\"2\"/></integrator>",
         15},
        // 4 directions.
        {"<integrator type=\"ao\"><integer name=\"shading_samples\" value=\"4\"/></integrator>", 8}};
    for (const Case& c : integrators) {
        INFO(c.xml);
        Ref<Scene> scene = validation_scene("glass", c.xml, {{"res", "16"}});
        auto& integrator = dynamic_cast<SamplingIntegrator&>(scene->integrator());
        integrator.prepare(*scene);
        DimensionLog sampler;
        sampler.set_sample_count(8);
        sampler.set_film(Vec2i(16, 16), 0);
        int samples = 0, repeated = 0;
        size_t most = 0;
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 16; ++x)
                for (uint32_t index = 0; index < 8; ++index) {
                    sampler.start(Vec2i(x, y), index);
                    sampler.set_dimension(SampleDimensions::FirstBounce);
                    SampleRecord record;
                    record.film_pos = Vec2(float(x) + 0.5f, float(y) + 0.5f);
                    const Ray ray = scene->sensor().sample_ray(record.film_pos, Vec2(0.5f), 0.0f);
                    integrator.sample_radiance(*scene, sampler, ray, record);
                    std::vector<uint32_t> drawn = sampler.drawn;
                    std::sort(drawn.begin(), drawn.end());
                    repeated += std::adjacent_find(drawn.begin(), drawn.end()) != drawn.end();
                    most = std::max(most, drawn.size());
                    ++samples;
                }
        CHECK(repeated == 0);
        CHECK(most >= c.least);
        CHECK(samples == 16 * 16 * 8);
    }
}
