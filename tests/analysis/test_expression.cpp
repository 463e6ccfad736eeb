// The expression evaluator that analytic scenes state their answers in: values, precedence, and
// bad input as InputError (never a crash): also input nested deeper than the stack could take.

#include "analysis/expression.h"
#include "core/error.h"

#include <catch2/catch.hpp>

#include <string>
#include <vector>

using namespace candela;

TEST_CASE("expression: numbers, precedence, right-associative power, functions", "[expression]") {
    CHECK(evaluate_expression("1 / (1 - 0.5)") == 2.0);
    CHECK(evaluate_expression("2 ^ 3 ^ 2") == 512.0);
    CHECK(evaluate_expression("-2 ^ 2") == -4.0);
    CHECK(evaluate_expression("1 + 2 * 3") == 7.0);
    CHECK(evaluate_expression("2 * pi * 0.7^2") == Approx(2 * 3.14159265358979323846 * 0.49));
    CHECK(evaluate_expression("sqrt(16) + exp(0) + log(1) + sin(0) + cos(0)") == 6.0);
    CHECK(evaluate_expression(std::string(150, '(') + "1" + std::string(150, ')')) == 1.0);
}

TEST_CASE("expression: bad input is an InputError naming the position", "[expression][errors]") {
    for (const std::string& text :
         std::vector<std::string>{"", "1 +", "(1", "foo", "bar(1)", "1 2", "1 / 0", "log(-1)", "sqrt(-1)", "nan", "1e999"}) {
        INFO(text);
        CHECK_THROWS_AS(evaluate_expression(text), InputError);
    }
    // Nesting beyond the limit (each level a stack frame or more): an error, not a stack
    // overflow. 100000 of each, as a fuzzer would write them.
    for (const std::string& text : std::vector<std::string>{std::string(100000, '('), std::string(100000, '-') + "1", [] {
                                                                std::string s;
                                                                for (int i = 0; i < 50000; ++i) s += "2^";
                                                                return s + "1";
                                                            }()}) {
        CHECK_THROWS_WITH(evaluate_expression(text), Catch::Contains("nested too deeply"));
    }
}
