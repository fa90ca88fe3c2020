// Orientation of a tetrahedron with a certified sign.
//
// The determinant det[b-a, c-a, d-a] is evaluated in double together with Shewchuk's static
// error bound for orient3d (errboundA = (7 + 56 eps) eps times the permanent). When |det| is above
// the bound its sign is exact; otherwise we answer 0 ("not certainly positive"). Callers treat 0
// as degenerate, which is conservative: the builder rejects such a tet as near-zero volume and the
// kernel rejects a collapse that would create one. It never accepts an inverted tet.
#pragma once

#include <glm/vec3.hpp>

namespace topotet {

// +1 positively oriented, -1 inverted, 0 degenerate or too close to call.
int orient3d_sign(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d);

// Six times the signed volume, plain double (for quality and reporting, not for decisions).
double signed_volume6(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d);

}  // namespace topotet
