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
CANDELA_SANITIZER_HOOK const char* __tsan_default_options() { return "halt_on_error=1:second_deadlock_stack=1"; }

CANDELA_SANITIZER_HOOK const char* __tsan_default_suppressions() { return ""; }
#endif
