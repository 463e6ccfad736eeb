#pragma once
// Parallel loops: the one way Candela spreads work over threads.
//
//   parallel_for(count, body)               body(i) for every i in [0, count)
//   parallel_chunks(count, grain, body)     body(begin, end) over consecutive chunks of [0, count)
//                                           of about `grain` indices (at least 1)
//
// Both run on oneTBB: inside the caller's tbb::task_arena when called within arena.execute, else
// on TBB's default arena. They return when every index has run. Which thread runs which chunk is
// not fixed, so a body must not make its result depend on it (chunks write to disjoint outputs,
// or to per-chunk partial results combined in index order afterwards).
//
// Why a wrapper: ThreadSanitizer. Debian's libtbb is not built with ThreadSanitizer, so TSan does
// not see the hand-offs TBB makes between the calling thread and its workers (they wait on
// futexes inside the library) and would report every read by a chunk of data the caller wrote
// before the loop, and every read by the caller of a chunk's results after it, as a race. In a
// TSan build these loops tell it about exactly those two hand-offs (the caller's writes before
// the loop happen before every chunk; every chunk happens before the caller continues), and
// nothing else: chunks are not ordered with each other, so races between chunks are still found.
// In other builds the annotations compile to nothing.

#include <tbb/blocked_range.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cstddef>

#if defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define CANDELA_TSAN_ANNOTATIONS 1
#endif
#endif
#if defined(__SANITIZE_THREAD__)
#define CANDELA_TSAN_ANNOTATIONS 1
#endif

#ifdef CANDELA_TSAN_ANNOTATIONS
extern "C" void __tsan_acquire(void* addr);
extern "C" void __tsan_release(void* addr);
#endif

namespace candela {

// The arena of a render or solver asked for `requested` threads (0 or less: one per core). More
// than the cores is capped to them: TBB would cap its workers anyway, and say so on stderr.
inline tbb::task_arena thread_arena(int requested) {
    if (requested <= 0) return tbb::task_arena(tbb::task_arena::automatic);
    return tbb::task_arena(std::min(requested, tbb::info::default_concurrency()));
}

// The two synchronisation points of one parallel loop (see above). Also used by code that hands
// work to threads TBB starts on its own behalf, such as Embree's BVH build calling shape bounds
// callbacks (core/accel.cpp).
class ParallelHandOff {
public:
    void before_loop() { release(&start_); }  // on the calling thread, before any chunk can run
    void chunk_begins() { acquire(&start_); }
    void chunk_ends() { release(&end_); }
    void after_loop() { acquire(&end_); }  // on the calling thread, once every chunk has run

private:
#ifdef CANDELA_TSAN_ANNOTATIONS
    static void release(void* p) { __tsan_release(p); }
    static void acquire(void* p) { __tsan_acquire(p); }
#else
    static void release(void*) {}
    static void acquire(void*) {}
#endif
    char start_ = 0, end_ = 0;
};

template <typename Body>
void parallel_chunks(size_t count, size_t grain, const Body& body) {
    ParallelHandOff hand_off;
    hand_off.before_loop();
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, std::max<size_t>(grain, 1)), [&](const tbb::blocked_range<size_t>& r) {
        hand_off.chunk_begins();
        body(r.begin(), r.end());
        hand_off.chunk_ends();
    });
    hand_off.after_loop();
}

template <typename Body>
void parallel_for(size_t count, const Body& body) {
    parallel_chunks(count, 1, [&](size_t begin, size_t end) {
        for (size_t i = begin; i != end; ++i) body(i);
    });
}

}  // namespace candela
