// Embedding throughput of embed_isosurfaces (topotet/isosurface.h): input tets per second per
// thread, on a generated cube-sphere (its field f) or a mesh file (its first field), one level at
// the median of the field, best of `repeats` runs per thread count. One line per thread count.
//   build/bench/bench_isosurface [--tets N] [--mesh FILE] [--level V] [--repeats R] [--threads 1,2]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

#include "topotet/generate.h"
#include "topotet/io.h"
#include "topotet/isosurface.h"
#include "topotet/threads.h"

int main(int argc, char** argv) {
  std::uint64_t tets = 5'000'000;
  std::string mesh_path;
  double level = std::numeric_limits<double>::quiet_NaN();
  int repeats = 3;
  std::vector<int> threads = {1, 2};
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i], v = argv[i + 1];
    if (a == "--tets") tets = std::strtoull(v.c_str(), nullptr, 10);
    else if (a == "--mesh") mesh_path = v;
    else if (a == "--level") level = std::strtod(v.c_str(), nullptr);
    else if (a == "--repeats") repeats = std::atoi(v.c_str());
    else if (a == "--threads") {
      threads.clear();
      for (std::size_t p = 0; p < v.size();) {
        threads.push_back(std::atoi(v.c_str() + p));
        p = v.find(',', p);
        if (p == std::string::npos) break;
        ++p;
      }
    }
  }
  topotet::MeshData input;
  if (mesh_path.empty()) {
    topotet::GenerateOptions g;
    g.target_tets = tets;
    input = topotet::generate_mesh(g);
  } else {
    input = topotet::read_mesh(mesh_path);
  }
  if (input.fields.empty()) {
    std::fprintf(stderr, "the mesh has no field\n");
    return 2;
  }
  const topotet::VertexField& field = input.fields[0];
  if (level != level) {  // NaN: the median of the field's first component
    std::vector<double> values;
    for (std::size_t v = 0; v < input.positions.size(); ++v) values.push_back(field.values[v * field.components]);
    std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
    level = values[values.size() / 2];
  }
  std::printf("mesh %s: %zu tets, level %s=%.17g\n", mesh_path.empty() ? "cube-sphere" : mesh_path.c_str(),
              input.tets.size(), field.name.c_str(), level);
  for (int t : threads) {
    double best = 1e30;
    topotet::IsoEmbedReport report;
    for (int r = 0; r < repeats; ++r) {
      topotet::MeshData data = input;
      const auto start = std::chrono::steady_clock::now();
      topotet::run_with_thread_limit(t, [&] { report = topotet::embed_isosurfaces(data, {{field.name, 0, level}}); });
      best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    const topotet::IsoLevelStats& s = report.stats[0];
    std::printf("threads %d: %.3f s, %.2f M input tets/s (%.2f M/s per thread); %llu tets split, %llu vertices added, "
                "%llu triangles\n",
                t, best, input.tets.size() / best * 1e-6, input.tets.size() / best * 1e-6 / t,
                static_cast<unsigned long long>(s.tets_split), static_cast<unsigned long long>(s.vertices_added),
                static_cast<unsigned long long>(s.triangles));
  }
}
