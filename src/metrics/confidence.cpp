// Confidence intervals of the error measures (docs/measures.md#confidence): Clopper-Pearson for a
// rate, order statistics for a percentile, both from the regularized incomplete beta function.
#include <algorithm>
#include <cmath>

#include "heightmarch/metrics.hpp"

namespace heightmarch {
namespace {

constexpr double kLowerTail = 0.025, kUpperTail = 0.975;  // 95%
constexpr int kBisections = 200;  // halvings of a bracket: far below a double's resolution

// The continued fraction of I_x(a, b) (modified Lentz); it converges in about sqrt(max(a, b))
// terms, so a bound of a few thousand covers a hundred million rays.
double beta_fraction(double a, double b, double x) {
  constexpr double kTiny = 1e-300, kEpsilon = 1e-15;
  constexpr int kMaxTerms = 100000;
  double c = 1.0, d = 1.0 - (a + b) * x / (a + 1.0);
  if (std::fabs(d) < kTiny) d = kTiny;
  d = 1.0 / d;
  double h = d;
  for (int m = 1; m <= kMaxTerms; ++m) {
    const double m2 = 2.0 * m;
    double num = m * (b - m) * x / ((a + m2 - 1.0) * (a + m2));
    d = 1.0 + num * d;
    c = 1.0 + num / c;
    d = 1.0 / (std::fabs(d) < kTiny ? kTiny : d);
    c = std::fabs(c) < kTiny ? kTiny : c;
    h *= d * c;
    num = -(a + m) * (a + b + m) * x / ((a + m2) * (a + m2 + 1.0));
    d = 1.0 + num * d;
    c = 1.0 + num / c;
    d = 1.0 / (std::fabs(d) < kTiny ? kTiny : d);
    c = std::fabs(c) < kTiny ? kTiny : c;
    const double step = d * c;
    h *= step;
    if (std::fabs(step - 1.0) < kEpsilon) break;
  }
  return h;
}

// The x in [0, 1] where an increasing function of x reaches `target`, by bisection.
template <class F>
double solve_increasing(const F& f, double target, double lo, double hi) {
  for (int i = 0; i < kBisections && lo < hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    (f(mid) < target ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

double beta_quantile(double q, double a, double b) {
  return solve_increasing([&](double x) { return incomplete_beta(a, b, x); }, q, 0.0, 1.0);
}

}  // namespace

double incomplete_beta(double a, double b, double x) {
  if (x <= 0.0) return 0.0;
  if (x >= 1.0) return 1.0;
  const double front =
      std::exp(std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) + b * std::log1p(-x));
  if (x < (a + 1.0) / (a + b + 2.0)) return front * beta_fraction(a, b, x) / a;
  return 1.0 - front * beta_fraction(b, a, 1.0 - x) / b;
}

Interval clopper_pearson(double successes, double trials) {
  if (!(trials > 0)) return {0.0, 1.0};
  const double x = std::clamp(successes, 0.0, trials);
  return {x > 0 ? beta_quantile(kLowerTail, x, trials - x + 1.0) : 0.0,
          x < trials ? beta_quantile(kUpperTail, x + 1.0, trials - x) : 1.0};
}

Interval quantile_rank_interval(double p, double trials) {
  if (!(trials >= 1) || !(p > 0 && p < 1)) return {0.0, 1.0};
  // P(B <= k) for B ~ Binomial(trials, p), continuous in k through I_{1-p}(n - k, k + 1): the
  // p-quantile lies between the order statistics at its 2.5% and 97.5% points (and one above).
  const auto cdf = [&](double k) { return incomplete_beta(trials - k, k + 1.0, 1.0 - p); };
  const double top = trials * (1.0 - 1e-12);
  const double low = cdf(0.0) >= kLowerTail ? 0.0 : solve_increasing(cdf, kLowerTail, 0.0, top);
  const double high = cdf(top) <= kUpperTail ? trials : solve_increasing(cdf, kUpperTail, 0.0, top) + 1.0;
  return {std::clamp(low / trials, 0.0, 1.0), std::clamp(high / trials, 0.0, 1.0)};
}

}  // namespace heightmarch
