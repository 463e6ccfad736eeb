#pragma once
// A bounding volume hierarchy over lights for many-light sampling (Conty Estevez & Kulla 2018,
// "Importance Sampling of Many Lights with Adaptive Tree Splitting"; the orientation-aware
// build and importance of pbrt-v4, section 12.6.3). Lights without bounds (infinite and
// directional ones) are picked separately, uniformly, with probability n_unbounded / (n + 1).

#include "lights/light_sampler.h"

namespace candela {

// An upper bound on the contribution of lights within `b` to point p with normal n (n may be
// zero for points without a surface).
float light_importance(const LightBounds& b, const Vec3& p, const Vec3& n);
// The bounds of the union of two light sets.
LightBounds light_bounds_union(const LightBounds& a, const LightBounds& b);

class LightTree final : public LightSampler {
public:
    explicit LightTree(const Scene& scene);
    const Emitter* sample(const SurfaceInteraction& ref, float u, float& prob) const override;
    float pmf(const SurfaceInteraction& ref, const Emitter* emitter) const override;

private:
    struct Node {
        LightBounds bounds;
        int child1 = -1;  // interior: second child (the first is the next node, and its
                          // subtree is the nodes before child1)
        int light = -1;   // leaf: index into bounded_
    };
    void build(const std::vector<LightBounds>& all);

    std::vector<Node> nodes_;
    std::vector<const Emitter*> bounded_, unbounded_;
    // The probability of picking an unbounded light, n_unbounded / (n_unbounded + 1) (1 without
    // bounded lights). Computed once: size_t -> float conversions cost about ten instructions
    // each on x86-64, and sample() runs at every path vertex.
    float p_unbounded_ = 1.0f;
    // The leaf of each bounded light. Nodes are stored depth first, so a node's subtree is a
    // contiguous range and the first child's ends where the second child begins: the path to a
    // leaf follows from the leaf's index alone, at any depth.
    std::unordered_map<const Emitter*, int> leaf_;
    std::unordered_map<const Emitter*, size_t> unbounded_index_;
};

}  // namespace candela
