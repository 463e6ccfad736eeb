#include "lights/light_tree.h"

#include "core/scene.h"

#include <numeric>

namespace candela {

namespace {

float angle_of(float cos_theta) { return safe_acos(cos_theta); }

// cos(max(0, a - b)) from the sines and cosines of a and b.
float cos_sub_clamped(float sin_a, float cos_a, float sin_b, float cos_b) {
    if (cos_a > cos_b) return 1.0f;
    return cos_a * cos_b + sin_a * sin_b;
}
float sin_sub_clamped(float sin_a, float cos_a, float sin_b, float cos_b) {
    if (cos_a > cos_b) return 0.0f;
    return sin_a * cos_b - cos_a * sin_b;
}

// The orientation measure M_Omega of pbrt-v4's surface-area-orientation heuristic.
float orientation_measure(const LightBounds& b) {
    float theta_o = angle_of(b.cos_theta_o), theta_e = angle_of(b.cos_theta_e);
    float theta_w = std::min(theta_o + theta_e, Pi);
    float sin_o = std::sin(theta_o);
    return TwoPi * (1.0f - b.cos_theta_o) +
           Pi / 2.0f * (2.0f * theta_w * sin_o - std::cos(theta_o - 2.0f * theta_w) - 2.0f * theta_o * sin_o + b.cos_theta_o);
}

float surface_area(const BoundingBox& b) {
    Vec3 d = b.extents();
    return 2.0f * (d.x * d.y + d.y * d.z + d.z * d.x);
}

}  // namespace

float light_importance(const LightBounds& b, const Vec3& p, const Vec3& n) {
    if (b.phi <= 0.0f) return 0.0f;
    Vec3 pc = b.box.center();
    float diag = glm::length(b.box.extents());
    float d2 = std::max(std::max(squared_length(p - pc), 0.25f * diag * diag), 1e-20f);
    Vec3 wi = p - pc;
    float len = glm::length(wi);
    wi = len > 0.0f ? wi / len : Vec3(0.0f, 0.0f, 1.0f);
    // Angle between the emission axis and the direction toward p.
    float cos_w = glm::dot(b.axis, wi);
    if (b.two_sided) cos_w = std::abs(cos_w);
    float sin_w = safe_sqrt(1.0f - cos_w * cos_w);
    // Half-angle of the bounding sphere of the box as seen from p.
    float r2 = 0.25f * diag * diag, dist2 = squared_length(p - pc);
    float cos_b = dist2 <= r2 ? -1.0f : safe_sqrt(1.0f - r2 / dist2);
    float sin_b = safe_sqrt(1.0f - cos_b * cos_b);
    float sin_o = safe_sqrt(1.0f - b.cos_theta_o * b.cos_theta_o);
    // theta' = max(0, theta_w - theta_o - theta_b): the smallest angle from the cone to p.
    float cos_x = cos_sub_clamped(sin_w, cos_w, sin_o, b.cos_theta_o);
    float sin_x = sin_sub_clamped(sin_w, cos_w, sin_o, b.cos_theta_o);
    float cos_p = cos_sub_clamped(sin_x, cos_x, sin_b, cos_b);
    // Nothing is emitted more than theta_e beyond the cone (strictly: a spot light has
    // theta_e = 0 and still lights everything inside its cone).
    if (cos_p < b.cos_theta_e) return 0.0f;
    float importance = b.phi * cos_p / d2;
    if (n != Vec3(0.0f)) {
        // The receiver's cosine, widened by the same bounding angle.
        float cos_i = std::abs(glm::dot(wi, n)), sin_i = safe_sqrt(1.0f - cos_i * cos_i);
        importance *= cos_sub_clamped(sin_i, cos_i, sin_b, cos_b);
    }
    return std::max(importance, 0.0f);
}

LightBounds light_bounds_union(const LightBounds& a, const LightBounds& b) {
    if (a.phi == 0.0f) return b;
    if (b.phi == 0.0f) return a;
    LightBounds r;
    r.box = a.box;
    r.box.expand(b.box);
    r.phi = a.phi + b.phi;
    r.two_sided = a.two_sided || b.two_sided;
    r.cos_theta_e = std::min(a.cos_theta_e, b.cos_theta_e);
    // Smallest cone around both direction cones (pbrt-v4's DirectionCone::Union).
    float theta_a = angle_of(a.cos_theta_o), theta_b = angle_of(b.cos_theta_o);
    float theta_d = angle_of(std::clamp(glm::dot(a.axis, b.axis), -1.0f, 1.0f));
    if (std::min(theta_d + theta_b, Pi) <= theta_a) {
        r.axis = a.axis;
        r.cos_theta_o = a.cos_theta_o;
    } else if (std::min(theta_d + theta_a, Pi) <= theta_b) {
        r.axis = b.axis;
        r.cos_theta_o = b.cos_theta_o;
    } else {
        float theta_o = 0.5f * (theta_a + theta_d + theta_b);
        if (theta_o >= Pi) {
            r.axis = a.axis;
            r.cos_theta_o = -1.0f;
        } else {
            // Rotate a's axis toward b's by theta_o - theta_a.
            float theta_r = theta_o - theta_a;
            Vec3 w = glm::cross(a.axis, b.axis);
            if (squared_length(w) == 0.0f) {
                r.axis = a.axis;
                r.cos_theta_o = -1.0f;
            } else {
                r.axis = glm::normalize(Vec3(Transform::rotate(w, degrees(theta_r)).apply_vector(a.axis)));
                r.cos_theta_o = std::cos(theta_o);
            }
        }
    }
    return r;
}

LightTree::LightTree(const Scene& scene) : LightSampler(scene) {
    std::vector<LightBounds> all;
    for (const auto& e : scene.emitters()) {
        if (auto b = e->bounds()) {
            bounded_.push_back(e.get());
            all.push_back(*b);
        } else {
            unbounded_index_[e.get()] = unbounded_.size();
            unbounded_.push_back(e.get());
        }
    }
    if (bounded_.empty()) return;
    build(all);
    for (int node = 0; node < int(nodes_.size()); ++node)
        if (nodes_[node].light >= 0) leaf_[bounded_[nodes_[node].light]] = node;
    p_unbounded_ = float(unbounded_.size()) / float(unbounded_.size() + 1);
}

namespace {

// Where to split the lights ids[begin, end) (at least two): the surface-area-orientation
// heuristic over 12 buckets per axis; in the middle when all centroids coincide or every bucket
// falls on one side.
size_t split_lights(std::vector<int>& ids, size_t begin, size_t end, const std::vector<LightBounds>& all) {
    LightBounds total;
    BoundingBox centroids;
    for (size_t i = begin; i < end; ++i) {
        total = light_bounds_union(total, all[ids[i]]);
        centroids.expand(all[ids[i]].box.center());
    }
    if (total.phi == 0.0f) total.box = all[ids[begin]].box;
    constexpr int Buckets = 12;
    float best_cost = Infinity;
    int best_axis = -1, best_bucket = -1;
    Vec3 ext = centroids.extents();
    float max_ext = max_component(total.box.extents());
    for (int axis = 0; axis < 3; ++axis) {
        if (ext[axis] <= 0.0f) continue;
        LightBounds bucket[Buckets];
        for (size_t i = begin; i < end; ++i) {
            float t = (all[ids[i]].box.center()[axis] - centroids.min[axis]) / ext[axis];
            int b = std::min(int(t * Buckets), Buckets - 1);
            bucket[b] = light_bounds_union(bucket[b], all[ids[i]]);
        }
        for (int split = 0; split < Buckets - 1; ++split) {
            LightBounds below, above;
            for (int b = 0; b <= split; ++b) below = light_bounds_union(below, bucket[b]);
            for (int b = split + 1; b < Buckets; ++b) above = light_bounds_union(above, bucket[b]);
            float kr = max_ext / std::max(total.box.extents()[axis], 1e-20f);
            auto cost = [&](const LightBounds& lb) { return lb.phi * orientation_measure(lb) * surface_area(lb.box); };
            float c = kr * (cost(below) + cost(above));
            if (c < best_cost) {
                best_cost = c;
                best_axis = axis;
                best_bucket = split;
            }
        }
    }
    if (best_axis < 0) return (begin + end) / 2;  // all centroids coincide
    auto it = std::partition(ids.begin() + long(begin), ids.begin() + long(end), [&](int id) {
        float t = (all[id].box.center()[best_axis] - centroids.min[best_axis]) / ext[best_axis];
        return std::min(int(t * Buckets), Buckets - 1) <= best_bucket;
    });
    size_t mid = size_t(it - ids.begin());
    return mid == begin || mid == end ? (begin + end) / 2 : mid;
}

}  // namespace

// Depth first with an explicit stack (the tree may be as deep as there are lights: collinear
// lights have bounds of zero area, every split costs zero and cuts off one bucket), so nodes get
// the order of a recursive build: a node, its first subtree, then its second.
void LightTree::build(const std::vector<LightBounds>& all) {
    std::vector<int> ids(all.size());
    std::iota(ids.begin(), ids.end(), 0);
    struct Range {
        size_t begin, end;
        int parent;  // the node whose second child this range becomes, or -1
    };
    std::vector<Range> todo = {{0, ids.size(), -1}};
    while (!todo.empty()) {
        Range r = todo.back();
        todo.pop_back();
        int index = int(nodes_.size());
        nodes_.emplace_back();
        if (r.parent >= 0) nodes_[r.parent].child1 = index;
        if (r.end - r.begin == 1) {
            nodes_[index].bounds = all[ids[r.begin]];
            nodes_[index].light = ids[r.begin];
            continue;
        }
        size_t mid = split_lights(ids, r.begin, r.end, all);
        todo.push_back({mid, r.end, index});
        todo.push_back({r.begin, mid, -1});
    }
    // Children come after their parent: a backward sweep bounds every interior node.
    for (int i = int(nodes_.size()) - 1; i >= 0; --i)
        if (nodes_[i].light < 0) nodes_[i].bounds = light_bounds_union(nodes_[i + 1].bounds, nodes_[nodes_[i].child1].bounds);
}

const Emitter* LightTree::sample(const SurfaceInteraction& ref, float u, float& prob) const {
    prob = 0.0f;
    size_t n_unbounded = unbounded_.size();
    const float p_unbounded = p_unbounded_;
    if (u < p_unbounded) {
        if (n_unbounded == 0) return nullptr;
        size_t i = std::min(size_t(u / p_unbounded * float(n_unbounded)), n_unbounded - 1);
        prob = p_unbounded / float(n_unbounded);
        return unbounded_[i];
    }
    if (nodes_.empty()) return nullptr;
    u = std::min((u - p_unbounded) / (1.0f - p_unbounded), std::nextafter(1.0f, 0.0f));
    const Vec3& n = ref.shading.n;
    float pmf = 1.0f - p_unbounded;
    int node = 0;
    while (nodes_[node].light < 0) {
        const Node& nd = nodes_[node];
        float i0 = light_importance(nodes_[node + 1].bounds, ref.p, n), i1 = light_importance(nodes_[nd.child1].bounds, ref.p, n);
        if (i0 == 0.0f && i1 == 0.0f) return nullptr;
        float p0 = i0 / (i0 + i1);
        if (u < p0) {
            u = std::min(u / p0, std::nextafter(1.0f, 0.0f));
            pmf *= p0;
            node = node + 1;
        } else {
            u = std::min((u - p0) / (1.0f - p0), std::nextafter(1.0f, 0.0f));
            pmf *= 1.0f - p0;
            node = nd.child1;
        }
    }
    prob = pmf;
    return bounded_[nodes_[node].light];
}

float LightTree::pmf(const SurfaceInteraction& ref, const Emitter* emitter) const {
    const float p_unbounded = p_unbounded_;
    if (unbounded_index_.count(emitter)) return p_unbounded / float(unbounded_.size());
    auto it = leaf_.find(emitter);
    if (it == leaf_.end()) return 0.0f;
    const int leaf = it->second;
    const Vec3& n = ref.shading.n;
    float pmf = 1.0f - p_unbounded;
    // The same descent as sample(), steered toward the leaf instead of by u.
    int node = 0;
    while (node != leaf) {
        const Node& nd = nodes_[node];
        float i0 = light_importance(nodes_[node + 1].bounds, ref.p, n), i1 = light_importance(nodes_[nd.child1].bounds, ref.p, n);
        if (i0 == 0.0f && i1 == 0.0f) return 0.0f;
        bool second = leaf >= nd.child1;
        pmf *= second ? i1 / (i0 + i1) : i0 / (i0 + i1);
        node = second ? nd.child1 : node + 1;
    }
    return pmf;
}

}  // namespace candela
