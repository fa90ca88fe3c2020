// A raw byte volume as a MEDIT mesh with its field (raw_volume.h), for the command-line benches
// (bench/table_7_1.sh): raw_to_mesh IN.raw OUT.mesh [FIELD_NAME]
#include <cstdio>
#include <exception>
#include <string>

#include "raw_volume.h"
#include "topotet/io.h"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: raw_to_mesh IN.raw OUT.mesh [FIELD_NAME]\n");
    return 2;
  }
  try {
    const topotet::MeshData d = topotet::bench::read_raw_volume(argv[1], {0, 0, 0}, argc > 3 ? argv[3] : "density");
    topotet::write_mesh(argv[2], d);
    std::printf("%s: %zu vertices, %zu tets\n", argv[2], d.vertex_count(), d.tet_count());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "raw_to_mesh: %s\n", e.what());
    return 1;
  }
}
