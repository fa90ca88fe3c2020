// Between the public API's plain positions (std::array<double, 3>: MeshData, Hierarchy, Voi) and
// glm::dvec3, which the engine, the metrics and the tools compute with. Internal: no installed
// header includes glm, so that a program using topotet needs no glm of its own.
#pragma once

#include <array>

#include <glm/vec3.hpp>

namespace topotet {

inline glm::dvec3 to_glm(const std::array<double, 3>& p) { return {p[0], p[1], p[2]}; }
inline std::array<double, 3> from_glm(const glm::dvec3& p) { return {p.x, p.y, p.z}; }

}  // namespace topotet
