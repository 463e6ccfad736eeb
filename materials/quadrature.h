#pragma once
// Gauss-Legendre quadrature nodes and weights on [-1, 1] (Golub & Welsch would also do; here
// Newton's method on the Legendre recurrence, exact to double precision).

#include <vector>

namespace candela {

void gauss_legendre(int n, std::vector<double>& nodes, std::vector<double>& weights);

}  // namespace candela
