#include "quality.h"

#include <cmath>

#include <glm/geometric.hpp>

#include "orient.h"

namespace topotet {

double mean_ratio(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d) {
  const double vol = signed_volume6(a, b, c, d) / 6.0;
  const double sum_sq = glm::dot(b - a, b - a) + glm::dot(c - a, c - a) + glm::dot(d - a, d - a) +
                        glm::dot(c - b, c - b) + glm::dot(d - b, d - b) + glm::dot(d - c, d - c);
  if (!(sum_sq > 0.0)) return 0.0;
  const double q = 12.0 * std::cbrt(9.0 * vol * vol) / sum_sq;  // (3|V|)^(2/3) = cbrt(9 V^2)
  return vol < 0.0 ? -q : q;
}

}  // namespace topotet
