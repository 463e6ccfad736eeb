// libFuzzer target for the expression evaluator (analysis/expression.h), which reads the exact
// answers that analytic scenes state: any input either evaluates to a finite number or throws
// InputError. Anything else (another exception, a sanitizer report, a stack overflow, a
// non-finite result) is a crash for libFuzzer.

#include "analysis/expression.h"
#include "core/error.h"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    try {
        double v = candela::evaluate_expression(std::string(reinterpret_cast<const char*>(data), size));
        if (!std::isfinite(v)) {
            std::fprintf(stderr, "candela fuzz: the expression evaluated to a non-finite value\n");
            std::abort();
        }
    } catch (const candela::InputError&) {}
    return 0;
}
