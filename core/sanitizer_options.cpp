// Run-time options and suppressions of the sanitizer builds (CANDELA_SANITIZE=address or thread,
// see README "Sanitizers and fuzzing"). The sanitizer run-times call these functions at start-up,
// so every program of such a build (tests, the candela program the CLI tests start, fuzzers)
// runs with the same settings however it is started; an *SAN_OPTIONS variable in the environment
// still overrides them. In an ordinary build this file compiles to nothing.
//
// A suppression may only name code outside Candela, and each says why it is there.

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define CANDELA_ASAN 1
#endif
#if __has_feature(thread_sanitizer)
#define CANDELA_TSAN 1
#endif
#endif

#define CANDELA_SANITIZER_HOOK extern "C" __attribute__((visibility("default"), used))

#ifdef CANDELA_ASAN
// Leaks are errors; use-after-return and initialization-order bugs too (plugins register
// through static objects, so the order of dynamic initialisation matters here).
CANDELA_SANITIZER_HOOK const char* __asan_default_options() {
    return "detect_leaks=1:detect_stack_use_after_return=1:check_initialization_order=1:strict_init_order=1";
}

// The build always pairs UBSan with ASan (-fno-sanitize-recover=all makes every finding fatal).
CANDELA_SANITIZER_HOOK const char* __ubsan_default_options() { return "print_stacktrace=1:halt_on_error=1"; }

CANDELA_SANITIZER_HOOK const char* __lsan_default_suppressions() {
    // Mesa's OSMesa (used only by the OpenGL oracle test) keeps memory it allocates inside
    // OSMesaMakeCurrent after OSMesaDestroyContext; unbinding the context first does not free
    // it (checked with Mesa 22.3.6). Every allocating frame is inside libOSMesa.so.
    //
    // OpenImageIO 2.4's PNG reader builds an error message (a std::string) in its libpng read
    // callback, and libpng then longjmps out of the callback past the string's destructor: every
    // truncated PNG leaks the message. Matching needs the full allocation stack (libstdc++ has no
    // frame pointers), so the image fuzzer runs with fast_unwind_on_malloc=0 (fuzz/CMakeLists.txt).
    return "leak:libOSMesa.so\n"
           "leak:PNGInput::PngReadCallback\n";
}
#endif

#ifdef CANDELA_TSAN
#include <OpenEXR/ImfThreading.h>

namespace {
// OpenEXR compresses and decompresses on a pool of its own threads (IlmThread), uninstrumented,
// whose semaphore locks a mutex on one thread and unlocks it on another: TSan reports that as
// misuse inside Candela's frames, where OpenEXR's calls return. Candela does not depend on that
// pool, so this build does its EXR work on the calling thread (Imf::setGlobalThreadCount(0):
// single-threaded; the image module turns OpenImageIO's exr_threads off when it is loaded, see
// imageio/oiio_codecs.cpp). Other builds keep the pool.
struct SingleThreadedExr {
    SingleThreadedExr() { Imf::setGlobalThreadCount(0); }
} single_threaded_exr;
}  // namespace

CANDELA_SANITIZER_HOOK const char* __tsan_default_options() { return "halt_on_error=1:second_deadlock_stack=1"; }

CANDELA_SANITIZER_HOOK const char* __tsan_default_suppressions() {
    // Debian builds libtbb and libembree3 without ThreadSanitizer, so TSan cannot see how they
    // synchronise their own threads. Candela's code and the hand-offs to it stay checked
    // (core/parallel.h, EmbreeCallbackScope in core/accel.h, core/tsan_ignorelist.txt); these
    // cover what is left inside the libraries:
    //
    // - called_from_lib: TSan still intercepts the C library calls the libraries make (malloc and
    //   free, memcpy, memcmp, memset) and would report, say, a block Embree's build thread
    //   allocates and the main thread frees. Interceptor calls from inside them are ignored, as
    //   everything else they do is. libstdc++.so is one of them: Embree compares its device's
    //   settings strings (written by rtcNewDevice on the main thread) on its build threads
    //   through libstdc++'s out-of-line string functions. Candela's own string code is inlined
    //   from the headers and stays checked.
    // - race:fold_tree: when a worker finishes the last chunk of a parallel loop, oneTBB's
    //   (header) code decrements the loop's wait counter, which lives on the stack of the thread
    //   that started the loop; that thread wakes up inside libtbb and reuses the stack. Only
    //   oneTBB's bookkeeping runs in fold_tree (a parallel_for's finalisation calls no Candela
    //   code), so no race of Candela's own is hidden by it.
    // - race:is_group_execution_cancelled: the same stack, read the other way. Between chunks,
    //   oneTBB's partitioner (header code, after Candela's chunk has ended and published its
    //   hand-off) asks the loop's task_group_context, also on the starting thread's stack, whether
    //   the loop was cancelled. The read precedes the worker's decrement of the wait counter, but
    //   the starting thread's wake-up on that counter happens inside libtbb, so TSan may pair the
    //   read with the next use of that stack (seen once in 2026-12-01's TSan stage, under ctest
    //   -j2, raster clipping followed by the light set-up). Only oneTBB calls that function.
    return "called_from_lib:libtbb.so.12\n"
           "called_from_lib:libembree3.so.3\n"
           "called_from_lib:libstdc++.so.6\n"
           "race:fold_tree<tbb::detail::d1::tree_node>\n"
           "race:is_group_execution_cancelled\n";
}
#endif
