#include "physics/fem/prony.hpp"

#include <cmath>

namespace tactus::physics {

namespace {

Mat3 load_sym(std::span<const double> s) {
  Mat3 m;
  m << s[0], s[3], s[5], s[3], s[1], s[4], s[5], s[4], s[2];
  return m;
}

void store_sym(const Mat3& m, std::span<double> s) {
  s[0] = m(0, 0);
  s[1] = m(1, 1);
  s[2] = m(2, 2);
  s[3] = m(0, 1);
  s[4] = m(1, 2);
  s[5] = m(0, 2);
}

}  // namespace

Mat3 prony_reference(std::span<const double> q) { return load_sym(q.subspan(0, 6)); }

Mat3 prony_offset(const std::vector<PronyTerm>& terms, std::span<const double> q) {
  const Mat3 ref = load_sym(q.subspan(0, 6));
  Mat3 out = Mat3::Zero();
  for (std::size_t i = 0; i < terms.size(); ++i) out += load_sym(q.subspan(6 * (i + 1), 6)) - terms[i].weight * ref;
  return out;
}

void prony_update(const std::vector<PronyTerm>& terms, const Mat3& sbar, double dt, std::span<double> q) {
  const Mat3 jump = sbar - load_sym(q.subspan(0, 6));
  for (std::size_t i = 0; i < terms.size(); ++i) {
    const double x = dt / terms[i].tau;
    const double decay = std::exp(-x);
    const double gamma = x > 1e-8 ? -std::expm1(-x) / x : 1.0 - 0.5 * x;
    const auto h = q.subspan(6 * (i + 1), 6);
    store_sym(decay * load_sym(h) + (terms[i].weight * gamma) * jump, h);
  }
  store_sym(sbar, q.subspan(0, 6));
}

}  // namespace tactus::physics
