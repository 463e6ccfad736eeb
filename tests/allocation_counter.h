#pragma once
// Counts the calls of the global operator new (every thread) while an AllocationCount is alive.
// The test binary replaces operator new and delete for this (allocation_counter.cpp); the
// sanitizer builds keep their own (they must, to check every allocation), and there counting is
// not available.

#include <cstddef>

namespace candela::test {

// Whether this build counts allocations.
bool allocations_counted();

class AllocationCount {
public:
    AllocationCount();   // starts counting from zero
    ~AllocationCount();  // stops counting
    AllocationCount(const AllocationCount&) = delete;
    AllocationCount& operator=(const AllocationCount&) = delete;
    size_t calls() const;
    size_t bytes() const;
};

}  // namespace candela::test
