// Robust sign of the tetrahedron orientation determinant, private to the topology checker.
//
// The checker must not trust the kernel's own predicate (it is the referee), so it carries its own:
// a floating-point evaluation guarded by Shewchuk's static error bound, and an exact evaluation
// with floating-point expansions when the bound cannot certify the sign.
#pragma once

#include <glm/vec3.hpp>

namespace topotet::metrics::detail {

// Exact sign of det[p1 - p0, p2 - p0, p3 - p0] (+1, -1 or 0), the convention of mesh_data.h.
// Non-finite coordinates (or products that overflow) give 0, so such a tet is reported as
// degenerate, never as valid. Like Shewchuk's predicates it assumes no underflow in intermediate
// products, which holds for coordinates between about 1e-70 and 1e70 in magnitude (or exactly 0).
int orient3d_sign(const glm::dvec3& p0, const glm::dvec3& p1, const glm::dvec3& p2,
                  const glm::dvec3& p3);

}  // namespace topotet::metrics::detail
