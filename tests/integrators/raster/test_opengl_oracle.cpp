// The OpenGL oracle: Mesa's software OpenGL (OSMesa) renders a scene with fixed-function
// lighting (Gouraud shading, Blinn-Phong with a local viewer, an attenuated point light and a
// spot light with exponent and cutoff), and Candela's Gouraud / Blinn-Phong raster render of the
// same scene must match it: mean absolute difference under 1% of the range, 99th percentile of
// the per-pixel difference under 2/255.
//
// Both draw the same triangles (Candela's tessellation) through the same matrices. GL's
// parameters are Candela's model written in GL's terms: material diffuse = kd / pi, material
// specular = ks (n + 8) / (8 pi), light colours = the intensity I, attenuation and spot as given;
// then GL's per-vertex sum over lights att spot I (diffuse max(N.L, 0) + specular max(N.H, 0)^n)
// is exactly Candela's lighting equation.

#include "core/xml.h"
#include "integrators/raster/raster.h"
#include "integrators/raster/raster_scene.h"
#include "tests/util.h"

#include <GL/gl.h>
#include <GL/osmesa.h>
#include <catch2/catch.hpp>

#include <algorithm>

using namespace candela;
using namespace candela::raster;
using namespace candela::test;

namespace {

struct OracleMaterial {
    float kd[3], ks, n;
};

// Scene parameters shared by both renderers.
const int W = 256, H = 192;
const OracleMaterial Materials[] = {{{0.8f, 0.8f, 0.8f}, 0.0f, 1.0f},      // floor
                                    {{0.6f, 0.25f, 0.15f}, 0.35f, 40.0f},  // spheres (kd + ks <= 1)
                                    {{0.15f, 0.45f, 0.6f}, 0.35f, 90.0f},
                                    {{0.55f, 0.55f, 0.15f}, 0.3f, 12.0f}};

std::string bsdf(const OracleMaterial& m) {
    char buf[256];
    std::snprintf(
        buf, sizeof buf,
        R"(<bsdf type="blinnphong"><rgb name="kd" value="%g, %g, %g"/><rgb name="ks" value="%g"/><float name="exponent" value="%g"/></bsdf>)",
        m.kd[0], m.kd[1], m.kd[2], m.ks, m.n);
    return buf;
}

}  // namespace

TEST_CASE("opengl oracle: Gouraud Blinn-Phong matches Mesa's fixed-function pipeline", "[raster][opengl]") {
    auto dir = scratch_dir("oracle");
    std::string xml = R"(
        <sensor type="perspective"><float name="fov" value="50"/><float name="near_clip" value="0.1"/><float name="far_clip" value="100"/>
            <transform name="to_world"><lookat origin="0, 2.5, 6" target="0, 0.4, 0" up="0, 1, 0"/></transform>
            <film type="hdrfilm"><integer name="width" value="256"/><integer name="height" value="192"/><rfilter type="box"/></film></sensor>
        <shape type="rectangle"><transform name="to_world"><scale value="3"/><rotate x="1" angle="-90"/></transform>)" +
                      bsdf(Materials[0]) + R"(</shape>
        <shape type="sphere"><point name="center" x="-1.3" y="0.6" z="0"/><float name="radius" value="0.6"/>)" +
                      bsdf(Materials[1]) + R"(</shape>
        <shape type="sphere"><point name="center" x="0.2" y="0.5" z="0.6"/><float name="radius" value="0.5"/>)" +
                      bsdf(Materials[2]) + R"(</shape>
        <shape type="sphere"><point name="center" x="1.4" y="0.7" z="-0.5"/><float name="radius" value="0.7"/>)" +
                      bsdf(Materials[3]) + R"(</shape>
        <emitter type="point"><point name="position" x="-2" y="3" z="2"/><rgb name="intensity" value="1.0, 0.9, 0.8"/>
            <float name="attenuation_constant" value="0.5"/><float name="attenuation_linear" value="0.3"/><float name="attenuation_quadratic" value="0.1"/></emitter>
        <emitter type="spot"><transform name="to_world"><lookat origin="2, 4, 2" target="0.5, 0, 0"/></transform>
            <rgb name="intensity" value="1.1, 1.1, 1.3"/><float name="cutoff_angle" value="30"/><float name="falloff_exponent" value="8"/>
            <float name="attenuation_constant" value="1"/><float name="attenuation_linear" value="0"/><float name="attenuation_quadratic" value="0.05"/></emitter>)";
    write_text(dir / "oracle.xml", scene_xml(xml));
    Ref<Scene> scene = load_scene((dir / "oracle.xml").string());

    RasterSettings s;
    s.shading = RasterSettings::Shading::Gouraud;
    s.reflection = RasterSettings::Reflection::Blinn;
    s.shadows = RasterSettings::Shadows::None;
    s.tessellation = 48;
    RasterIntegrator raster(s);
    Image ours = raster.render(*scene, RenderOptions{}).image;

    // --- the same scene through OSMesa ---
    RasterGeometry g = build_geometry(*scene, s.tessellation, false, 0);
    RasterCamera cam = RasterCamera::from_pinhole(*scene->sensor().pinhole());
    OSMesaContext ctx = OSMesaCreateContextExt(OSMESA_RGBA, 24, 0, 0, nullptr);
    REQUIRE(ctx != nullptr);
    std::vector<unsigned char> buffer(size_t(W) * H * 4, 0);
    REQUIRE(OSMesaMakeCurrent(ctx, buffer.data(), GL_UNSIGNED_BYTE, W, H));
    glViewport(0, 0, W, H);
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glShadeModel(GL_SMOOTH);
    glEnable(GL_NORMALIZE);
    glMatrixMode(GL_PROJECTION);
    glLoadMatrixf(&cam.projection[0][0]);  // column-major, as GL expects
    glMatrixMode(GL_MODELVIEW);
    glLoadMatrixf(&cam.view[0][0]);
    glEnable(GL_LIGHTING);
    const float zero[4] = {0, 0, 0, 1};
    glLightModelfv(GL_LIGHT_MODEL_AMBIENT, zero);
    glLightModeli(GL_LIGHT_MODEL_LOCAL_VIEWER, GL_TRUE);
    // Lights are given in world space: the modelview (the view) transforms them to eye space.
    const float p0[4] = {-2, 3, 2, 1}, c0[4] = {1.0f, 0.9f, 0.8f, 1};
    glEnable(GL_LIGHT0);
    glLightfv(GL_LIGHT0, GL_POSITION, p0);
    glLightfv(GL_LIGHT0, GL_AMBIENT, zero);
    glLightfv(GL_LIGHT0, GL_DIFFUSE, c0);
    glLightfv(GL_LIGHT0, GL_SPECULAR, c0);
    glLightf(GL_LIGHT0, GL_CONSTANT_ATTENUATION, 0.5f);
    glLightf(GL_LIGHT0, GL_LINEAR_ATTENUATION, 0.3f);
    glLightf(GL_LIGHT0, GL_QUADRATIC_ATTENUATION, 0.1f);
    Vec3 axis = glm::normalize(Vec3(0.5f, 0, 0) - Vec3(2, 4, 2));
    const float p1[4] = {2, 4, 2, 1}, c1[4] = {1.1f, 1.1f, 1.3f, 1}, d1[3] = {axis.x, axis.y, axis.z};
    glEnable(GL_LIGHT1);
    glLightfv(GL_LIGHT1, GL_POSITION, p1);
    glLightfv(GL_LIGHT1, GL_AMBIENT, zero);
    glLightfv(GL_LIGHT1, GL_DIFFUSE, c1);
    glLightfv(GL_LIGHT1, GL_SPECULAR, c1);
    glLightfv(GL_LIGHT1, GL_SPOT_DIRECTION, d1);
    glLightf(GL_LIGHT1, GL_SPOT_EXPONENT, 8.0f);
    glLightf(GL_LIGHT1, GL_SPOT_CUTOFF, 30.0f);
    glLightf(GL_LIGHT1, GL_CONSTANT_ATTENUATION, 1.0f);
    glLightf(GL_LIGHT1, GL_LINEAR_ATTENUATION, 0.0f);
    glLightf(GL_LIGHT1, GL_QUADRATIC_ATTENUATION, 0.05f);
    for (size_t s_index = 0; s_index < g.shapes.size(); ++s_index) {
        const OracleMaterial& m = Materials[s_index];
        const float pi = 3.14159265358979f;
        float diffuse[4] = {m.kd[0] / pi, m.kd[1] / pi, m.kd[2] / pi, 1};
        float spec = m.ks * (m.n + 8.0f) / (8.0f * pi), specular[4] = {spec, spec, spec, 1};
        glMaterialfv(GL_FRONT_AND_BACK, GL_AMBIENT, zero);
        glMaterialfv(GL_FRONT_AND_BACK, GL_EMISSION, zero);
        glMaterialfv(GL_FRONT_AND_BACK, GL_DIFFUSE, diffuse);
        glMaterialfv(GL_FRONT_AND_BACK, GL_SPECULAR, specular);
        glMaterialf(GL_FRONT_AND_BACK, GL_SHININESS, m.n);
        const RasterShape& rs = g.shapes[s_index];
        glBegin(GL_TRIANGLES);
        for (uint32_t t = rs.first_triangle; t < rs.first_triangle + rs.triangle_count; ++t)
            for (int k = 0; k < 3; ++k) {
                unsigned v = g.triangles[t][k];
                glNormal3fv(&g.normals[v].x);
                glVertex3fv(&g.positions[v].x);
            }
        glEnd();
    }
    glFinish();

    // Row 0 of OSMesa's buffer is the bottom of the window, which is Candela's row 0 (both map
    // y_ndc = -1 to row 0; Candela's camera looks with +y toward the top of the image).
    std::vector<double> diffs;
    double max_value = 0.0;
    int lit = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const unsigned char* gl = &buffer[(size_t(y) * W + x) * 4];
            Spectrum c = ours.rgb_at(x, y);
            double worst = 0.0;
            for (int k = 0; k < 3; ++k) {
                max_value = std::max(max_value, double(c[k]));
                double mine = std::round(std::clamp(double(c[k]), 0.0, 1.0) * 255.0);
                worst = std::max(worst, std::abs(mine - double(gl[k])));
            }
            lit += gl[0] + gl[1] + gl[2] > 0;
            diffs.push_back(worst);
        }
    OSMesaDestroyContext(ctx);
    double mean = 0.0;
    for (double d : diffs) mean += d;
    mean /= double(diffs.size());
    std::sort(diffs.begin(), diffs.end());
    double p99 = diffs[size_t(0.99 * double(diffs.size() - 1))];
    INFO("mean |difference| " << mean << " / 255, 99th percentile " << p99 << " / 255, largest " << diffs.back() << "; brightest value "
                              << max_value << ", " << lit << " lit pixels");
    CHECK(max_value < 1.0);  // below GL's clamp, so both compute the same sums
    CHECK(lit > W * H / 2);  // the comparison covers a mostly lit image
    CHECK(mean < 0.01 * 255.0);
    CHECK(p99 < 2.0);
}
