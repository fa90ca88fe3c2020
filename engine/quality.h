// Shape quality of a tetrahedron, used by the kernel's quality floor.
#pragma once

#include <glm/vec3.hpp>

namespace topotet {

// Mean ratio 12 (3|V|)^(2/3) / sum of squared edge lengths: 1 for the regular tet, -> 0 for
// slivers and needles; negative (the same magnitude, signed) for inverted tets.
double mean_ratio(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d);

}  // namespace topotet
