// libFuzzer target for the mesh readers: the input bytes are written to a temporary file and
// read as .mesh, as .msh, and as the .sol beside a fixed valid .mesh. Every outcome but a parsed
// mesh or an InputError (a crash, a sanitizer report, another exception, a huge allocation) is
// a bug. Build with clang and -DTOPOTET_FUZZ=ON (see tests/CMakeLists.txt), then e.g.
//   ./fuzz_readers -max_total_time=60 -rss_limit_mb=2048 corpus/
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <string>

#include "topotet/error.h"
#include "topotet/io.h"

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
    return std::string(made);
  }();
  return dir;
}

void read_as(const std::string& path, const std::string& read_path, const std::uint8_t* data, std::size_t size) {
  {
    ::unlink(path.c_str());
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    const topotet::MeshData mesh = topotet::read_mesh(read_path);
    (void)mesh;
  } catch (const topotet::InputError&) {
    // Rejected with a message: the expected outcome for most inputs.
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string& dir = work_dir();
  read_as(dir + "/input.mesh", dir + "/input.mesh", data, size);
  read_as(dir + "/input.msh", dir + "/input.msh", data, size);
  read_as(dir + "/sol.sol", dir + "/sol.mesh", data, size);
  return 0;
}
