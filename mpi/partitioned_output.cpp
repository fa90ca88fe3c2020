// topotet::mpi::write_partitioned: a .pvtu and one .vtu per rank (see topotet/mpi.h).
#include <cctype>
#include <cstdint>
#include <vector>

#include "exchange.h"
#include "io/xml_escape.h"
#include "migrate.h"
#include "topotet/io.h"
#include "topotet/mpi.h"

namespace topotet::mpi {

namespace {

bool ends_with_pvtu(const std::string& path) {
  if (path.size() < 5) return false;
  std::string tail = path.substr(path.size() - 5);
  for (char& c : tail) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return tail == ".pvtu";
}


std::string base_name(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

// The .pvtu: the arrays every piece has (as write_vtu writes them) and the pieces, by file name
// relative to the .pvtu.
std::string pvtu_text(const MeshData& layout, const std::vector<std::string>& pieces) {
  std::string x = "<?xml version=\"1.0\"?>\n"
                  "<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
                  "header_type=\"UInt64\">\n  <PUnstructuredGrid GhostLevel=\"0\">\n    <PPointData>\n";
  for (const VertexField& f : layout.fields) {
    x += "      <PDataArray type=\"Float64\" Name=\"" + io::xml_escape(f.name) + "\"";
    if (f.components != 1) x += " NumberOfComponents=\"" + std::to_string(f.components) + "\"";
    x += "/>\n";
  }
  x += "    </PPointData>\n    <PCellData Scalars=\"material\">\n"
       "      <PDataArray type=\"Int32\" Name=\"material\"/>\n    </PCellData>\n"
       "    <PPoints>\n      <PDataArray type=\"Float64\" NumberOfComponents=\"3\"/>\n    </PPoints>\n";
  for (const std::string& p : pieces) x += "    <Piece Source=\"" + io::xml_escape(p) + "\"/>\n";
  x += "  </PUnstructuredGrid>\n</VTKFile>\n";
  return x;
}

}  // namespace

void write_partitioned(MPI_Comm comm, const DistributedMesh& mesh, const std::string& pvtu_path) {
  const int me = detail::rank_of(comm), ranks = detail::size_of(comm);
  detail::agree_or_throw(comm, ends_with_pvtu(pvtu_path),
                         pvtu_path + ": a partitioned output is a .pvtu (with one .vtu per rank beside it)");
  const std::string stem = pvtu_path.substr(0, pvtu_path.size() - 5);
  const std::string piece = stem + "_" + std::to_string(me) + ".vtu";
  // The piece: this rank's part and its global ids as one more point field. The field layout is
  // agreed first, so that a rank without tets (rank 0 among them) knows the arrays of the .pvtu.
  DistributedMesh part = mesh;
  detail::agree_layout(comm, part);
  MeshData data = std::move(part.local);
  VertexField ids{"global_id", 1, {}};
  ids.values.reserve(mesh.global_ids.size());
  for (GlobalId g : mesh.global_ids) ids.values.push_back(static_cast<double>(g));
  data.fields.push_back(std::move(ids));
  const int has_tets = data.tet_count() > 0 ? 1 : 0;
  std::string error;
  if (has_tets) {
    try {
      write_mesh(piece, data);
    } catch (const std::exception& e) {
      error = e.what();
    }
  }
  detail::agree_or_throw(comm, error.empty(), error);
  std::vector<int> written(ranks);
  MPI_Gather(&has_tets, 1, MPI_INT, written.data(), 1, MPI_INT, 0, comm);
  if (me == 0) {
    std::vector<std::string> pieces;
    for (int r = 0; r < ranks; ++r)
      if (written[r]) pieces.push_back(base_name(stem) + "_" + std::to_string(r) + ".vtu");
    try {
      write_text_file(pvtu_path, pvtu_text(data, pieces));
    } catch (const std::exception& e) {
      error = e.what();
    }
  }
  detail::agree_or_throw(comm, error.empty(), error);
}

}  // namespace topotet::mpi
