// libFuzzer target for the simplifier on valid meshes: the input bytes choose a small jittered
// Freudenthal grid (tests/test_meshes.h), its materials (holes included), listed patches on grid
// planes with random refs, polylines along grid lines, pinned vertices, the target ratio, the
// minimum quality, the engine and the thread count. The mesh is built, simplified, and the result
// must pass what `topotet check` checks: the same Betti numbers for the mesh and every
// substructure (topotet::compute_topology, the independent checker) and no inverted or flat tet.
// Anything else (a crash, a sanitizer report, an exception, a topology change, an inverted tet,
// a status other than ok) is a bug. Build with clang and -DTOPOTET_FUZZ=ON, then e.g.
//   ./fuzz_simplify -max_total_time=60 -rss_limit_mb=2048
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <algorithm>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

#include "test_meshes.h"
#include "topotet/metrics/quality.h"
#include "topotet/metrics/topology.h"
#include "topotet/simplify.h"
#include "topotet/tet_mesh.h"

namespace {

// Reads the fuzzer's bytes in order; zeros once they run out (a short input is a valid one).
class ByteSource {
 public:
  ByteSource(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  std::uint8_t next() { return at_ < size_ ? data_[at_++] : 0; }
  int in(int lo, int hi) { return lo + next() % (hi - lo + 1); }  // [lo, hi]
  bool empty() const { return at_ >= size_; }

 private:
  const std::uint8_t* data_;
  std::size_t size_, at_ = 0;
};

void fail(const char* what, const std::string& detail = {}) {
  std::fprintf(stderr, "fuzz_simplify: %s\n%s\n", what, detail.c_str());
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace topotet;
  ByteSource bytes(data, size);
  const int nx = bytes.in(2, 5), ny = bytes.in(2, 5), nz = bytes.in(1, 4);
  const int material_count = bytes.in(1, 4);
  const double jitter = 0.02 * bytes.in(0, 10);
  const std::uint64_t seed = bytes.next();
  // Materials per cube, from a bit budget: a few bytes paint boxes of cubes; 0 = a hole (only
  // when the mesh keeps at least one cube, checked below).
  std::vector<int> cube_material(static_cast<std::size_t>(nx * ny * nz), 1);
  for (int boxes = bytes.in(0, 4); boxes > 0; --boxes) {
    const int i0 = bytes.in(0, nx - 1), j0 = bytes.in(0, ny - 1), k0 = bytes.in(0, nz - 1);
    const int i1 = bytes.in(i0, nx - 1), j1 = bytes.in(j0, ny - 1), k1 = bytes.in(k0, nz - 1);
    const int m = bytes.in(0, material_count);
    for (int k = k0; k <= k1; ++k)
      for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i) cube_material[static_cast<std::size_t>(i + nx * (j + ny * k))] = m;
  }
  bool any = false;
  for (int m : cube_material) any = any || m > 0;
  if (!any) return 0;
  testing::Grid g = testing::make_grid(
      nx, ny, nz, [&](int i, int j, int k) { return cube_material[static_cast<std::size_t>(i + nx * (j + ny * k))] > 0 ? cube_material[static_cast<std::size_t>(i + nx * (j + ny * k))] : -1; },
      jitter, seed + 1);
  // Listed patches: squares of one grid plane, in a box of the plane, with a ref. A square with
  // no tet on either side is not a face of the mesh: leave those out (the builder would refuse).
  const int n[3] = {nx, ny, nz};
  auto has_cube = [&](int i, int j, int k) {
    return i >= 0 && j >= 0 && k >= 0 && i < nx && j < ny && k < nz && cube_material[static_cast<std::size_t>(i + nx * (j + ny * k))] > 0;
  };
  for (int patches = bytes.in(0, 3); patches > 0; --patches) {
    const int axis = bytes.in(0, 2), level = bytes.in(0, n[axis]);
    const int ax_a = axis == 0 ? 1 : 0, ax_b = axis == 2 ? 1 : 2;
    const int a0 = bytes.in(0, n[ax_a] - 1), a1 = bytes.in(a0, n[ax_a] - 1);
    const int b0 = bytes.in(0, n[ax_b] - 1), b1 = bytes.in(b0, n[ax_b] - 1);
    const std::int32_t ref = bytes.in(1, 5);
    testing::add_patch(
        g, axis, level,
        [&](int a, int b) {
          if (a < a0 || a > a1 || b < b0 || b > b1) return false;
          int c[3];
          c[axis] = level;
          c[ax_a] = a;
          c[ax_b] = b;
          int below[3] = {c[0], c[1], c[2]};
          --below[axis];
          return has_cube(c[0], c[1], c[2]) || has_cube(below[0], below[1], below[2]);
        },
        ref);
  }
  // Polylines along one grid line, a run of grid steps on which some cube touches the line.
  for (int lines = bytes.in(0, 2); lines > 0; --lines) {
    const int axis = bytes.in(0, 2);
    int c[3] = {bytes.in(0, nx), bytes.in(0, ny), bytes.in(0, nz)};
    const int from = bytes.in(0, n[axis] - 1), to = bytes.in(from + 1, n[axis]);
    std::vector<std::array<int, 3>> points;
    for (int s = from; s <= to; ++s) {
      c[axis] = s;
      points.push_back({c[0], c[1], c[2]});
    }
    // Every step must be an edge of a kept cube: a cube with the step's both ends as corners.
    bool on_mesh = true;
    for (std::size_t s = 0; s + 1 < points.size() && on_mesh; ++s) {
      bool touches = false;
      for (int dk = -1; dk <= 0; ++dk)
        for (int dj = -1; dj <= 0; ++dj)
          for (int di = -1; di <= 0; ++di) {
            int q[3] = {points[s][0] + di, points[s][1] + dj, points[s][2] + dk};
            q[axis] = points[s][axis];
            touches = touches || has_cube(q[0], q[1], q[2]);
          }
      on_mesh = touches;
    }
    if (on_mesh) testing::add_polyline(g, points, bytes.in(1, 3));
  }
  for (int pins = bytes.in(0, 3); pins > 0; --pins) {
    const VertId v = g.vid(bytes.in(0, nx), bytes.in(0, ny), bytes.in(0, nz));
    if (std::find(g.data.corners.begin(), g.data.corners.end(), v) == g.data.corners.end()) g.data.corners.push_back(v);
  }
  // Drop vertices no kept tet uses would be the reader's job; here only pin used ones.
  std::vector<bool> used(g.data.positions.size(), false);
  for (const auto& t : g.data.tets)
    for (VertId v : t) used[v] = true;
  std::erase_if(g.data.corners, [&](VertId v) { return !used[v]; });

  SimplifyOptions options;
  options.target_vertex_ratio = 0.05 * bytes.in(1, 19);
  options.min_quality = 0.01 * bytes.in(0, 20);
  options.size_weight = 1e-4 * (bytes.in(0, 10) - 1);  // -1e-4 = auto, 0 = error only, up to 9e-4
  options.engine = bytes.next() % 2 ? Engine::kSequential : Engine::kParallel;
  options.num_threads = bytes.in(1, 2);

  TetMesh mesh;
  try {
    mesh = build_tet_mesh(g.data);
  } catch (const std::exception&) {
    // The input is valid by construction except where unused vertices remain (holes); the
    // builder may refuse those with a clear message, which is fine.
    return 0;
  }
  const topotet::TopologyReport before = topotet::compute_topology(mesh.to_mesh_data());
  const Report report = simplify(mesh, options);
  // Stopping early is legitimate: the structure may allow no legal collapse before the target.
  if (report.status != Status::kOk && report.status != Status::kStoppedEarly)
    fail("simplify returned neither ok nor stopped early", report.message);
  const MeshData out = mesh.to_mesh_data();
  const topotet::TopologyReport after = topotet::compute_topology(out);
  std::string differences;
  if (!topotet::same_topology(before, after, &differences)) fail("topology changed", differences);
  const QualityStats quality = compute_quality(out);
  if (quality.inverted != 0 || quality.zero_volume != 0) fail("inverted or flat tets in the output");
  return 0;
}
