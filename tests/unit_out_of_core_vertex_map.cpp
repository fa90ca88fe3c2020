// The vertex map of an out-of-core run (OutOfCoreOptions::vertex_map_path): for every input vertex
// the output vertex it became or merged into, across pieces, merges and levels, whether the pieces
// end as one or the limit keeps them apart; the same for 1 and 2 threads, and asking for it changes
// nothing else.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <utility>
#include <vector>

#include "io_test_files.h"
#include "outofcore/cut.h"
#include "outofcore/memory_budget.h"
#include "topotet/generate.h"
#include "topotet/io.h"
#include "topotet/metrics/topology.h"
#include "topotet/out_of_core.h"
#include "topotet/vertex_map_file.h"

namespace topotet {
namespace {

// A generated mesh with one vertex no tet uses, at the end: it maps to -1.
MeshData input_with_an_unused_vertex(std::uint64_t tets) {
  GenerateOptions g;
  g.family = "cube-sphere";
  g.target_tets = tets;
  MeshData m = generate_mesh(g);
  m.positions.push_back({0.5, 0.5, 0.5});
  for (VertexField& f : m.fields) f.values.resize(m.positions.size() * static_cast<std::size_t>(f.components), 0.0);
  return m;
}

// Collapses only rename vertices (without the optimisation's flips): the output tets are exactly
// the input tets mapped through the map, less those whose images repeat a vertex. A wrong link in
// any chain of merges (a piece, then its merge with a neighbour, ...) shows up here.
void expect_map_renames_the_tets(const MeshData& input, const MeshData& output, const std::vector<std::int64_t>& map) {
  ASSERT_EQ(map.size(), input.vertex_count());
  std::vector<bool> used(input.vertex_count(), false);
  for (const auto& t : input.tets)
    for (VertId v : t) used[v] = true;
  std::vector<int> preimages(output.vertex_count(), 0);
  for (std::size_t i = 0; i < map.size(); ++i) {
    if (!used[i]) {
      EXPECT_EQ(map[i], -1) << "unused input vertex " << i;
      continue;
    }
    ASSERT_GE(map[i], 0) << "input vertex " << i;
    ASSERT_LT(map[i], static_cast<std::int64_t>(output.vertex_count())) << "input vertex " << i;
    ++preimages[static_cast<std::size_t>(map[i])];
  }
  for (std::size_t o = 0; o < preimages.size(); ++o) EXPECT_GE(preimages[o], 1) << "output vertex " << o;
  using Key = std::pair<std::array<std::int64_t, 4>, std::int32_t>;
  std::vector<Key> renamed, out;
  for (std::size_t t = 0; t < input.tet_count(); ++t) {
    std::array<std::int64_t, 4> v;
    for (int k = 0; k < 4; ++k) v[k] = map[input.tets[t][k]];
    std::sort(v.begin(), v.end());
    if (std::adjacent_find(v.begin(), v.end()) == v.end()) renamed.push_back({v, input.tet_material[t]});
  }
  for (std::size_t t = 0; t < output.tet_count(); ++t) {
    std::array<std::int64_t, 4> v;
    for (int k = 0; k < 4; ++k) v[k] = output.tets[t][k];
    std::sort(v.begin(), v.end());
    out.push_back({v, output.tet_material[t]});
  }
  std::sort(renamed.begin(), renamed.end());
  std::sort(out.begin(), out.end());
  EXPECT_EQ(renamed.size(), out.size());
  EXPECT_TRUE(renamed == out);
}

struct Mapped {
  OutOfCoreReport report;
  MeshData output;
  std::string bytes;
  std::vector<std::int64_t> map;
};

Mapped run(const std::string& in, const test::TempDir& folder, int threads, const std::string& map_name,
           std::uint64_t limit = 0, std::uint32_t pieces = 8, double ratio = 0.15) {
  SimplifyOptions options;
  options.target_vertex_ratio = ratio;
  options.num_threads = threads;
  options.optimize = Optimize::kNone;
  OutOfCoreOptions ooc;
  ooc.pieces = pieces;
  ooc.memory_limit_bytes = limit;
  ooc.vertex_map_path = map_name.empty() ? std::string() : folder.file(map_name);
  Mapped m;
  const std::string out = folder.file("out.mesh");
  m.report = simplify_out_of_core(in, out, options, ooc);
  m.output = read_mesh(out);
  m.bytes = test::read_text(out);
  if (!map_name.empty()) m.map = read_vertex_map(folder.file(map_name));
  return m;
}

TEST(OutOfCoreVertexMap, EveryInputVertexGoesToTheVertexItMergedIntoThroughEveryLevel) {
  const MeshData input = input_with_an_unused_vertex(20000);
  test::TempDir folder;
  const std::string in = folder.file("in.mesh");
  write_mesh(in, input);
  const Mapped two = run(in, folder, 2, "map.npy");
  EXPECT_EQ(two.report.output_pieces, 1u);
  EXPECT_GE(two.report.levels.size(), 4u);  // 8 pieces: level 0 and three merges
  expect_map_renames_the_tets(input, two.output, two.map);
  const Mapped one = run(in, folder, 1, "map.txt");
  EXPECT_EQ(one.map, two.map);
  EXPECT_EQ(one.bytes, two.bytes);
  EXPECT_EQ(run(in, folder, 2, "").bytes, two.bytes);  // the map changes nothing else
  for (const std::string& e : folder.entries()) {
    EXPECT_EQ(e.find(".topotet-scratch"), std::string::npos) << e;
    EXPECT_EQ(e.find(".tmp-"), std::string::npos) << e;
  }
}

// Two pieces and a limit that does not let them merge once simplified to 90% of their vertices:
// the output is written from the pieces (streaming), their common border kept; the map names its
// vertices too.
TEST(OutOfCoreVertexMap, PiecesKeptApartByTheLimitAreMappedToo) {
  const MeshData input = input_with_an_unused_vertex(50000);
  test::TempDir folder;
  const std::string in = folder.file("in.mesh");
  write_mesh(in, input);
  ooc::InputCounts counts;
  counts.vertex_stride = 1;  // the generated field
  // Room for a piece of 1.3 halves beside what the process holds.
  const auto limit = static_cast<std::uint64_t>(
      (static_cast<double>(ooc::budget_baseline(ooc::resident_bytes())) +
       0.65 * static_cast<double>(input.tet_count() * ooc::bytes_per_piece_tet(counts)) +
       2.0 * static_cast<double>(input.vertex_count())) /
      (1.0 - ooc::kHeadroom));
  const Mapped m = run(in, folder, 2, "map.npy", limit, 2, 0.9);
  ASSERT_GT(m.report.output_pieces, 1u);
  expect_map_renames_the_tets(input, m.output, m.map);
  std::string differences;
  EXPECT_TRUE(same_topology(compute_topology(input), compute_topology(m.output), &differences)) << differences;
}

TEST(OutOfCoreVertexMap, AnotherExtensionIsRefusedBeforeAnyWork) {
  const MeshData input = input_with_an_unused_vertex(4000);
  test::TempDir folder;
  const std::string in = folder.file("in.mesh");
  write_mesh(in, input);
  EXPECT_THROW(run(in, folder, 2, "map.csv"), InputError);
  EXPECT_FALSE(std::filesystem::exists(folder.file("out.mesh")));
}

}  // namespace
}  // namespace topotet
