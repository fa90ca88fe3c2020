#include "raw_volume.h"

#include <cmath>
#include <fstream>
#include <iterator>
#include <vector>

#include "generate/freudenthal_grid.h"
#include "topotet/error.h"

namespace topotet::bench {

bool is_raw_volume(const std::string& path) {
  return path.size() >= 4 && path.compare(path.size() - 4, 4, ".raw") == 0;
}

MeshData read_raw_volume(const std::string& path, std::array<std::uint32_t, 3> dims, const std::string& field_name) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open");
  const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (dims[0] == 0) {
    const auto side = static_cast<std::uint32_t>(std::llround(std::cbrt(static_cast<double>(bytes.size()))));
    dims = {side, side, side};
  }
  if (std::uint64_t{dims[0]} * dims[1] * dims[2] != bytes.size())
    throw InputError(path + ": " + std::to_string(bytes.size()) + " bytes, not " + std::to_string(dims[0]) + "x" +
                     std::to_string(dims[1]) + "x" + std::to_string(dims[2]));
  if (dims[0] < 2 || dims[1] < 2 || dims[2] < 2) throw InputError(path + ": every side needs 2 samples or more");

  const gen::FreudenthalGrid grid({dims[0] - 1, dims[1] - 1, dims[2] - 1});
  MeshData mesh;
  mesh.positions.resize(grid.vertex_count());
  for (std::uint32_t k = 0; k < dims[2]; ++k)
    for (std::uint32_t j = 0; j < dims[1]; ++j)
      for (std::uint32_t i = 0; i < dims[0]; ++i) mesh.positions[grid.vertex(i, j, k)] = {double(i), double(j), double(k)};
  gen::build_tets(grid, [](const glm::dvec3&) { return 0; }, mesh);
  // The grid numbers vertices x fastest, as the file stores its samples.
  mesh.fields.push_back({field_name, 1, std::vector<double>(bytes.begin(), bytes.end())});
  return mesh;
}

}  // namespace topotet::bench
