// gridvolume: values on a voxel grid read from Mitsuba's binary .vol file, interpolated
// (Mitsuba 3's `gridvolume`).
//
// Parameters:
//   filename        string      the .vol file (found like every file a scene names)
//   filter_type     string      trilinear (default) or nearest: how values between voxel centres
//                               are found; voxel (i, j, k) has its centre at ((i, j, k) + 0.5) / res
//                               in the unit cube, as in Mitsuba's textures
//   wrap_mode       string      clamp (default), repeat or mirror: lookups beyond the edge voxels
//   use_grid_bbox   boolean     place the unit cube on the bounding box stored in the file, before
//                               to_world (default false)
//   to_world        transform   places the unit cube [0, 1]^3 (default identity)
//   raw             boolean     Mitsuba's switch that turns spectral upsampling off (default
//                               false); true is accepted in scalar_rgb, where it changes nothing,
//                               and refused in scalar_spectral for a grid of 3 channels
//
// In scalar_spectral a grey grid (1 channel) gives its value at every wavelength; a 3-channel
// grid is interpolated as a colour and the colour upsampled for the role of the medium
// parameter it serves (core/volume.h). Majorants: the grey value, or 2 max(rgb) (core/volume.h).
//
// The .vol format (little endian): bytes 1-3 "VOL", byte 4 the version (3), bytes 5-8 the
// encoding (int32; 1 = float32, the only one), then the int32 resolutions x, y, z, the int32
// channel count (1, 3, or 6 for the matrix S of an `sggx` phase function: S_xx, S_yy, S_zz, S_xy,
// S_xz, S_yz; a colour parameter refuses 6), the bounding box as six
// float32 (xmin, ymin, zmin, xmax, ymax, zmax), and the data, x fastest:
// data[((z * yres + y) * xres + x) * channels + channel].

#include "core/memory_budget.h"
#include "core/registry.h"
#include "core/volume.h"

#include <cstring>
#include <fstream>

namespace candela {

class GridVolume : public Volume {
public:
    explicit GridVolume(const Properties& props) : Volume(props) {
        std::string filter = props.get_string("filter_type", "trilinear");
        if (filter != "trilinear" && filter != "nearest")
            props.fail("filter_type", "filter_type must be trilinear or nearest, not \"" + filter + "\"");
        nearest_ = filter == "nearest";
        std::string wrap = props.get_string("wrap_mode", "clamp");
        if (wrap == "clamp")
            wrap_ = Wrap::Clamp;
        else if (wrap == "repeat")
            wrap_ = Wrap::Repeat;
        else if (wrap == "mirror")
            wrap_ = Wrap::Mirror;
        else
            props.fail("wrap_mode", "wrap_mode must be clamp, repeat or mirror, not \"" + wrap + "\"");
        const bool raw = props.get_bool("raw", false);
        read_file(props.get_file_path("filename"), props.location_of("filename"));
        if (raw && channels_ == 3 && props.variant() != Variant::ScalarRGB)
            props.fail("raw", "gridvolume: raw colour data (no spectral upsampling) is not implemented in the spectral variant");
        if (props.get_bool("use_grid_bbox", false)) {
            Vec3 extent = file_bbox_.max - file_bbox_.min;
            if (!(min_component(extent) > 0.0f)) props.fail("use_grid_bbox", "the bounding box stored in the file is empty");
            set_to_world(to_world_ * Transform::translate(file_bbox_.min) * Transform::scale(extent));
        }
    }

    Spectrum eval(const Vec3& p_world) const override {
        float v[6];
        eval_channels(p_world, v);
        return channels_ == 1 ? Spectrum(v[0]) : Spectrum(v[0], v[1], v[2]);
    }

    void eval_channels(const Vec3& p_world, float* out) const override {
        Vec3 p = to_local(p_world) * Vec3(resolution_);
        if (nearest_) {
            const float* v = voxel_values(glm::ivec3(glm::floor(p)));
            for (int k = 0; k < channels_; ++k) out[k] = v[k];
            return;
        }
        Vec3 x = p - Vec3(0.5f);
        Vec3 base = glm::floor(x);
        Vec3 f = x - base;
        glm::ivec3 i0(base);
        for (int k = 0; k < channels_; ++k) out[k] = 0.0f;
        for (int corner = 0; corner < 8; ++corner) {
            glm::ivec3 offset(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1);
            float weight = (offset.x ? f.x : 1.0f - f.x) * (offset.y ? f.y : 1.0f - f.y) * (offset.z ? f.z : 1.0f - f.z);
            if (!(weight > 0.0f)) continue;
            const float* v = voxel_values(i0 + offset);
            for (int k = 0; k < channels_; ++k) out[k] += weight * v[k];
        }
    }
    void max_channels(float* out) const override {
        for (int k = 0; k < channels_; ++k) out[k] = max_[size_t(k)];
    }

    Spectrum max_in_local_box(const Vec3& lo, const Vec3& hi) const override {
        // The voxels whose values can reach a point of the box: for trilinear lookups, those
        // whose centres lie within one voxel of it.
        Vec3 a = lo * Vec3(resolution_), b = hi * Vec3(resolution_);
        glm::ivec3 first = nearest_ ? glm::ivec3(glm::floor(a)) : glm::ivec3(glm::floor(a - Vec3(0.5f)));
        glm::ivec3 last = nearest_ ? glm::ivec3(glm::floor(b)) : glm::ivec3(glm::floor(b - Vec3(0.5f))) + glm::ivec3(1);
        last = glm::min(last, first + resolution_);  // a wider range only repeats voxels
        Spectrum m(0.0f);
        for (int z = first.z; z <= last.z; ++z)
            for (int y = first.y; y <= last.y; ++y)
                for (int x = first.x; x <= last.x; ++x) m = glm::max(m, voxel(glm::ivec3(x, y, z)));
        return m;
    }
    glm::ivec3 resolution() const override { return resolution_; }
    std::string to_string() const override { return "gridvolume"; }

private:
    enum class Wrap { Clamp, Repeat, Mirror };

    int wrap_index(int i, int n) const {
        switch (wrap_) {
            case Wrap::Clamp: return std::clamp(i, 0, n - 1);
            case Wrap::Repeat: return ((i % n) + n) % n;
            case Wrap::Mirror: {
                int m = ((i % (2 * n)) + 2 * n) % (2 * n);
                return m < n ? m : 2 * n - 1 - m;
            }
        }
        return 0;
    }
    const float* voxel_values(const glm::ivec3& i) const {
        size_t index = (size_t(wrap_index(i.z, resolution_.z)) * size_t(resolution_.y) + size_t(wrap_index(i.y, resolution_.y))) *
                           size_t(resolution_.x) +
                       size_t(wrap_index(i.x, resolution_.x));
        return &data_[index * size_t(channels_)];
    }
    Spectrum voxel(const glm::ivec3& i) const {
        const float* v = voxel_values(i);
        return channels_ == 1 ? Spectrum(v[0]) : Spectrum(v[0], v[1], v[2]);
    }

    void read_file(const std::string& path, const SourceLocation& where) {
        std::ifstream in(path, std::ios::binary);
        auto fail = [&](const std::string& message) { throw SceneError(where, "gridvolume \"" + path + "\": " + message); };
        if (!in) fail("cannot open the file");
        char header[48];
        if (!in.read(header, sizeof header)) fail("shorter than the 48-byte header of a .vol file");
        if (std::memcmp(header, "VOL", 3) != 0) fail("not a .vol file (it does not start with \"VOL\")");
        if (header[3] != 3) fail("version " + std::to_string(int(header[3])) + " is not supported (only version 3)");
        int32_t ints[5];
        std::memcpy(ints, header + 4, sizeof ints);
        if (ints[0] != 1) fail("encoding " + std::to_string(ints[0]) + " is not supported (only 1, float32)");
        resolution_ = glm::ivec3(ints[1], ints[2], ints[3]);
        channels_ = ints[4];
        if (min_component(Vec3(resolution_)) < 1.0f) fail("the resolution must be positive in every axis");
        if (channels_ != 1 && channels_ != 3 && channels_ != 6)
            fail(std::to_string(channels_) + " channels: a volume has 1 (grey), 3 (rgb) or 6 (SGGX's S)");
        float box[6];
        std::memcpy(box, header + 24, sizeof box);
        file_bbox_.min = Vec3(box[0], box[1], box[2]);
        file_bbox_.max = Vec3(box[3], box[4], box[5]);
        uint64_t count = saturating_mul(
            saturating_mul(saturating_mul(uint64_t(resolution_.x), uint64_t(resolution_.y)), uint64_t(resolution_.z)), uint64_t(channels_));
        in.seekg(0, std::ios::end);
        uint64_t size = uint64_t(in.tellg());
        if (size != 48 + saturating_mul(count, 4))
            fail("the header promises " + std::to_string(count) + " values (" + std::to_string(48 + saturating_mul(count, 4)) +
                 " bytes) but the file has " + std::to_string(size) + " bytes");
        check_memory(saturating_mul(count, sizeof(float)), "the voxels of a gridvolume", where);
        data_.resize(count);
        in.seekg(48);
        if (!in.read(reinterpret_cast<char*>(data_.data()), std::streamsize(count * sizeof(float)))) fail("cannot read the voxels");
        max_.assign(size_t(channels_), -Infinity);
        for (size_t i = 0; i < data_.size(); ++i) {
            if (!std::isfinite(data_[i])) fail("a voxel value is not finite");
            max_[i % size_t(channels_)] = std::max(max_[i % size_t(channels_)], data_[i]);
        }
    }

    glm::ivec3 resolution_{1};
    bool nearest_ = false;
    Wrap wrap_ = Wrap::Clamp;
    BoundingBox file_bbox_;
    std::vector<float> data_;
    std::vector<float> max_;  // per channel, over all voxels
};

CANDELA_REGISTER_SPECTRAL(GridVolume, ObjectKind::Volume, "gridvolume");

}  // namespace candela
