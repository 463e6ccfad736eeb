#pragma once
// What sampling profilers read about the calling thread (defined in accel.cpp).

namespace candela {

// Whether the calling thread is inside an Embree query at this moment. A sampling profiler
// (bench_throughput's SIGPROF handler) reads it to tell the time spent in Embree from the rest.
bool thread_inside_embree();

}  // namespace candela
