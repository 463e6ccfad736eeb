#include "core/medium.h"

#include "core/properties.h"
#include "core/registry.h"
#include "core/volume.h"

namespace candela {

Medium::Medium(const Properties& props) {
    sample_emitters_ = props.get_bool("sample_emitters", true);
    auto phases = props.get_objects(ObjectKind::Phase);
    if (phases.size() > 1) props.fail("a medium has at most one phase function");
    phase_ = phases.empty() ? create_plugin_as<PhaseFunction>(ObjectKind::Phase, Properties("isotropic", props.location()))
                            : std::static_pointer_cast<PhaseFunction>(phases[0]);
    microflake_ = phase_->is_microflake();
}

MediumPoint Medium::eval(const Vec3& p, const Vec3& d, const Wavelengths* w) const {
    MediumPoint mp = coefficients(p, w);
    if (!microflake_) return mp;
    float area = phase_->projected_area(MediumInteraction{p, -d});
    mp.sigma_t *= area;
    mp.sigma_s *= area;
    return mp;
}

MajorantIterator Medium::majorants(const Ray& ray, float tmax) const {
    MajorantIterator it = coefficient_majorants(ray, tmax);
    if (microflake_) it.scale_by(phase_->max_projected_area(ray.d));
    return it;
}

Spectrum Medium::transmittance(const Ray& ray, float tmax, PCG32& rng) const { return ratio_tracking_transmittance(*this, ray, tmax, rng); }

// --- majorants ---------------------------------------------------------------------------------

MajorantGrid::MajorantGrid(const Volume& volume, const glm::ivec3& resolution, float scale, bool spectral)
    : volume_(&volume), resolution_(glm::max(resolution, glm::ivec3(1))) {
    maxima_.resize(size_t(resolution_.x) * size_t(resolution_.y) * size_t(resolution_.z));
    Vec3 cell_size = Vec3(1.0f) / Vec3(resolution_);
    size_t i = 0;
    for (int z = 0; z < resolution_.z; ++z)
        for (int y = 0; y < resolution_.y; ++y)
            for (int x = 0; x < resolution_.x; ++x) {
                Vec3 lo = Vec3(float(x), float(y), float(z)) * cell_size;
                maxima_[i++] = spectral ? Spectrum(volume.max_spectrum_in_local_box(lo, lo + cell_size) * scale)
                                        : volume.max_in_local_box(lo, lo + cell_size) * scale;
            }
}

MajorantIterator::MajorantIterator(float t0, float t1, const Spectrum& sigma_maj)
    : done_(!(t1 > t0)), t0_(t0), t1_(t1), sigma_(sigma_maj) {}

MajorantIterator::MajorantIterator(const MajorantGrid& grid, const Ray& ray, float tmin, float tmax) : grid_(&grid) {
    // The ray in the volume's local coordinates: an affine map keeps the ray parameter t.
    const Volume& volume = grid.volume();
    Vec3 o = volume.to_local(ray.o), d = volume.to_local_vector(ray.d);
    float ta = tmin, tb = tmax;
    for (int axis = 0; axis < 3; ++axis) {
        if (d[axis] == 0.0f) {
            if (o[axis] < 0.0f || o[axis] > 1.0f) return;  // parallel to the slab and outside it
            continue;
        }
        float t_near = (0.0f - o[axis]) / d[axis], t_far = (1.0f - o[axis]) / d[axis];
        if (t_near > t_far) std::swap(t_near, t_far);
        ta = std::max(ta, t_near);
        tb = std::min(tb, t_far);
    }
    if (!(ta < tb)) return;
    done_ = false;
    t0_ = ta;
    t1_ = tb;
    const glm::ivec3& res = grid.resolution();
    Vec3 p = o + ta * d;
    for (int axis = 0; axis < 3; ++axis) {
        cell_[axis] = std::clamp(int(std::floor(p[axis] * float(res[axis]))), 0, res[axis] - 1);
        if (d[axis] > 0.0f) {
            step_[axis] = 1;
            next_t_[axis] = ta + (float(cell_[axis] + 1) / float(res[axis]) - p[axis]) / d[axis];
            delta_t_[axis] = 1.0f / (float(res[axis]) * d[axis]);
        } else if (d[axis] < 0.0f) {
            step_[axis] = -1;
            next_t_[axis] = ta + (float(cell_[axis]) / float(res[axis]) - p[axis]) / d[axis];
            delta_t_[axis] = -1.0f / (float(res[axis]) * d[axis]);
        } else {
            step_[axis] = 0;
            next_t_[axis] = Infinity;
            delta_t_[axis] = Infinity;
        }
    }
}

bool MajorantIterator::next(MajorantSegment& segment) {
    if (done_) return false;
    if (!grid_) {
        segment = MajorantSegment{t0_, t1_, sigma_ * factor_};
        done_ = true;
        return true;
    }
    int axis = next_t_.x < next_t_.y ? (next_t_.x < next_t_.z ? 0 : 2) : (next_t_.y < next_t_.z ? 1 : 2);
    float t_exit = std::min(next_t_[axis], t1_);
    segment = MajorantSegment{t0_, std::max(t_exit, t0_), grid_->at(cell_) * factor_};
    t0_ = t_exit;
    cell_[axis] += step_[axis];
    next_t_[axis] += delta_t_[axis];
    if (t_exit >= t1_ || cell_[axis] < 0 || cell_[axis] >= grid_->resolution()[axis]) done_ = true;
    return true;
}

// --- tracking ----------------------------------------------------------------------------------

namespace {

// exp(-(a - b) * distance), with 0 * infinity taken as 0 (equal majorants over an endless segment).
Spectrum relative_decay(const Spectrum& a, float b, float distance) {
    Spectrum out;
    for (int k = 0; k < 3; ++k) {
        float difference = a[k] - b;
        out[k] = difference == 0.0f ? 1.0f : std::exp(-difference * distance);
    }
    return out;
}

// An exponential free path of rate `rate` (> 0).
float exponential_step(PCG32& rng, float rate) { return -std::log1p(-rng.next_float()) / rate; }

}  // namespace

bool sample_free_flight(const Medium& medium, const Ray& ray, float tmax, PCG32& rng, TrackingWeights& w, float& t, MediumPoint& point) {
    MajorantIterator segments = medium.majorants(ray, tmax);
    MajorantSegment seg;
    const int c = w.channel;
    while (segments.next(seg)) {
        Spectrum majorant = w.shared_majorant ? Spectrum(max_component(seg.sigma_maj)) : seg.sigma_maj;
        float mu_c = majorant[c];
        float t0 = seg.t0;
        for (;;) {
            // Passing the rest of the segment: f_j = exp(-mu_j d), technique k's pdf exp(-mu_k d).
            float step = mu_c > 0.0f ? exponential_step(rng, mu_c) : Infinity;
            if (!(t0 + step < seg.t1)) {
                Spectrum decay = relative_decay(majorant, mu_c, seg.t1 - t0);
                w.beta *= decay;
                w.ratio *= decay;
                break;
            }
            // A collision: f_j = exp(-mu_j s), technique k's pdf mu_k exp(-mu_k s), then real
            // (f sigma_s, pdf sigma_t / mu) or null (f sigma_n, pdf sigma_n / mu).
            t0 += step;
            Spectrum decay = relative_decay(majorant, mu_c, step);
            point = medium.eval(ray(t0), ray.d, ray.wavelengths);
            Spectrum sigma_n = glm::max(majorant - point.sigma_t, Spectrum(0.0f));
            float p_real = std::clamp(point.sigma_t[c] / mu_c, 0.0f, 1.0f);
            if (rng.next_float() < p_real) {
                w.beta *= point.sigma_s * decay / point.sigma_t[c];
                w.ratio *= point.sigma_t * decay / point.sigma_t[c];
                t = t0;
                return true;
            }
            w.beta *= sigma_n * decay / sigma_n[c];
            w.ratio *= sigma_n * decay / sigma_n[c];
            if (is_black(w.beta)) return false;
        }
    }
    return false;
}

Spectrum ratio_tracking_transmittance(const Medium& medium, const Ray& ray, float tmax, PCG32& rng) {
    MajorantIterator segments = medium.majorants(ray, tmax);
    MajorantSegment seg;
    Spectrum T(1.0f);
    while (segments.next(seg)) {
        float mu = max_component(seg.sigma_maj);
        if (!(mu > 0.0f)) continue;
        for (float t = seg.t0 + exponential_step(rng, mu); t < seg.t1; t += exponential_step(rng, mu)) {
            T *= glm::max(Spectrum(1.0f) - medium.eval(ray(t), ray.d, ray.wavelengths).sigma_t / mu, Spectrum(0.0f));
            // Russian roulette once little is left: unbiased, and it ends long walks early.
            if (max_component(T) < 0.1f) {
                if (rng.next_float() < 0.5f) return Spectrum(0.0f);
                T *= 2.0f;
            }
            if (is_black(T)) return T;
        }
    }
    return T;
}

}  // namespace candela
