// Whole simplification runs: datasets x engines x thread counts, repeated; one JSON line per run,
// then a table of medians with speed-up and efficiency, and a work/span projection of the
// parallel rounds to thread counts this machine does not have.
//
//   build/bench/bench_simplify --dataset cube-sphere --tets 200000,1000000 --ratio 0.1
//       --threads 1,2 --repeat 3 --json bench/results.jsonl   (one command line)
//   build/bench/bench_simplify --dataset ../shared/data/large/liver_1.31M.mesh.gz --threads 1,2
//
// A dataset is a generator family (--tets sets its size) or a mesh file (read in each child; the
// reading is not timed).
// Besides speed, every run measures what it produced: the RMS field error (both directions pooled,
// relative to the field's range; the mean over components) and the standard deviation of the
// dihedral angles, so the parallel engine's quality is printed next to the sequential reference's.
//
// Each run happens in a forked child process, so peak memory (VmHWM) is per run and one run's
// allocations never warm up the next. The parent never starts TBB (fork-safe).
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "topotet/generate.h"
#include "topotet/io.h"
#include "topotet/metrics/field_error.h"
#include "topotet/metrics/quality.h"
#include "topotet/round_log.h"
#include "topotet/simplify.h"
#include "topotet/tet_mesh.h"

namespace {

using namespace topotet;

struct Args {
  std::vector<std::string> datasets = {"cube-sphere"};
  std::vector<std::uint64_t> tets = {200000};
  double ratio = 0.1;
  double round_fraction = SimplifyOptions{}.round_fraction;
  // The geometric defaults (sharp features, tolerance); the throughput table of docs/performance.md sets
  // both off (180, 0) to time the engine alone, as it was measured.
  double feature_angle = SimplifyOptions{}.feature_angle;
  double tolerance_rel = SimplifyOptions{}.tolerance_rel;
  bool quality = true;  // measure error and angles of each result (not timed)
  std::vector<int> threads = {1, 2};
  bool sequential = true;
  int repeat = 3;
  std::string json;
  std::vector<int> project = {4, 8, 16, 32, 64};
};

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, ',');) out.push_back(item);
  return out;
}

long peak_rss_bytes() {
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);)
    if (line.rfind("VmHWM:", 0) == 0) return std::atol(line.c_str() + 6) * 1024;
  return 0;
}

struct Run {
  std::string dataset, engine;
  int threads = 0;
  std::uint64_t tets_in = 0, tets_out = 0, vertices_in = 0, vertices_out = 0, collapses = 0, evaluations = 0,
                rounds = 0;
  double seconds = 0, phase[4] = {0, 0, 0, 0}, mean_set = 0;
  long peak_rss = 0;
  std::string status;
  // Projection (parallel engine, measured at this thread count): projected seconds at P threads.
  std::vector<double> projected;
};

// T_P = sum over rounds of  max(t_eval/P, one proposal) + t_serial + (t_select - t_serial)/P
//                          + max(t_apply/P, one collapse).
// t_serial is the measured sequential code of the round (RoundStats::serial_seconds); the select
// phase's parallel loops (stencils, reservation passes: thousands of independent items) are taken
// as perfectly divisible, their barriers as free: the projection is an upper bound on speed-up that
// ignores memory bandwidth and synchronisation, meant to show where the rounds' Amdahl terms are.
// Outside the rounds: the setup (quadrics and orders, a parallel loop) counts as divisible, the
// final compaction (sequential code) as it is.
double project(const Report& r, const std::vector<RoundStats>& rounds, int threads_measured, int p) {
  const double setup = r.seconds - (r.phase_seconds[0] + r.phase_seconds[1] + r.phase_seconds[2] + r.phase_seconds[3]);
  double t = std::max(0.0, setup) * threads_measured / p + r.phase_seconds[3];
  for (const RoundStats& s : rounds) {
    const double eval_work = s.phase_seconds[0] * threads_measured, apply_work = s.phase_seconds[2] * threads_measured;
    const double eval_span = s.evaluated ? eval_work / static_cast<double>(s.evaluated) : 0;
    const double apply_span = s.winners ? apply_work / static_cast<double>(s.winners) : 0;
    const double select_work = std::max(0.0, s.phase_seconds[1] - s.serial_seconds) * threads_measured;
    t += std::max(eval_work / p, eval_span) + s.serial_seconds + select_work / p + std::max(apply_work / p, apply_span);
  }
  return t;
}

double serial_seconds(const std::vector<RoundStats>& rounds) {
  double t = 0;
  for (const RoundStats& s : rounds) t += s.serial_seconds;
  return t;
}

std::string run_child(const Args& a, const std::string& dataset, std::uint64_t tets, const std::string& engine,
                      int threads) {
  // A dataset is a generator family, or a mesh file (any name with a '.' or a '/').
  const bool from_file = dataset.find_first_of("./") != std::string::npos;
  GenerateOptions g;
  g.family = dataset;
  g.target_tets = tets;
  const auto input = [&] { return from_file ? read_mesh(dataset) : generate_mesh(g); };
  TetMesh mesh = build_tet_mesh(input());
  SimplifyOptions o;
  o.target_vertex_ratio = a.ratio;
  o.round_fraction = a.round_fraction;
  o.feature_angle = a.feature_angle;
  o.tolerance_rel = a.tolerance_rel;
  o.engine = engine == "sequential" ? Engine::kSequential : Engine::kParallel;
  o.num_threads = threads;
  std::vector<RoundStats> rounds;
  o.round_log = &rounds;
  const Report r = simplify(mesh, o);
  const long peak = peak_rss_bytes();  // before the quality measurement below allocates
  double rms_rel = 0, dihedral_sd = 0;
  if (a.quality) {
    const MeshData output = mesh.to_mesh_data();
    // Generated again (deterministic, fast) rather than kept: it would count in the peak above.
    const FieldError error = compare_fields(input(), output);
    for (const ComponentError& c : error.components) rms_rel += c.rms_both_rel / static_cast<double>(error.components.size());
    dihedral_sd = compute_quality(output).dihedral_deg.std_dev;
  }
  std::ostringstream js;
  double set = 0, competing = 0, evaluated = 0;
  for (const RoundStats& s : rounds) {
    set += static_cast<double>(s.winners);
    competing += static_cast<double>(s.candidates);
    evaluated += static_cast<double>(s.evaluated);
  }
  js << "{\"dataset\":\"" << dataset << "\",\"tets\":" << tets << ",\"engine\":\"" << engine << "\",\"threads\":" << threads
     << ",\"tets_in\":" << r.tets_before << ",\"tets_out\":" << r.tets_after << ",\"vertices_in\":" << r.vertices_before
     << ",\"vertices_out\":" << r.vertices_after << ",\"collapses\":" << r.collapses << ",\"evaluations\":" << r.evaluations << ",\"legality_checks\":" << r.legality_checks
     << ",\"seconds\":" << r.seconds << ",\"collapses_per_second\":" << r.collapses / std::max(r.seconds, 1e-9)
     << ",\"rounds\":" << r.rounds << ",\"mean_independent_set\":" << (r.rounds ? set / r.rounds : 0)
     << ",\"mean_candidates\":" << (r.rounds ? competing / r.rounds : 0)
     << ",\"mean_reevaluated\":" << (r.rounds ? evaluated / r.rounds : 0)
     << ",\"evaluations_per_collapse\":" << static_cast<double>(r.evaluations) / std::max<double>(1, r.collapses)
     << ",\"checks_per_collapse\":" << static_cast<double>(r.legality_checks) / std::max<double>(1, r.collapses)
     << ",\"phase_seconds\":{\"evaluate\":" << r.phase_seconds[0] << ",\"select\":" << r.phase_seconds[1]
     << ",\"apply\":" << r.phase_seconds[2] << ",\"compact\":" << r.phase_seconds[3] << "}"
     << ",\"serial_seconds\":" << serial_seconds(rounds) << ",\"round_fraction\":" << a.round_fraction
     << ",\"rms_rel\":" << rms_rel << ",\"dihedral_sd\":" << dihedral_sd
     << ",\"peak_rss_bytes\":" << peak
     << ",\"peak_bytes_per_tet\":" << static_cast<double>(peak) / std::max<double>(r.tets_before, 1)
     << ",\"status\":\"" << to_string(r.status) << "\",\"projected_seconds\":{";
  for (std::size_t i = 0; i < a.project.size(); ++i)
    js << (i ? "," : "") << "\"" << a.project[i] << "\":" << (engine == "parallel" ? project(r, rounds, threads, a.project[i]) : 0.0);
  js << "}}";
  return js.str();
}

double field(const std::string& json, const std::string& key) {
  const auto pos = json.find("\"" + key + "\":");
  return pos == std::string::npos ? 0.0 : std::atof(json.c_str() + pos + key.size() + 3);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    const std::string k = argv[i];
    const char* val = i + 1 < argc ? argv[i + 1] : "";
    if (k == "--dataset") a.datasets = split(val), ++i;
    else if (k == "--tets") { a.tets.clear(); for (auto& t : split(val)) a.tets.push_back(std::strtoull(t.c_str(), nullptr, 10)); ++i; }
    else if (k == "--round-fraction") a.round_fraction = std::atof(val), ++i;
    else if (k == "--feature-angle") a.feature_angle = std::atof(val), ++i;
    else if (k == "--tolerance-rel") a.tolerance_rel = std::atof(val), ++i;
    else if (k == "--no-quality") a.quality = false;
    else if (k == "--ratio") a.ratio = std::atof(val), ++i;
    else if (k == "--threads") { a.threads.clear(); for (auto& t : split(val)) a.threads.push_back(std::atoi(t.c_str())); ++i; }
    else if (k == "--repeat") a.repeat = std::atoi(val), ++i;
    else if (k == "--json") a.json = val, ++i;
    else if (k == "--no-sequential") a.sequential = false;
    else {
      std::fprintf(stderr, "usage: bench_simplify [--dataset a,b] [--tets N,M] [--ratio R] [--threads 1,2] [--repeat K] "
                           "[--round-fraction F] [--feature-angle A] [--tolerance-rel H] [--json FILE] [--no-sequential] [--no-quality]\n");
      return 2;
    }
  }
  std::FILE* out = a.json.empty() ? nullptr : std::fopen(a.json.c_str(), "a");
  for (const std::string& dataset : a.datasets)
  for (const std::uint64_t tets : a.tets) {
    std::vector<std::pair<std::string, int>> configs;
    if (a.sequential) configs.push_back({"sequential", 1});
    for (int t : a.threads) configs.push_back({"parallel", t});
    std::vector<std::vector<std::string>> results(configs.size());
    // Interleave repetitions across configurations: slow drifts of a noisy machine hit all alike.
    for (int rep = 0; rep < a.repeat; ++rep)
      for (std::size_t c = 0; c < configs.size(); ++c) {
        int fds[2];
        if (pipe(fds) != 0) return 1;
        const pid_t pid = fork();
        if (pid == 0) {
          close(fds[0]);
          const std::string line = run_child(a, dataset, tets, configs[c].first, configs[c].second);
          if (write(fds[1], line.data(), line.size()) < 0) _exit(1);
          _exit(0);
        }
        close(fds[1]);
        std::string line;
        char buf[4096];
        for (ssize_t n; (n = read(fds[0], buf, sizeof buf)) > 0;) line.append(buf, static_cast<std::size_t>(n));
        close(fds[0]);
        int wstatus = 0;
        waitpid(pid, &wstatus, 0);
        std::printf("%s\n", line.c_str());
        if (out) std::fprintf(out, "%s\n", line.c_str());
        results[c].push_back(line);
      }
    // Medians and ratios.
    auto med = [&](std::size_t c, const char* key) {
      std::vector<double> v;
      for (const auto& l : results[c]) v.push_back(field(l, key));
      return median(v);
    };
    const std::size_t seq = a.sequential ? 0 : configs.size();
    std::size_t one = configs.size();
    for (std::size_t c = 0; c < configs.size(); ++c)
      if (configs[c].first == "parallel" && configs[c].second == 1) one = c;
    // A file's size is its own, not --tets: print what the runs read.
    const double tets_read = results.empty() || results[0].empty() ? static_cast<double>(tets) : field(results[0][0], "tets_in");
    std::printf("\n%s, %.0f tets -> %.0f%% vertices, median of %d runs\n", dataset.c_str(), tets_read, a.ratio * 100,
                a.repeat);
    std::printf("%-11s %7s %9s %12s %9s %9s %10s %8s %10s %9s %10s %9s\n", "engine", "threads", "seconds", "collapses/s",
                "speedup", "effic.", "vs_seq", "rounds", "bytes/tet", "serial_s", "rms_rel", "dih_sd");
    for (std::size_t c = 0; c < configs.size(); ++c) {
      const double s = med(c, "seconds");
      const double s1 = one < configs.size() ? med(one, "seconds") : s;
      const double sq = seq < configs.size() ? med(seq, "seconds") : s;
      std::printf("%-11s %7d %9.3f %12.0f %9.2f %9.2f %10.2f %8.0f %10.0f %9.3f %10.3g %9.3f\n", configs[c].first.c_str(),
                  configs[c].second, s, med(c, "collapses_per_second"), s1 / s, s1 / s / configs[c].second, sq / s,
                  med(c, "rounds"), med(c, "peak_bytes_per_tet"), med(c, "serial_seconds"), med(c, "rms_rel"),
                  med(c, "dihedral_sd"));
    }
    if (one < configs.size()) {
      std::size_t two = configs.size();
      for (std::size_t c = 0; c < configs.size(); ++c)
        if (configs[c].first == "parallel" && configs[c].second == 2) two = c;
      // The select phase's loops are short and atomic-heavy and do not scale like the others.
      // With a 2-thread run, fit Amdahl's law to the phase (S1 = s + p, S2 = s + p/2, so
      // s = 2 S2 - S1) and project its non-scaling part s as sequential.
      const double s1 = med(one, "select"), serial = med(one, "serial_seconds");
      const double s_fit = two < configs.size() ? std::clamp(2 * med(two, "select") - s1, serial, s1) : serial;
      std::printf("projection from the 1-thread rounds (work/span; A: measured serial code counted sequential");
      if (two < configs.size())
        std::printf(", B: also the select phase's non-scaling part fitted from 2 threads, %.3f of %.3f s", s_fit, s1);
      std::printf("):\n");
      const double t1 = med(one, "seconds");
      for (int p : a.project) {
        std::vector<double> v;
        for (const auto& l : results[one]) {
          const auto pos = l.find("\"projected_seconds\":");
          v.push_back(field(l.substr(pos), std::to_string(p)));
        }
        const double tp = median(v);
        std::printf("  %3d threads: A %.3f s, speed-up %.2f, efficiency %.2f", p, tp, t1 / tp, t1 / tp / p);
        if (two < configs.size()) {
          const double tb = tp - (serial + (s1 - serial) / p) + (s_fit + (s1 - s_fit) / p);
          std::printf("   B %.3f s, speed-up %.2f, efficiency %.2f", tb, t1 / tb, t1 / tb / p);
        }
        std::printf("\n");
      }
    }
  }
  if (out) std::fclose(out);
  return 0;
}
