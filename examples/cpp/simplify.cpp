// Simplifies a mesh through the installed C++ library: a generated cube with a ball inside (or the
// file given), keeping the topology of the mesh, of its materials and of its surfaces and polylines.
// Usage: simplify_cpp [IN [OUT]]
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <topotet/generate.h>
#include <topotet/nothrow.h>
#include <topotet/simplify.h>

int main(int argc, char** argv) {
  topotet::MeshData input;
  std::string message;
  if (argc > 1 && topotet::try_read_mesh(argv[1], input, message) != topotet::Status::kOk) {
    std::fprintf(stderr, "%s\n", message.c_str());
    return 1;
  }
  if (argc <= 1) input = topotet::generate_mesh({.family = "cube-sphere", .target_tets = 5000});
  topotet::TetMesh mesh;
  if (topotet::try_build_tet_mesh(input, mesh, message) != topotet::Status::kOk) {
    std::fprintf(stderr, "%s\n", message.c_str());
    return 1;
  }

  topotet::SimplifyOptions options;
  options.target_vertex_ratio = 0.2;
  options.tolerance_rel = 0.01;  // surfaces stay within 1% of the bounding box diagonal
  std::vector<topotet::VertId> vertex_map;  // input vertex -> the output vertex it merged into
  const topotet::Report report = topotet::simplify(mesh, options, vertex_map);
  if (report.status != topotet::Status::kOk && report.status != topotet::Status::kStoppedEarly) {
    std::fprintf(stderr, "%s\n", report.message.c_str());
    return 1;
  }
  double largest_move = 0.0;  // how far an input vertex went (positions are std::array<double, 3>)
  for (std::size_t v = 0; v < vertex_map.size(); ++v) {
    if (vertex_map[v] == topotet::kInvalid) continue;  // a vertex no tet uses
    const std::array<double, 3> to = mesh.position(vertex_map[v]), from = input.positions[v];
    largest_move = std::max(largest_move, std::hypot(to[0] - from[0], to[1] - from[1], to[2] - from[2]));
  }
  const topotet::MeshData output = mesh.to_mesh_data();
  std::printf("%s: %zu -> %zu vertices, %zu -> %zu tets; %llu collapses refused to keep a substructure's topology;"
              " largest vertex move %.3g\n",
              topotet::to_string(report.status), input.vertex_count(), output.vertex_count(), input.tet_count(),
              output.tet_count(), static_cast<unsigned long long>(report.rejected_by(topotet::RejectReason::kLinkKtilde)),
              largest_move);
  if (argc > 2 && topotet::try_write_mesh(argv[2], output, message) != topotet::Status::kOk) {
    std::fprintf(stderr, "%s\n", message.c_str());
    return 1;
  }
  return 0;
}
