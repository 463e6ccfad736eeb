#pragma once
// Evaluates arithmetic expressions such as "1 / (1 - 0.5)" or "2 * pi * 0.7^2": numbers, + - * /,
// ^ (power, right-associative), unary minus, parentheses, the constant pi and the functions
// sqrt, exp, log, sin, cos. Analytic scenes state their exact answers this way.

#include <string>

namespace candela {

// Throws InputError naming the position of the first problem.
double evaluate_expression(const std::string& text);

}  // namespace candela
