// Private helpers of the mannequin generator: monotone cubic interpolation (Fritsch & Carlson
// 1980), so ring parameters pass exactly through the imposed values without overshoot.
#pragma once
#include <algorithm>
#include <cmath>
#include <vector>

namespace caliper::mannequin::detail {

class MonotoneCurve {
 public:
  MonotoneCurve() = default;
  // Knots should have increasing x; a knot not strictly after the previous kept one is dropped
  // (clamped levels of unusual bodies can coincide).
  MonotoneCurve(const std::vector<double>& x, const std::vector<double>& y) {
    for (size_t i = 0; i < x.size(); ++i)
      if (x_.empty() || x[i] > x_.back() + 1e-9) { x_.push_back(x[i]); y_.push_back(y[i]); }
    const size_t n = x_.size();
    m_.assign(n, 0.0);
    if (n < 2) return;
    std::vector<double> d(n - 1);
    for (size_t i = 0; i + 1 < n; ++i) d[i] = (y_[i + 1] - y_[i]) / (x_[i + 1] - x_[i]);
    m_[0] = d[0];
    m_[n - 1] = d[n - 2];
    for (size_t i = 1; i + 1 < n; ++i) m_[i] = (d[i - 1] * d[i] <= 0) ? 0.0 : (d[i - 1] + d[i]) / 2;
    for (size_t i = 0; i + 1 < n; ++i) {
      if (d[i] == 0) { m_[i] = m_[i + 1] = 0; continue; }
      const double a = m_[i] / d[i], b = m_[i + 1] / d[i], s = a * a + b * b;
      if (s > 9) {
        const double t = 3 / std::sqrt(s);
        m_[i] = t * a * d[i];
        m_[i + 1] = t * b * d[i];
      }
    }
  }
  double operator()(double t) const {
    const size_t n = x_.size();
    if (n == 1) return y_[0];
    if (t <= x_.front()) return y_.front();
    if (t >= x_.back()) return y_.back();
    const size_t i = static_cast<size_t>(std::upper_bound(x_.begin(), x_.end(), t) - x_.begin()) - 1;
    const double h = x_[i + 1] - x_[i], u = (t - x_[i]) / h;
    const double u2 = u * u, u3 = u2 * u;
    return (2 * u3 - 3 * u2 + 1) * y_[i] + (u3 - 2 * u2 + u) * h * m_[i] + (-2 * u3 + 3 * u2) * y_[i + 1] +
           (u3 - u2) * h * m_[i + 1];
  }

 private:
  std::vector<double> x_, y_, m_;
};

// One quintic Hermite segment between two ends: the value, slope and second derivative given at
// both, so a profile made of it and its neighbours is continuous in curvature (a shaded
// surface shows a jump in curvature as a band; the monotone curve above is only C¹).
struct QuinticEnd {
  double x = 0, y = 0, slope = 0, second_derivative = 0;  // dy/dx and d²y/dx² at x
};
inline double quintic_hermite(const QuinticEnd& a, const QuinticEnd& b, double x) {
  const double h = b.x - a.x, t = std::clamp((x - a.x) / h, 0.0, 1.0);
  const double t2 = t * t, t3 = t2 * t, t4 = t3 * t, t5 = t4 * t;
  const double h0 = 1 - 10 * t3 + 15 * t4 - 6 * t5, h1 = t - 6 * t3 + 8 * t4 - 3 * t5;
  const double h2 = 0.5 * (t2 - 3 * t3 + 3 * t4 - t5), h3 = 0.5 * (t3 - 2 * t4 + t5);
  const double h4 = -4 * t3 + 7 * t4 - 3 * t5, h5 = 10 * t3 - 15 * t4 + 6 * t5;
  return h0 * a.y + h * h1 * a.slope + h * h * h2 * a.second_derivative + h * h * h3 * b.second_derivative + h * h4 * b.slope + h5 * b.y;
}

inline double smoothstep(double e0, double e1, double x) {
  const double t = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0);
  return t * t * (3 - 2 * t);
}

}  // namespace caliper::mannequin::detail
