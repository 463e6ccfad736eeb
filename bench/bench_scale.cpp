// bench_scale: Candela at real scene sizes, against the floor.
//
//   bench_scale generate DIR [--triangles N]     write a displaced-grid mesh of about N triangles
//                                                 (default 10^7) as DIR/mesh.ply (binary),
//                                                 mesh.serialized and mesh.obj, and a scene for each
//   bench_scale floor FILE.ply                    the floor: read the PLY into two arrays, hand them
//                                                 to Embree as shared buffers, build at Candela's
//                                                 build quality, trace one ray
//   bench_scale parse FILE                        construct one mesh plugin (obj, ply, serialized)
//                                                 in this process and time it: MB/s of the file
//   bench_scale load DIR --candela BIN [--rounds R] [--obj 0]
//                                                 start to first sample and peak resident memory,
//                                                 side by side: the floor, then `candela render` of
//                                                 each format's scene (1 spp at 32 x 32), R times
//   bench_scale instances DIR --candela BIN [--instances K] [--triangles N]
//                                                 K instances (default 10^4) of one N-triangle mesh
//                                                 (default 10^6): peak memory against one mesh alone
//   bench_scale growth DIR --candela BIN          time per sample on the same view for 10^3, 10^5,
//                                                 10^7 triangles and 10^10 instanced; writes
//                                                 DIR/growth.svg
//   bench_scale film DIR --candela BIN            an 8K render with AOVs: peak memory against the
//                                                 memory check's estimate
//
// Every measured run is a child process: its wall time from fork to exit and its peak resident
// set (getrusage of the child, ru_maxrss) include everything from start to the first sample (for
// Candela, a 1-spp render of a 32 x 32 film, which then writes its EXR). The generated files are
// large (10^7 triangles: 230 MB PLY, 600 MB OBJ) and are not committed. Figures only; nothing is
// asserted.

#include "bench/bench_args.h"
#include "core/properties.h"
#include "core/registry.h"
#include "core/shape.h"

#include <embree3/rtcore.h>
#include <zlib.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// A grid of (n x n) vertices over [-1, 1]^2, displaced in z by a few sines and a hash (so that
// the BVH sees an uneven surface), two triangles per cell.
struct GridMesh {
    std::vector<float> positions;   // x y z per vertex
    std::vector<uint32_t> indices;  // three per triangle
};

GridMesh make_grid(uint64_t triangles) {
    const uint32_t n = uint32_t(std::max<double>(2.0, std::round(std::sqrt(double(triangles) / 2.0)) + 1.0));
    GridMesh m;
    m.positions.resize(size_t(n) * n * 3);
    for (uint32_t j = 0; j < n; ++j)
        for (uint32_t i = 0; i < n; ++i) {
            float x = -1.0f + 2.0f * float(i) / float(n - 1), y = -1.0f + 2.0f * float(j) / float(n - 1);
            uint32_t h = (i * 73856093u) ^ (j * 19349663u);
            h ^= h >> 13;
            h *= 0x5bd1e995u;
            h ^= h >> 15;
            float z =
                0.08f * std::sin(7.0f * x) * std::cos(5.0f * y) + 0.03f * std::sin(23.0f * x * y) + 0.002f * float(h & 1023u) / 1023.0f;
            size_t v = (size_t(j) * n + i) * 3;
            m.positions[v] = x;
            m.positions[v + 1] = y;
            m.positions[v + 2] = z;
        }
    m.indices.reserve(size_t(n - 1) * (n - 1) * 6);
    for (uint32_t j = 0; j + 1 < n; ++j)
        for (uint32_t i = 0; i + 1 < n; ++i) {
            uint32_t a = j * n + i, b = a + 1, c = a + n, d = c + 1;
            m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
        }
    return m;
}

void write_ply(const GridMesh& m, const fs::path& path) {
    std::ofstream out(path, std::ios::binary);
    const size_t vertices = m.positions.size() / 3, triangles = m.indices.size() / 3;
    out << "ply\nformat binary_little_endian 1.0\nelement vertex " << vertices
        << "\nproperty float x\nproperty float y\nproperty float z\nelement face " << triangles
        << "\nproperty list uchar int vertex_indices\nend_header\n";
    out.write(reinterpret_cast<const char*>(m.positions.data()), std::streamsize(m.positions.size() * 4));
    std::vector<char> face(13 * 4096);
    for (size_t t = 0; t < triangles; t += 4096) {
        size_t count = std::min<size_t>(4096, triangles - t);
        for (size_t k = 0; k < count; ++k) {
            face[13 * k] = 3;
            std::memcpy(&face[13 * k + 1], &m.indices[3 * (t + k)], 12);
        }
        out.write(face.data(), std::streamsize(13 * count));
    }
    if (!out) throw std::runtime_error("cannot write " + path.string());
}

// Mitsuba's serialized format, version 4: magic, version, a zlib stream of flags (single
// precision), name, counts, positions and indices; then the dictionary of mesh offsets.
void write_serialized(const GridMesh& m, const fs::path& path) {
    std::ofstream out(path, std::ios::binary);
    const uint16_t header[2] = {0x041C, 4};
    out.write(reinterpret_cast<const char*>(header), 4);
    z_stream zs{};
    deflateInit(&zs, 1);
    std::vector<unsigned char> buffer(1 << 20);
    auto feed = [&](const void* data, size_t bytes, bool finish) {
        zs.next_in = reinterpret_cast<Bytef*>(const_cast<void*>(data));
        zs.avail_in = uInt(bytes);
        int status;
        do {
            zs.next_out = buffer.data();
            zs.avail_out = uInt(buffer.size());
            status = deflate(&zs, finish ? Z_FINISH : Z_NO_FLUSH);
            out.write(reinterpret_cast<const char*>(buffer.data()), std::streamsize(buffer.size() - zs.avail_out));
        } while (zs.avail_out == 0 || (finish && status != Z_STREAM_END));
    };
    const uint32_t flags = 0x1000;
    const uint64_t counts[2] = {m.positions.size() / 3, m.indices.size() / 3};
    feed(&flags, 4, false);
    feed("grid", 5, false);
    feed(counts, 16, false);
    for (size_t at = 0; at < m.positions.size(); at += 1 << 20)
        feed(&m.positions[at], 4 * std::min<size_t>(1 << 20, m.positions.size() - at), false);
    for (size_t at = 0; at < m.indices.size(); at += 1 << 20)
        feed(&m.indices[at], 4 * std::min<size_t>(1 << 20, m.indices.size() - at), false);
    feed(nullptr, 0, true);
    deflateEnd(&zs);
    const uint64_t offset = 0;
    const uint32_t count = 1;
    out.write(reinterpret_cast<const char*>(&offset), 8);
    out.write(reinterpret_cast<const char*>(&count), 4);
    if (!out) throw std::runtime_error("cannot write " + path.string());
}

void write_obj(const GridMesh& m, const fs::path& path) {
    std::FILE* f = std::fopen(path.c_str(), "w");
    if (!f) throw std::runtime_error("cannot write " + path.string());
    for (size_t v = 0; v < m.positions.size(); v += 3)
        std::fprintf(f, "v %.6f %.6f %.6f\n", double(m.positions[v]), double(m.positions[v + 1]), double(m.positions[v + 2]));
    for (size_t t = 0; t < m.indices.size(); t += 3)
        std::fprintf(f, "f %u %u %u\n", m.indices[t] + 1, m.indices[t + 1] + 1, m.indices[t + 2] + 1);
    std::fclose(f);
}

// A scene of the given shape elements seen from above at an angle, lit by the sky and the sun.
std::string scene_xml(const std::string& shapes, int width, int height, const std::string& integrator = "path") {
    std::ostringstream s;
    s << "<scene version=\"3.0.0\">\n"
      << "  <integrator type=\"" << integrator << "\"><integer name=\"max_depth\" value=\"4\"/></integrator>\n"
      << "  <sensor type=\"perspective\"><float name=\"fov\" value=\"40\"/>\n"
      << "    <transform name=\"to_world\"><lookat origin=\"0, -2.4, 1.8\" target=\"0, 0, 0\" up=\"0, 0, 1\"/></transform>\n"
      << "    <sampler type=\"independent\"><integer name=\"sample_count\" value=\"1\"/></sampler>\n"
      << "    <film type=\"hdrfilm\"><integer name=\"width\" value=\"" << width << "\"/><integer name=\"height\" value=\"" << height
      << "\"/></film>\n  </sensor>\n"
      << "  <emitter type=\"constant\"><rgb name=\"radiance\" value=\"0.3\"/></emitter>\n"
      << "  <emitter type=\"directional\"><vector name=\"direction\" x=\"-1\" y=\"1\" z=\"-2\"/><rgb name=\"irradiance\" value=\"3\"/></emitter>\n"
      << shapes << "</scene>\n";
    return s.str();
}

std::string mesh_shape(const std::string& type, const std::string& file) {
    return "  <shape type=\"" + type + "\"><string name=\"filename\" value=\"" + file +
           "\"/><bsdf type=\"diffuse\"><rgb name=\"reflectance\" value=\"0.6\"/></bsdf></shape>\n";
}

// k instances of one mesh on a sqrt(k) x sqrt(k) lattice over [-1, 1]^2, each scaled to its cell.
std::string instanced_shapes(const std::string& file, int k) {
    const int side = std::max(1, int(std::lround(std::sqrt(double(k)))));
    std::ostringstream s;
    s << "  <shape type=\"shapegroup\" id=\"tile\">\n" << mesh_shape("ply", file) << "  </shape>\n";
    const double cell = 2.0 / side;
    for (int j = 0; j < side; ++j)
        for (int i = 0; i < side; ++i) {
            double x = -1.0 + cell * (i + 0.5), y = -1.0 + cell * (j + 0.5);
            s << "  <shape type=\"instance\"><ref id=\"tile\"/><transform name=\"to_world\"><scale x=\"" << cell / 2 << "\" y=\""
              << cell / 2 << "\" z=\"" << cell / 2 << "\"/><translate x=\"" << x << "\" y=\"" << y << "\"/></transform></shape>\n";
        }
    return s.str();
}

void write_text(const fs::path& path, const std::string& text) {
    std::ofstream out(path);
    out << text;
    if (!out) throw std::runtime_error("cannot write " + path.string());
}

struct ChildRun {
    double seconds = 0.0;
    double peak_mb = 0.0;      // ru_maxrss of the child, MiB
    double cpu_seconds = 0.0;  // its user and system time
    int status = 0;
    std::string output;  // its stderr and stdout
};

// Runs argv as a child process; wall time from fork to exit, the child's peak resident set.
ChildRun run_child(const std::vector<std::string>& argv) {
    char log_name[] = "/tmp/bench_scale_XXXXXX";
    int log = mkstemp(log_name);
    auto t0 = std::chrono::steady_clock::now();
    pid_t pid = fork();
    if (pid == 0) {
        dup2(log, 1);
        dup2(log, 2);
        std::vector<char*> args;
        for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
        args.push_back(nullptr);
        execv(args[0], args.data());
        _exit(127);
    }
    ChildRun r;
    struct rusage usage {};
    wait4(pid, &r.status, 0, &usage);
    r.seconds = seconds_since(t0);
    r.peak_mb = double(usage.ru_maxrss) / 1024.0;
    r.cpu_seconds = double(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) + 1e-6 * double(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
    std::ifstream in(log_name);
    r.output.assign(std::istreambuf_iterator<char>(in), {});
    close(log);
    unlink(log_name);
    if (!WIFEXITED(r.status) || WEXITSTATUS(r.status) != 0)
        throw std::runtime_error("failed (" + std::to_string(r.status) + "): " + argv[0] + " ... " + argv.back() + "\n" + r.output);
    return r;
}

std::string self_path() { return fs::read_symlink("/proc/self/exe").string(); }

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

// The floor: what any renderer must do to trace a ray through the PLY's triangles with Embree.
int floor_run(const std::string& path) {
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) throw std::runtime_error("cannot open " + path);
    char line[256];
    size_t vertices = 0, triangles = 0;
    while (std::fgets(line, sizeof(line), f)) {
        if (std::sscanf(line, "element vertex %zu", &vertices) == 1) continue;
        if (std::sscanf(line, "element face %zu", &triangles) == 1) continue;
        if (std::strncmp(line, "end_header", 10) == 0) break;
    }
    // One float of padding: Embree reads vertices with 16-byte loads.
    float* positions = static_cast<float*>(std::malloc((vertices * 3 + 1) * sizeof(float)));
    uint32_t* indices = static_cast<uint32_t*>(std::malloc(triangles * 12));
    if (std::fread(positions, 12, vertices, f) != vertices) throw std::runtime_error("short vertex block");
    std::vector<unsigned char> chunk(13 << 16);
    for (size_t t = 0; t < triangles;) {
        size_t count = std::min<size_t>(1 << 16, triangles - t);
        if (std::fread(chunk.data(), 13, count, f) != count) throw std::runtime_error("short face block");
        for (size_t k = 0; k < count; ++k) std::memcpy(&indices[3 * (t + k)], &chunk[13 * k + 1], 12);
        t += count;
    }
    std::fclose(f);
    RTCDevice device = rtcNewDevice(nullptr);
    RTCScene scene = rtcNewScene(device);
    rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, positions, 0, 12, vertices);
    rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, indices, 0, 12, triangles);
    rtcCommitGeometry(g);
    rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(scene);
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh{};
    rh.ray.org_z = 5.0f;
    rh.ray.dir_z = -1.0f;
    rh.ray.tfar = 1e30f;
    rh.ray.mask = ~0u;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene, &context, &rh);
    std::printf("floor: %zu vertices, %zu triangles, first hit at t = %g\n", vertices, triangles, double(rh.ray.tfar));
    rtcReleaseScene(scene);
    rtcReleaseDevice(device);
    std::free(positions);
    std::free(indices);
    return 0;
}

int parse_run(const std::string& path) {
    // The mesh plugin comes from the extension: name the file before that choice can fail.
    if (!fs::is_regular_file(path)) throw bench::UsageError(path + ": no such file");
    const std::string extension = fs::path(path).extension().string();
    const std::string type = extension.empty() ? "" : extension.substr(1);
    if (type != "obj" && type != "ply" && type != "serialized")
        throw bench::UsageError(path + ": parse reads .obj, .ply and .serialized meshes (the extension chooses the plugin)");
    candela::Properties props(type, candela::SourceLocation{});
    props.set_string("filename", fs::absolute(path).string());
    auto t0 = std::chrono::steady_clock::now();
    auto shape = candela::create_plugin(candela::ObjectKind::Shape, props);
    double s = seconds_since(t0);
    double mb = double(fs::file_size(path)) / 1e6;
    std::printf("parse %s: %.1f MB in %.3f s, %.0f MB/s (the plugin's whole construction: reading, parsing, finalize)\n", type.c_str(), mb,
                s, mb / s);
    return shape ? 0 : 1;
}

std::vector<std::string> candela_render(const std::string& candela, const fs::path& scene, const fs::path& out, int spp) {
    return {candela, "render", scene.string(), "-o", out.string(), "--spp", std::to_string(spp)};
}

// The samples/s figure of a `candela render` summary line ("..., 821.2k samples/s, ...").
double samples_per_second(const std::string& output) {
    size_t at = output.find(" samples/s");
    if (at == std::string::npos) return 0.0;
    size_t start = output.rfind(' ', at - 1) + 1;
    std::string number = output.substr(start, at - start);
    double scale = 1.0;
    if (!number.empty() && number.back() == 'k') scale = 1e3;
    if (!number.empty() && number.back() == 'M') scale = 1e6;
    return std::atof(number.c_str()) * scale;
}

int load_run(const fs::path& dir, const std::string& candela, int rounds, bool obj) {
    const uint64_t triangles = [&] {
        std::ifstream in(dir / "mesh.ply");
        std::string word;
        uint64_t n = 0;
        while (in >> word)
            if (word == "face" && (in >> n)) break;
        return n;
    }();
    std::printf("start to first sample, peak resident memory; %llu triangles; %d rounds side by side\n", (unsigned long long)triangles,
                rounds);
    std::vector<std::string> names = {"floor (ply)", "candela ply", "candela serialized", "candela obj"};
    std::vector<std::vector<double>> time(names.size()), memory(names.size()), cpu(names.size());
    // Each round runs the floor, PLY and serialized in a rotated order: a process's time depends
    // on what ran just before it (on this project's virtual machines, whether the memory it
    // touches first was used lately), so that no format always follows the same one.
    for (int r = 0; r < rounds; ++r) {
        for (size_t step = 0; step < names.size(); ++step) {
            const size_t k = step < 3 ? (step + size_t(r)) % 3 : step;
            if (k == 3 && (r > 0 || !obj)) continue;  // obj once: it is the slow format
            std::vector<std::string> argv = k == 0 ? std::vector<std::string>{self_path(), "floor", (dir / "mesh.ply").string()}
                                                   : candela_render(candela,
                                                                    dir / (std::string("scene_") +
                                                                           (k == 1   ? "ply"
                                                                            : k == 2 ? "serialized"
                                                                                     : "obj") +
                                                                           ".xml"),
                                                                    dir / "out.exr", 1);
            ChildRun c = run_child(argv);
            time[k].push_back(c.seconds);
            memory[k].push_back(c.peak_mb);
            cpu[k].push_back(c.cpu_seconds);
            std::printf("  round %d %-20s %7.2f s (%6.2f s of CPU)  %8.1f MB  %6.1f bytes/triangle\n", r + 1, names[k].c_str(), c.seconds,
                        c.cpu_seconds, c.peak_mb, c.peak_mb * 1048576.0 / double(triangles));
            std::fflush(stdout);
        }
    }
    const double floor_time = median(time[0]), floor_memory = median(memory[0]);
    for (size_t k = 0; k < names.size(); ++k)
        if (!time[k].empty()) {
            // Also the median of each round's ratio to that round's floor.
            std::vector<double> ratios;
            for (size_t r = 0; r < time[k].size(); ++r) ratios.push_back(time[k][r] / time[0][r]);
            std::printf(
                "%-20s median %7.2f s (x%.2f of the floor, rounds' median x%.2f; CPU x%.2f)  %8.1f MB (x%.2f)  %6.1f bytes/triangle\n",
                names[k].c_str(), median(time[k]), median(time[k]) / floor_time, median(ratios), median(cpu[k]) / median(cpu[0]),
                median(memory[k]), median(memory[k]) / floor_memory, median(memory[k]) * 1048576.0 / double(triangles));
        }
    return 0;
}

int generate(const fs::path& dir, uint64_t triangles, bool obj) {
    fs::create_directories(dir);
    auto t0 = std::chrono::steady_clock::now();
    GridMesh m = make_grid(triangles);
    write_ply(m, dir / "mesh.ply");
    write_serialized(m, dir / "mesh.serialized");
    if (obj) write_obj(m, dir / "mesh.obj");
    write_text(dir / "scene_ply.xml", scene_xml(mesh_shape("ply", "mesh.ply"), 32, 32));
    write_text(dir / "scene_serialized.xml", scene_xml(mesh_shape("serialized", "mesh.serialized"), 32, 32));
    if (obj) write_text(dir / "scene_obj.xml", scene_xml(mesh_shape("obj", "mesh.obj"), 32, 32));
    std::printf("wrote %s: %zu vertices, %zu triangles, in %.1f s\n", dir.c_str(), m.positions.size() / 3, m.indices.size() / 3,
                seconds_since(t0));
    return 0;
}

int instances_run(const fs::path& dir, const std::string& candela, int k, uint64_t triangles) {
    fs::create_directories(dir);
    write_ply(make_grid(triangles), dir / "tile.ply");
    write_text(dir / "scene_one.xml", scene_xml(mesh_shape("ply", "tile.ply"), 32, 32));
    write_text(dir / "scene_instances.xml", scene_xml(instanced_shapes("tile.ply", k), 32, 32));
    ChildRun one = run_child(candela_render(candela, dir / "scene_one.xml", dir / "out.exr", 1));
    ChildRun many = run_child(candela_render(candela, dir / "scene_instances.xml", dir / "out.exr", 1));
    const int side = std::max(1, int(std::lround(std::sqrt(double(k)))));
    std::printf("one mesh of %llu triangles:          %7.2f s  peak %8.1f MB\n", (unsigned long long)triangles, one.seconds, one.peak_mb);
    std::printf("%d instances of it (%.3g triangles): %7.2f s  peak %8.1f MB: %.1f MB more, %.0f bytes per instance\n", side * side,
                double(side) * side * double(triangles), many.seconds, many.peak_mb, many.peak_mb - one.peak_mb,
                (many.peak_mb - one.peak_mb) * 1048576.0 / double(side * side));
    return 0;
}

int growth_run(const fs::path& dir, const std::string& candela) {
    fs::create_directories(dir);
    struct Step {
        std::string name;
        double triangles;
        std::string scene;
    };
    std::vector<Step> steps;
    for (int e : {3, 5, 7}) {
        std::string file = "grid_1e" + std::to_string(e) + ".ply";
        write_ply(make_grid(uint64_t(std::pow(10.0, e))), dir / file);
        steps.push_back({"1e" + std::to_string(e), std::pow(10.0, e), "growth_1e" + std::to_string(e) + ".xml"});
        write_text(dir / steps.back().scene, scene_xml(mesh_shape("ply", file), 256, 256));
    }
    write_ply(make_grid(1000000), dir / "grid_1e6.ply");
    steps.push_back({"1e10 (10^4 instances of 10^6)", 1e10, "growth_1e10.xml"});
    write_text(dir / steps.back().scene, scene_xml(instanced_shapes("grid_1e6.ply", 10000), 256, 256));
    std::vector<double> ns_per_sample;
    for (const Step& s : steps) {
        std::vector<double> rates;
        for (int r = 0; r < 3; ++r)
            rates.push_back(samples_per_second(run_child(candela_render(candela, dir / s.scene, dir / "out.exr", 16)).output));
        double ns = 1e9 / median(rates);
        ns_per_sample.push_back(ns);
        std::printf("%-32s %8.0f ns per sample (median of 3; 256 x 256, 16 spp, path, max_depth 4)  x%.2f of 10^3\n", s.name.c_str(), ns,
                    ns / ns_per_sample[0]);
        std::fflush(stdout);
    }
    // The plot: ns per sample against log10(triangles), with log2 of the count scaled to the first
    // point as the "grows like the BVH depth" line.
    std::ostringstream svg;
    const double w = 520, h = 320, x0 = 60, y0 = 270, xs = 400.0 / 7.0, top = *std::max_element(ns_per_sample.begin(), ns_per_sample.end());
    const double ys = 220.0 / (1.6 * top);
    svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << w << "\" height=\"" << h
        << "\" font-family=\"sans-serif\" font-size=\"12\">\n"
        << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
        << "<line x1=\"" << x0 << "\" y1=\"" << y0 << "\" x2=\"" << x0 + 7 * xs << "\" y2=\"" << y0 << "\" stroke=\"black\"/>\n"
        << "<line x1=\"" << x0 << "\" y1=\"" << y0 << "\" x2=\"" << x0 << "\" y2=\"30\" stroke=\"black\"/>\n";
    for (int e = 3; e <= 10; ++e) svg << "<text x=\"" << x0 + (e - 3) * xs - 10 << "\" y=\"" << y0 + 16 << "\">1e" << e << "</text>\n";
    svg << "<text x=\"" << x0 + 120 << "\" y=\"" << y0 + 36 << "\">triangles (log scale)</text>\n"
        << "<text x=\"8\" y=\"22\">ns per sample (256 x 256, 16 spp, 2 threads)</text>\n";
    for (int k = 0; k <= 4; ++k) {
        double v = 1.6 * top * k / 4;
        svg << "<text x=\"4\" y=\"" << y0 - v * ys + 4 << "\">" << int(v) << "</text>\n";
    }
    std::string measured, depth;
    for (size_t i = 0; i < steps.size(); ++i) {
        double x = x0 + (std::log10(steps[i].triangles) - 3) * xs;
        double y = y0 - ns_per_sample[i] * ys;
        double yd = y0 - ns_per_sample[0] * std::log2(steps[i].triangles) / std::log2(steps[0].triangles) * ys;
        measured += std::to_string(x) + "," + std::to_string(y) + " ";
        depth += std::to_string(x) + "," + std::to_string(yd) + " ";
        svg << "<circle cx=\"" << x << "\" cy=\"" << y << "\" r=\"4\" fill=\"#c33\"/>\n";
    }
    svg << "<polyline points=\"" << depth << "\" fill=\"none\" stroke=\"#999\" stroke-dasharray=\"5,4\"/>\n"
        << "<polyline points=\"" << measured << "\" fill=\"none\" stroke=\"#c33\" stroke-width=\"2\"/>\n"
        << "<text x=\"" << x0 + 10 << "\" y=\"46\" fill=\"#c33\">measured</text>\n"
        << "<text x=\"" << x0 + 10 << "\" y=\"62\" fill=\"#777\">log2(n) / log2(1e3) x the first point (BVH depth)</text>\n</svg>\n";
    write_text(dir / "growth.svg", svg.str());
    std::printf("wrote %s\n", (dir / "growth.svg").c_str());
    return 0;
}

int film_run(const fs::path& dir, const std::string& candela) {
    fs::create_directories(dir);
    write_ply(make_grid(1000), dir / "small.ply");
    std::string xml = scene_xml(mesh_shape("ply", "small.ply"), 7680, 4320, "aov");
    // The aov integrator wraps the path tracer: colour plus albedo, depth and normals.
    const std::string wrapped =
        "<integrator type=\"aov\"><string name=\"aovs\" value=\"dd:depth,nn:sh_normal,aa:albedo\"/>"
        "<integrator type=\"path\"><integer name=\"max_depth\" value=\"4\"/></integrator></integrator>";
    size_t a = xml.find("<integrator"), b = xml.find("</integrator>") + std::strlen("</integrator>");
    xml.replace(a, b - a, wrapped);
    write_text(dir / "film_8k.xml", xml);
    std::vector<std::string> argv = candela_render(candela, dir / "film_8k.xml", dir / "film_8k.exr", 1);
    ChildRun r = run_child(argv);
    std::printf("8K (7680 x 4320) with 3 AOVs (7 extra channels), 1 spp: %.2f s, peak %.1f MB; EXR %.1f MB\n", r.seconds, r.peak_mb,
                double(fs::file_size(dir / "film_8k.exr")) / 1048576.0);
    // The estimate: what --max-memory refuses just below it.
    for (uint64_t limit_mb = 64; limit_mb < 65536; limit_mb = limit_mb * 5 / 4) {
        std::vector<std::string> limited = argv;
        limited.push_back("--max-memory");
        limited.push_back(std::to_string(limit_mb) + "M");
        try {
            run_child(limited);
            std::printf("the smallest --max-memory that runs (steps of 25%%): %llu MB\n", (unsigned long long)limit_mb);
            break;
        } catch (const std::exception& e) {
            std::string what = e.what();
            size_t at = what.find("needs");
            if (limit_mb == 64 && at != std::string::npos) std::printf("at 64 MB: %s", what.substr(what.rfind('\n', at) + 1).c_str());
        }
    }
    return 0;
}

const char* const usage =
    "usage: bench_scale COMMAND DIR|FILE [options]\n"
    "  generate DIR [--triangles N] [--obj 0|1]   write a displaced-grid mesh of about N triangles (default 10000000) as\n"
    "                                             DIR/mesh.ply (binary), mesh.serialized and mesh.obj (not with --obj 0),\n"
    "                                             and a scene for each\n"
    "  floor FILE.ply                             the floor: read the PLY into two arrays, hand them to Embree as shared\n"
    "                                             buffers, build at Candela's build quality, trace one ray\n"
    "  parse FILE                                 construct one mesh plugin (obj, ply, serialized) in this process and\n"
    "                                             time it: MB/s of the file\n"
    "  load DIR --candela BIN [--rounds R] [--obj 0|1]\n"
    "                                             start to first sample and peak resident memory, side by side: the floor,\n"
    "                                             then `candela render` of each format's scene, R times (default 3; the\n"
    "                                             obj scene once, not with --obj 0)\n"
    "  instances DIR --candela BIN [--instances K] [--triangles N]\n"
    "                                             K instances (default 10000) of one N-triangle mesh (default 1000000):\n"
    "                                             peak memory against one mesh alone\n"
    "  growth DIR --candela BIN                   time per sample on the same view for 10^3, 10^5, 10^7 triangles and\n"
    "                                             10^10 instanced; writes DIR/growth.svg\n"
    "  film DIR --candela BIN                     an 8K render with AOVs: peak memory against the memory check's estimate\n";

int run(int argc, char** argv) {
    if (argc > 1 && bench::is_option(argv[1])) bench::reject_argument(argv[1]);
    if (argc < 3) {
        std::fprintf(stderr, "usage: bench_scale generate|floor|parse|load|instances|growth|film DIR|FILE [options] (see --help)\n");
        return 2;
    }
    const std::string command = argv[1], target = argv[2];
    // The options of each command.
    const std::map<std::string, std::vector<std::string>> options = {{"generate", {"--triangles", "--obj"}},
                                                                     {"floor", {}},
                                                                     {"parse", {}},
                                                                     {"load", {"--candela", "--rounds", "--obj"}},
                                                                     {"instances", {"--candela", "--instances", "--triangles"}},
                                                                     {"growth", {"--candela"}},
                                                                     {"film", {"--candela"}}};
    const auto known = options.find(command);
    if (known == options.end()) throw bench::UsageError("unknown command " + command);
    std::string candela;
    long long triangles = command == "generate" ? 10000000 : 1000000;
    int rounds = 3, instances = 10000;
    bool obj = true;
    for (int i = 3; i < argc; ++i) {
        const std::string a = argv[i];
        if (std::find(known->second.begin(), known->second.end(), a) == known->second.end())
            bench::reject_argument(a);
        else if (a == "--candela")
            candela = bench::option_value(argc, argv, i);
        else if (a == "--triangles")
            triangles = bench::parse_whole(a, bench::option_value(argc, argv, i), 1, LLONG_MAX);
        else if (a == "--rounds")
            rounds = bench::int_option(argc, argv, i, 1);
        else if (a == "--instances")
            instances = bench::int_option(argc, argv, i, 1);
        else if (a == "--obj")
            obj = bench::parse_whole(a, bench::option_value(argc, argv, i), 0, 1) == 1;
    }
    if ((command == "load" || command == "instances" || command == "growth" || command == "film") && candela.empty())
        throw bench::UsageError("--candela BIN is needed");
    if (command == "generate") return generate(target, uint64_t(triangles), obj);
    if (command == "floor") return floor_run(target);
    if (command == "parse") return parse_run(target);
    if (command == "load") return load_run(target, fs::absolute(candela).string(), rounds, obj);
    if (command == "instances") return instances_run(target, fs::absolute(candela).string(), instances, uint64_t(triangles));
    if (command == "growth") return growth_run(target, fs::absolute(candela).string());
    return film_run(target, fs::absolute(candela).string());
}

}  // namespace

int main(int argc, char** argv) { return bench::run_main(argc, argv, usage, run); }
