// The collapse hierarchy's costs (issue #16): recording overhead versus a plain simplification,
// bytes per collapse, extraction throughput and the VOI sweep. One JSON line per measurement.
//
//   bench_hierarchy --generate cube-sphere --tets 1000000 [--ratio 0.1] [--threads 1] [--runs 5]
//   bench_hierarchy --input lox_post_tets.mesh.gz ...
// Times are process CPU seconds (see Clock), medians of `runs`.
//
// build:     plain simplify() and simplify_with_hierarchy() alternate, `runs` each, on fresh copies
//            of the same built mesh; medians and their ratio (A/B in one process, so machine load
//            hits both alike).
// extract:   uniform levels with a quarter, half, three quarters and all of the collapses applied;
//            median seconds and output tets per second (1 thread: extraction is sequential).
// voi_sweep: a sphere of radius 1/8 of the bounding box diagonal, fine inside (error 0) and coarse
//            outside (each VoiClosure), moved 10 times by a tenth of its diameter along x; per move, the time of the
//            new selection and the undo/apply of the difference (HierarchyCursor::move_to) and
//            separately the time to emit the mesh (HierarchyCursor::mesh), medians.
#include <algorithm>
#include <cmath>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include <glm/common.hpp>

#include "mesh/glm_convert.h"
#include "topotet/generate.h"
#include "topotet/hierarchy.h"
#include "topotet/io.h"
#include "topotet/simplify.h"
#include "topotet/threads.h"

namespace {

using namespace topotet;
// Process CPU time, not wall time: the machine these numbers come from is shared, and with one
// thread (the default here) CPU time is what the work costs, whatever the load.
struct Clock {
  static double now() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
  }
};

double since(double t) { return Clock::now() - t; }

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : (v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]));
}

struct Args {
  std::string input, family = "cube-sphere";
  std::uint64_t tets = 1000000;
  double ratio = 0.1;
  int threads = 1, runs = 5;
};

Args parse(int argc, char** argv) {
  Args a;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i], v = argv[i + 1];
    if (k == "--input") a.input = v;
    else if (k == "--generate") a.family = v;
    else if (k == "--tets") a.tets = std::strtoull(v.c_str(), nullptr, 10);
    else if (k == "--ratio") a.ratio = std::strtod(v.c_str(), nullptr);
    else if (k == "--threads") a.threads = std::atoi(v.c_str());
    else if (k == "--runs") a.runs = std::atoi(v.c_str());
    else {
      std::fprintf(stderr, "bench_hierarchy: unknown option %s\n", k.c_str());
      std::exit(2);
    }
  }
  return a;
}

}  // namespace

int main(int argc, char** argv) {
  const Args args = parse(argc, argv);
  MeshData data;
  std::string dataset;
  if (!args.input.empty()) {
    data = read_mesh(args.input);
    dataset = args.input;
  } else {
    GenerateOptions g;
    g.family = args.family;
    g.target_tets = args.tets;
    data = generate_mesh(g);
    dataset = args.family + "-" + std::to_string(args.tets);
  }
  run_with_thread_limit(args.threads, [&] {
    const TetMesh built = build_tet_mesh(data, BuildOptions{.skip_detached_substructures = true});
    SimplifyOptions options;
    options.target_vertex_ratio = args.ratio;
    options.num_threads = args.threads;
    std::vector<double> plain, recorded;
    Hierarchy h;
    for (int r = 0; r < args.runs; ++r) {
      TetMesh a = built;
      const auto t0 = Clock::now();
      const Report ra = simplify(a, options);
      plain.push_back(since(t0));
      TetMesh b = built;
      const auto t = Clock::now();
      const Report rb = simplify_with_hierarchy(b, options, h);
      recorded.push_back(since(t));
      if (ra.tets_after != rb.tets_after) std::fprintf(stderr, "bench_hierarchy: plain and recorded runs differ\n");
    }
    const double n = static_cast<double>(h.collapse_count());
    const std::string file = (std::filesystem::temp_directory_path() / "bench_hierarchy.tth").string();
    auto t_write = Clock::now();
    write_hierarchy(file, h);
    const double write_seconds = since(t_write);
    const auto file_bytes = std::filesystem::file_size(file);
    t_write = Clock::now();
    const Hierarchy reread = read_hierarchy(file);
    const double read_seconds = since(t_write);
    std::filesystem::remove(file);
    std::printf(
        "{\"bench\":\"build\",\"dataset\":\"%s\",\"threads\":%d,\"runs\":%d,\"tets_in\":%zu,\"collapses\":%zu,"
        "\"plain_seconds\":%.4f,\"recorded_seconds\":%.4f,\"overhead\":%.4f,\"record_bytes_per_collapse\":%.1f,"
        "\"parents_per_collapse\":%.2f,\"file_bytes\":%llu,\"write_seconds\":%.4f,\"read_seconds\":%.4f}\n",
        dataset.c_str(), args.threads, args.runs, built.tet_capacity(), h.collapse_count(), median(plain),
        median(recorded), median(recorded) / median(plain) - 1.0,
        static_cast<double>(hierarchy_collapse_bytes(h)) / n, static_cast<double>(h.parents.size()) / n,
        static_cast<unsigned long long>(file_bytes), write_seconds, read_seconds);
    if (reread.collapse_count() != h.collapse_count()) std::fprintf(stderr, "bench_hierarchy: file round trip differs\n");

    // Uniform extraction throughput, at a quarter, half, three quarters and all of the collapses.
    const double top = h.error.empty() ? 0.0 : h.error.back();
    for (double q : {0.25, 0.5, 0.75, 1.0}) {
      const std::vector<std::uint8_t> applied = select_prefix(h, static_cast<std::size_t>(q * n));
      std::vector<double> seconds;
      std::size_t tets_out = 0;
      for (int r = 0; r < std::max(3, args.runs); ++r) {
        const auto t = Clock::now();
        const MeshData level = extract(h, applied);
        seconds.push_back(since(t));
        tets_out = level.tet_count();
      }
      std::printf("{\"bench\":\"extract\",\"dataset\":\"%s\",\"collapse_fraction\":%g,\"tets_out\":%zu,\"seconds\":%.5f,"
                  "\"tets_per_second\":%.0f}\n",
                  dataset.c_str(), q, tets_out, median(seconds), static_cast<double>(tets_out) / median(seconds));
    }

    // VOI sweep, with each closure (topotet/hierarchy.h, select_voi).
    glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    for (const auto& p : h.original.positions) {
      lo = glm::min(lo, to_glm(p));
      hi = glm::max(hi, to_glm(p));
    }
    const glm::dvec3 d = hi - lo;
    for (VoiClosure closure : {VoiClosure::kKeepFine, VoiClosure::kReachCoarse}) {
      Voi voi;
      voi.kind = Voi::Kind::kSphere;
      voi.radius = std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z) / 8.0;
      voi.centre = from_glm(lo + 0.5 * d - glm::dvec3(5 * voi.size() / 10, 0, 0));
      HierarchyCursor cursor(h);
      cursor.move_to(select_voi(h, voi, 0.0, top, closure));
      std::vector<double> move_seconds, mesh_seconds;
      std::size_t changed_total = 0, tets_out = 0, applied_count = 0;
      for (int step = 0; step < 10; ++step) {
        voi = voi.moved({voi.size() / 10, 0, 0});
        auto t = Clock::now();
        changed_total += cursor.move_to(select_voi(h, voi, 0.0, top, closure));
        move_seconds.push_back(since(t));
        t = Clock::now();
        const MeshData level = cursor.mesh();
        mesh_seconds.push_back(since(t));
        tets_out = level.tet_count();
      }
      for (std::uint8_t a : cursor.applied()) applied_count += a;
      std::printf("{\"bench\":\"voi_sweep\",\"dataset\":\"%s\",\"closure\":\"%s\",\"radius\":%g,\"step\":%g,"
                  "\"moves\":10,\"applied\":%zu,\"changed_per_move\":%.0f,\"move_seconds\":%.5f,\"mesh_seconds\":%.5f,"
                  "\"tets_out\":%zu,\"tets_per_second\":%.0f}\n",
                  dataset.c_str(), closure == VoiClosure::kKeepFine ? "fine" : "coarse", voi.radius, voi.size() / 10,
                  applied_count, static_cast<double>(changed_total) / 10.0, median(move_seconds), median(mesh_seconds),
                  tets_out, static_cast<double>(tets_out) / median(mesh_seconds));
    }
  });
  return 0;
}
