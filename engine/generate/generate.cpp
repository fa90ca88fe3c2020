// generate_mesh: dispatch to the family generators (one file each, on freudenthal_grid.h).
#include "topotet/generate.h"

#include "generate/freudenthal_grid.h"
#include "topotet/error.h"

namespace topotet {

const std::vector<std::string>& generator_families() {
  static const std::vector<std::string> families = {"cube-sphere", "slab", "linked-tori"};
  return families;
}

MeshData generate_mesh(const GenerateOptions& options) {
  if (options.family == "cube-sphere") return gen::generate_cube_sphere(options.target_tets, options.seed);
  if (options.family == "slab") return gen::generate_slab(options.target_tets, options.seed);
  if (options.family == "linked-tori") return gen::generate_linked_tori(options.target_tets, options.seed);
  std::string list;
  for (const std::string& name : generator_families()) list += (list.empty() ? "" : ", ") + name;
  throw InputError("unknown mesh family '" + options.family + "' (families: " + list + ")");
}

}  // namespace topotet
