// Replaces the global operator new and delete of the test binary, to count allocations (see
// allocation_counter.h). libstdc++'s array and nothrow forms call these, so replacing them
// sees every non-aligned allocation. Not in sanitizer builds: AddressSanitizer
// and ThreadSanitizer provide their own.

#include "tests/allocation_counter.h"

#include <atomic>
#include <cstdlib>
#include <new>

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define CANDELA_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define CANDELA_SANITIZED 1
#endif
#endif

namespace {

std::atomic<bool> g_counting{false};
std::atomic<size_t> g_calls{0}, g_bytes{0};

}  // namespace

namespace candela::test {

AllocationCount::AllocationCount() {
    g_calls = 0;
    g_bytes = 0;
    g_counting = true;
}
AllocationCount::~AllocationCount() { g_counting = false; }
size_t AllocationCount::calls() const { return g_calls.load(); }
size_t AllocationCount::bytes() const { return g_bytes.load(); }

#ifdef CANDELA_SANITIZED
bool allocations_counted() { return false; }
#else
bool allocations_counted() { return true; }
#endif

}  // namespace candela::test

#ifndef CANDELA_SANITIZED

void* operator new(std::size_t size) {
    if (g_counting.load(std::memory_order_relaxed)) {
        g_calls.fetch_add(1, std::memory_order_relaxed);
        g_bytes.fetch_add(size, std::memory_order_relaxed);
    }
    if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
    throw std::bad_alloc();
}

void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

#endif
