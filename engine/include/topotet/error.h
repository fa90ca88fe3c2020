// Errors raised for bad input. Readers and the mesh builder throw InputError; its what() is one
// line that names the file (when there is one) and the line or element at fault, e.g.
//   "box.mesh:1234: Tetrahedra: vertex index 9001 out of range [1, 9000]"
//   "tet 17: zero volume (vertices 3 8 9 12 are coplanar)"
#pragma once

#include <stdexcept>
#include <string>

namespace topotet {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace topotet
