#include "materials/quadrature.h"

#include <cmath>

namespace candela {

void gauss_legendre(int n, std::vector<double>& nodes, std::vector<double>& weights) {
    nodes.assign(size_t(n), 0.0);
    weights.assign(size_t(n), 0.0);
    const double pi = 3.14159265358979323846;
    for (int i = 0; i < (n + 1) / 2; ++i) {
        // Tricomi's initial guess for the i-th root, then Newton on P_n.
        double x = std::cos(pi * (i + 0.75) / (n + 0.5)), dp = 1.0;
        for (int iter = 0; iter < 100; ++iter) {
            double p0 = 1.0, p1 = x;
            for (int k = 2; k <= n; ++k) {
                double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
                p0 = p1;
                p1 = p2;
            }
            double pn = n == 0 ? 1.0 : p1, pn1 = p0;
            dp = n * (x * pn - pn1) / (x * x - 1.0);
            double dx = pn / dp;
            x -= dx;
            if (std::abs(dx) < 1e-16) break;
        }
        nodes[size_t(i)] = -x;
        nodes[size_t(n - 1 - i)] = x;
        double w = 2.0 / ((1.0 - x * x) * dp * dp);
        weights[size_t(i)] = weights[size_t(n - 1 - i)] = w;
    }
}

}  // namespace candela
