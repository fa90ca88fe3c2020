// libFuzzer target for the mesh readers and writers: the input bytes are written to a temporary
// file and read as .mesh, as .meshb (binary MEDIT), as .msh, as the .sol beside a fixed valid .mesh, and as each TetGen file
// (.node, .ele, .face) beside fixed valid others, as a vertex map (.npy, .txt), and as a hierarchy (.tth); a .mesh or .msh that reads is streamed too
// (topotet/mesh_stream.h), which must refuse it or give the same counts. Every mesh that parses is written as .mesh,
// .msh 4.1 and .msh 2.2 and read back: the .mesh must give the same MeshData, and every file
// must read, and as .meshb, which must give the same MeshData; and as .vtu (ASCII and binary; write-only), which must be complete. It is also built into the model (which may refuse it). Every outcome but these or an
// InputError (a crash, a sanitizer report, another exception, a huge allocation) is a bug. Build with clang and -DTOPOTET_FUZZ=ON (see tests/CMakeLists.txt), then e.g.
//   ./fuzz_readers -max_total_time=60 -rss_limit_mb=2048 corpus/
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>

#include "topotet/error.h"
#include "topotet/hierarchy.h"
#include "topotet/io.h"
#include "topotet/mesh_stream.h"
#include "topotet/tet_mesh.h"
#include "topotet/vertex_map_file.h"

namespace {

// On tmpfs when there is one: rewriting the same file thousands of times a second on ext4
// waits on its flush-on-truncate heuristics and makes the fuzzer 30x slower.
const std::string& work_dir() {
  static const std::string dir = [] {
    char shm[] = "/dev/shm/topotet_fuzz_XXXXXX";
    char tmp[] = "/tmp/topotet_fuzz_XXXXXX";
    const char* made = mkdtemp(shm);
    if (made == nullptr) made = mkdtemp(tmp);
    if (made == nullptr) std::abort();
    std::ofstream(std::string(made) + "/sol.mesh") << "Dimension 3\nVertices\n4\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n"
                                                      "Tetrahedra\n1\n1 2 3 4 1\nEnd\n";
    // Valid TetGen files, each replaced in turn by the input.
    for (const char* stem : {"/n", "/e", "/f"}) {
      std::ofstream(std::string(made) + stem + ".node") << "5 3 0 1\n1 0 0 0 1\n2 1 0 0 1\n3 0 1 0 0\n4 0 0 1 1\n5 1 1 1 0\n";
      std::ofstream(std::string(made) + stem + ".ele") << "2 4 1\n1 1 2 3 4 7\n2 2 3 4 5 8\n";
      std::ofstream(std::string(made) + stem + ".face") << "1 1\n1 2 3 4 3\n";
      std::ofstream(std::string(made) + stem + ".edge") << "1 1\n1 1 2 5\n";
    }
    return std::string(made);
  }();
  return dir;
}

// Every writer's output reads back; the .mesh one exactly (MEDIT has no group names).
void write_and_read_back(const topotet::MeshData& mesh) {
  const std::string& dir = work_dir();
  for (const char* name : {"/out.mesh", "/out.meshb"}) {
    try {
      topotet::write_mesh(dir + name, mesh);
      topotet::MeshData back = topotet::read_mesh(dir + name);
      back.group_names = mesh.group_names;
      if (!(back == mesh)) std::abort();
    } catch (const topotet::InputError&) {
      // A field that .sol cannot hold (2, 4, 5... components) is refused: fine.
    }
  }
  for (const bool msh22 : {false, true}) {
    topotet::WriteOptions options;
    options.msh22 = msh22;
    try {
      topotet::write_mesh(dir + "/out.msh", mesh, options);
    } catch (const topotet::InputError&) {
      continue;  // a field of more than 9 components
    }
    const topotet::MeshData back = topotet::read_mesh(dir + "/out.msh");  // must not throw
    if (back.tet_count() != mesh.tet_count()) std::abort();
  }  // .vtu is write-only (ParaView reads it): ASCII and raw appended data, each complete.
  for (const bool binary : {false, true}) {
    topotet::WriteOptions options;
    options.binary = binary;
    try {
      topotet::write_mesh(dir + "/out.vtu", mesh, options);
    } catch (const topotet::InputError&) {
      continue;
    }
    std::ifstream in(dir + "/out.vtu", std::ios::binary);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (text.size() < 12 || text.find("</VTKFile>", text.size() - 12) == std::string::npos) std::abort();
  }
}

// The streaming reader (out of core) on a file read_mesh read: an InputError (a stream refuses
// more: MSH 2, fields in a .msh, sections out of the order it needs), or the entities read_mesh gave.
struct Counter : topotet::MeditVisitor {
  std::uint64_t vertices = 0, tets = 0, triangles = 0, segments = 0;
  void vertex(const std::array<double, 3>&, std::int32_t) override { ++vertices; }
  void tet(const std::array<topotet::VertId, 4>&, std::int32_t) override { ++tets; }
  void triangle(const topotet::Triangle&) override { ++triangles; }
  void segment(const topotet::Segment&) override { ++segments; }
  // A .msh's node views stream too (the out-of-core cut takes them).
  bool begin_node_view(const std::string&, int components) override { return components >= 1 && components <= 9; }
  void node_values(topotet::VertId v, const double*) override {
    if (v >= vertices) std::abort();
  }
  bool begin_cell_view(const std::string&, int components) override { return components >= 1 && components <= 9; }
  void cell_values(std::uint64_t t, const double*) override {
    if (t >= tets) std::abort();
  }
};

void stream_as(const std::string& path, const topotet::MeshData& read, bool tets_only) {
  Counter counter;
  try {
    topotet::ReadOptions options;
    options.tets_only = tets_only;
    topotet::ReadNotes notes;
    topotet::stream_mesh(path, counter, options, notes);
  } catch (const topotet::InputError&) {
    return;
  }
  if (counter.vertices != read.vertex_count() || counter.tets != read.tet_count() ||
      counter.triangles != read.triangles.size() || counter.segments != read.segments.size())
    std::abort();
}

void read_as(const std::string& path, const std::string& read_path, const std::uint8_t* data, std::size_t size) {
  {
    ::unlink(path.c_str());
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  topotet::MeshData mesh;
  try {
    topotet::ReadOptions options;
    options.tets_only = size % 2 == 0;  // both mixed-mesh policies
    mesh = topotet::read_mesh(read_path, options);
  } catch (const topotet::InputError&) {
    return;  // rejected with a message: the expected outcome for most inputs
  }
  if (path == read_path && (path.ends_with(".mesh") || path.ends_with(".meshb") || path.ends_with(".msh")))
    stream_as(read_path, mesh, size % 2 == 0);
  write_and_read_back(mesh);
  try {
    topotet::BuildOptions options;
    options.skip_detached_substructures = true;
    const topotet::TetMesh model = topotet::build_tet_mesh(mesh, options);
    if (model.to_mesh_data().tet_count() != mesh.tet_count()) std::abort();
  } catch (const topotet::InputError&) {
  }
}

// The vertex map reader (topotet/vertex_map_file.h): an InputError, or a map that writes back to
// the same bytes' meaning (read again: the same entries).
void read_vertex_map_as(const std::string& path, const std::uint8_t* data, std::size_t size) {
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  std::vector<std::int64_t> map;
  try {
    map = topotet::read_vertex_map(path);
  } catch (const topotet::InputError&) {
    return;
  }
  topotet::VertexMapWriter writer(path, map.size());
  for (std::int64_t o : map) writer.add(o);
  writer.commit();
  if (topotet::read_vertex_map(path) != map) std::abort();
}

// The hierarchy reader (.tth, io/tth.cpp): an InputError, or a valid hierarchy that writes back
// and reads again to the same records, and whose levels extract (or are refused with an InputError).
void read_hierarchy_as(const std::string& path, const std::uint8_t* data, std::size_t size) {
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  topotet::Hierarchy h;
  try {
    h = topotet::read_hierarchy(path);
  } catch (const topotet::InputError&) {
    return;
  }
  topotet::write_hierarchy(path + ".out", h);  // a hierarchy that read is valid: must write
  const topotet::Hierarchy back = topotet::read_hierarchy(path + ".out");
  if (!(back.original == h.original) || back.u != h.u || back.v != h.v || back.parents != h.parents) std::abort();
  try {
    for (std::size_t count : {std::size_t{0}, h.collapse_count() / 2, h.collapse_count()})
      topotet::extract(h, topotet::select_prefix(h, count));
  } catch (const topotet::InputError&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string& dir = work_dir();
  read_as(dir + "/input.mesh", dir + "/input.mesh", data, size);
  read_as(dir + "/input.msh", dir + "/input.msh", data, size);
  read_as(dir + "/input.meshb", dir + "/input.meshb", data, size);
  read_as(dir + "/sol.sol", dir + "/sol.mesh", data, size);
  read_as(dir + "/n.node", dir + "/n.node", data, size);
  read_as(dir + "/e.ele", dir + "/e.ele", data, size);
  read_as(dir + "/f.face", dir + "/f.face", data, size);
  read_vertex_map_as(dir + "/map.npy", data, size);
  read_vertex_map_as(dir + "/map.txt", data, size);
  read_hierarchy_as(dir + "/h.tth", data, size);
  return 0;
}
