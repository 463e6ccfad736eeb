// Animated point and spot lights: equal keyframes light a point as the static light does, and at
// time t the light is the one interpolated at t; the time is the reference point's.

#include "core/emitter.h"
#include "core/xml.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <sstream>

using namespace candela;
using namespace candela::test;

namespace {

const Emitter& only_emitter(const Ref<Scene>& scene) {
    REQUIRE(scene->emitters().size() == 1);
    return *scene->emitters()[0];
}

// `ref` lit by both emitters at their times: the same direction, distance and weight.
void check_same_light(const Emitter& a, const Emitter& b, float time_a, float time_b) {
    for (Vec3 p : {Vec3(0.0f), Vec3(0.3f, -0.2f, 0.0f), Vec3(-0.5f, 0.4f, 0.1f), Vec3(1.0f, 1.0f, -0.2f)}) {
        SurfaceInteraction ref;
        ref.p = p;
        ref.time = time_a;
        Spectrum wa, wb;
        DirectionSample da = a.sample_direction(ref, Vec2(0.5f), wa);
        ref.time = time_b;
        DirectionSample db = b.sample_direction(ref, Vec2(0.5f), wb);
        INFO("reference point " << p.x << ", " << p.y << ", " << p.z);
        CHECK(glm::length(da.p - db.p) < 1e-5f);
        CHECK(glm::length(da.d - db.d) < 1e-5f);
        CHECK(da.dist == Approx(db.dist).epsilon(1e-5));
        for (int c = 0; c < 3; ++c) CHECK(wa[c] == Approx(wb[c]).epsilon(1e-4).margin(1e-6));
    }
}

std::string spot(const std::string& to_world) {
    return R"(<emitter type="spot"><rgb name="intensity" value="5, 4, 3"/><float name="cutoff_angle" value="35"/>
        <float name="beam_width" value="20"/>)" +
           to_world + "</emitter>";
}

std::string lookat(const std::string& origin) { return "<lookat origin=\"" + origin + "\" target=\"0, 0, 0\" up=\"0, 0, 1\"/>"; }

}  // namespace

TEST_CASE("light motion: a spot light with equal keyframes lights as the static one", "[lights][animation]") {
    std::string pose = lookat("-1, -2, 3");
    Ref<Scene> still = load_scene_xml("spot-still", spot("<transform name=\"to_world\">" + pose + "</transform>"));
    Ref<Scene> moving = load_scene_xml("spot-moving", spot("<animation name=\"to_world\"><transform time=\"0\">" + pose +
                                                           "</transform><transform time=\"1\">" + pose + "</transform></animation>"));
    CHECK(only_emitter(moving).is_animated());
    CHECK(moving->is_animated());
    CHECK_FALSE(still->is_animated());
    for (float t : {0.0f, 0.4f, 1.0f}) check_same_light(only_emitter(still), only_emitter(moving), t, t);
}

TEST_CASE("light motion: at time t the spot and point lights are the ones interpolated at t", "[lights][animation]") {
    // The spot's apex moves from (-2, -2, 3) to (2, -2, 3), aimed at the origin at both ends;
    // halfway it is the pose with the translation and the rotation interpolated (written out as
    // a matrix for a static spot).
    std::string moving = "<animation name=\"to_world\"><transform time=\"0\">" + lookat("-2, -2, 3") +
                         "</transform><transform time=\"1\">" + lookat("2, -2, 3") + "</transform></animation>";
    Ref<Scene> spot_moving = load_scene_xml("spot-arc", spot(moving));
    // Build the halfway pose by hand: translation lerp (0, -2, 3), rotation slerp of the two.
    const AnimatedTransform a({{0.0f, Transform::look_at(Vec3(-2, -2, 3), Vec3(0), Vec3(0, 0, 1))},
                               {1.0f, Transform::look_at(Vec3(2, -2, 3), Vec3(0), Vec3(0, 0, 1))}});
    Transform half = a.eval(0.5f);
    CHECK(glm::length(Vec3(half.matrix()[3]) - Vec3(0, -2, 3)) < 1e-6f);
    std::ostringstream m;
    m.precision(9);
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) m << half.matrix()[c][r] << " ";
    Ref<Scene> spot_half =
        load_scene_xml("spot-half", spot("<transform name=\"to_world\"><matrix value=\"" + m.str() + "\"/></transform>"));
    check_same_light(only_emitter(spot_half), only_emitter(spot_moving), 0.0f, 0.5f);
    // A point light moving from (0, 0, 1) at time 2 to (2, 0, 1) at time 4 is at (0.5, 0, 1) at 2.5.
    Ref<Scene> point_moving = load_scene_xml("point-moving", R"(<emitter type="point"><rgb name="intensity" value="3"/>
        <animation name="to_world"><transform time="2"><translate z="1"/></transform><transform time="4"><translate x="2" z="1"/></transform></animation></emitter>)");
    Ref<Scene> point_there = load_scene_xml("point-there", R"(<emitter type="point"><rgb name="intensity" value="3"/>
        <point name="position" x="0.5" y="0" z="1"/></emitter>)");
    check_same_light(only_emitter(point_there), only_emitter(point_moving), 0.0f, 2.5f);
    // Before the first keyframe the first position holds.
    Ref<Scene> point_first = load_scene_xml("point-first", R"(<emitter type="point"><rgb name="intensity" value="3"/>
        <point name="position" x="0" y="0" z="1"/></emitter>)");
    check_same_light(only_emitter(point_first), only_emitter(point_moving), 0.0f, 1.0f);
}

TEST_CASE("light motion: a moving light's bounds hold it all along its path", "[lights][animation]") {
    Ref<Scene> moving = load_scene_xml("point-bounds", R"(<emitter type="point">
        <animation name="to_world"><transform time="0"><translate x="-1" z="1"/></transform><transform time="1"><translate x="3" y="2" z="1"/></transform></animation></emitter>)");
    auto b = only_emitter(moving).bounds();
    REQUIRE(b);
    CHECK(b->box.min.x <= -1.0f);
    CHECK(b->box.max.x >= 3.0f);
    CHECK(b->box.max.y >= 2.0f);
}
