#pragma once
// The Embree 3 acceleration structure: one BVH over every shape of the scene, answering
// closest-hit and shadow (any-hit) queries.

#include "core/shape.h"

#include <embree3/rtcore.h>
#include <vector>

namespace candela {

class Accel {
public:
    Accel();
    ~Accel();
    Accel(const Accel&) = delete;
    Accel& operator=(const Accel&) = delete;

    void build(const std::vector<Ref<Shape>>& shapes);

    // Closest hit within [ray.tmin, ray.tmax]; returns the shape hit (null for a miss).
    const Shape* intersect(const Ray& ray, RayHit& hit) const;
    // True when anything blocks the ray within [ray.tmin, ray.tmax].
    bool occluded(const Ray& ray) const;

    RTCDevice device() const { return device_; }

private:
    RTCDevice device_ = nullptr;
    RTCScene scene_ = nullptr;
    std::vector<const Shape*> shapes_;  // by Embree geometry id
};

}  // namespace candela
