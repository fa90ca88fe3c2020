// generate_mesh: dispatch to the family generators (one file each, on freudenthal_grid.h).
#include "topotet/generate.h"

#include <stdexcept>

#include "generate/freudenthal_grid.h"
#include "topotet/error.h"

namespace topotet {

const std::vector<std::string>& generator_families() {
  static const std::vector<std::string> families = {"cube-sphere", "slab", "linked-tori", "polycrystal"};
  return families;
}

MeshData generate_mesh(const GenerateOptions& options) {
  if (options.family == "polycrystal") return gen::generate_polycrystal(options.target_tets, options.seed, options.cells);
  MeshData (*generate)(std::uint64_t, std::uint64_t) = nullptr;
  if (options.family == "cube-sphere") generate = gen::generate_cube_sphere;
  if (options.family == "slab") generate = gen::generate_slab;
  if (options.family == "linked-tori") generate = gen::generate_linked_tori;
  if (generate == nullptr) {
    std::string list;
    for (const std::string& name : generator_families()) list += (list.empty() ? "" : ", ") + name;
    throw InputError("unknown mesh family '" + options.family + "' (families: " + list + ")");
  }
  // Only polycrystal has cells: refuse the option rather than ignore it.
  if (options.cells != 0) throw InputError(options.family + ": --cells applies to polycrystal only");
  return generate(options.target_tets, options.seed);
}

bool can_stream(const GenerateOptions& options) { return options.family == "cube-sphere"; }

void generate_streamed(const GenerateOptions& options, GenerateSink& sink) {
  if (!can_stream(options)) throw std::logic_error(options.family + ": this family does not stream");
  if (options.cells != 0) throw InputError(options.family + ": --cells applies to polycrystal only");
  gen::stream_cube_sphere(options.target_tets, options.seed, sink);
}

}  // namespace topotet
