// Exodus II output through VTK's vtkExodusIIWriter (io/vtk/exodus_writer.h: without its leak).
//
// The writer is given what VTK's own Exodus reader produces, so that its usual path writes it:
// a multiblock with
//  - "Element Blocks": one grid with every tet and an "ElementBlockIds" cell array = the material,
//    hence one element block per material (the writer orders blocks by id); then the listed edges
//    as line cells, one block per edge ref, with ids above every material (named
//    "topotet:edges ref=<ref>", which the reader maps back);
//  - "Side Sets": one grid per triangle ref (set id = ref), its faces given as SourceElementId /
//    SourceElementSide (the tet and its Exodus side);
//  - "Node Sets": "topotet:corners" and "topotet:required_vertices" when there are any;
//  - the fields as nodal variables: scalars and 3-vectors as they are, other component counts as
//    scalars "NAME[0]", "NAME[1]", ... (VTK's reader would regroup them wrongly otherwise);
//  - the cell fields as element variables, the same way.
// The cells are handed over in file order (tets sorted by material, stable; then the edges by
// ref), with global element ids 1..n, which is how the writer finds the side sets' elements.
// Block and set names (MeshData::group_names) are put in afterwards with the Exodus library (the
// writer would give one name to every block of a grid).
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkIdTypeArray.h>
#include <vtkInformation.h>
#include <vtkIntArray.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkUnstructuredGrid.h>

#include <vtk_exodusII.h>

#include <algorithm>
#include <array>
#include <map>
#include <numeric>
#include <tuple>
#include <unordered_map>

#include "io/atomic_file.h"
#include "io/formats.h"
#include "io/vtk/exodus_writer.h"
#include "io/vtk/vtk_check.h"
#include "io/vtk/vtk_quiet.h"
#include "topotet/error.h"
#include "topotet/io_vtk.h"

namespace topotet {
namespace {

// Exodus II TETRA side numbering (1-based sides, 0-based local nodes).
constexpr std::array<std::array<int, 3>, 4> kTetSides = {{{0, 1, 3}, {1, 2, 3}, {0, 3, 2}, {0, 2, 1}}};

using FaceKey = std::array<VertId, 3>;
struct FaceKeyHash {
  std::size_t operator()(const FaceKey& k) const {
    return (static_cast<std::size_t>(k[0]) * 0x9E3779B97F4A7C15ull) ^ (static_cast<std::size_t>(k[1]) * 0xC2B2AE3D27D4EB4Full) ^
           k[2];
  }
};
FaceKey sorted(FaceKey k) {
  std::sort(k.begin(), k.end());
  return k;
}

constexpr const char* kEdgesPrefix = "topotet:edges ref=";
constexpr const char* kCornersName = "topotet:corners";
constexpr const char* kRequiredName = "topotet:required_vertices";

void set_name(vtkMultiBlockDataSet* mb, unsigned i, const std::string& name) {
  mb->GetMetaData(i)->Set(vtkCompositeDataSet::NAME(), name.c_str());
}

}  // namespace

void write_exodus(const std::string& path, const MeshData& m) {
  if (!is_exodus_path(path)) throw InputError(path + ": write_exodus writes .exo, .e or .ex2 files");
  io::check_writable(path, m);
  if (m.positions.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()) ||
      m.tets.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw InputError(path + ": cannot write: too large for VTK's Exodus writer (32-bit ids)");

  // Element order: by material, stable.
  std::vector<std::size_t> order(m.tets.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  const auto material = [&](std::size_t t) { return m.tet_material.empty() ? 0 : m.tet_material[t]; };
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return material(a) < material(b); });

  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(static_cast<vtkIdType>(m.positions.size()));
  for (std::size_t v = 0; v < m.positions.size(); ++v) points->SetPoint(static_cast<vtkIdType>(v), m.positions[v].data());

  vtkNew<vtkUnstructuredGrid> grid;
  grid->SetPoints(points);
  grid->AllocateExact(static_cast<vtkIdType>(m.tets.size() + m.segments.size()), 4);
  vtkNew<vtkIntArray> blocks;
  blocks->SetName("ElementBlockIds");
  blocks->Allocate(static_cast<vtkIdType>(m.tets.size() + m.segments.size()));
  for (std::size_t i = 0; i < order.size(); ++i) {
    const auto& t = m.tets[order[i]];
    const vtkIdType ids[4] = {t[0], t[1], t[2], t[3]};
    grid->InsertNextCell(VTK_TETRA, 4, ids);
    blocks->InsertNextValue(material(order[i]));
  }
  // Listed edges: one block per ref, ids above the materials.
  std::map<std::int32_t, std::vector<std::size_t>> edges_by_ref;
  for (std::size_t i = 0; i < m.segments.size(); ++i) edges_by_ref[m.segments[i].ref].push_back(i);
  std::map<std::int32_t, std::int32_t> edge_block;  // ref -> block id
  std::int64_t next_id = 1;
  for (std::size_t t = 0; t < m.tets.size(); ++t) next_id = std::max<std::int64_t>(next_id, std::int64_t{material(t)} + 1);
  for (const auto& [ref, edges] : edges_by_ref) {
    if (next_id > std::numeric_limits<std::int32_t>::max())
      throw InputError(path + ": cannot write the listed edges: no element block id is left above the materials");
    const auto id = static_cast<std::int32_t>(next_id++);
    edge_block[ref] = id;
    for (std::size_t i : edges) {
      const vtkIdType ids[2] = {m.segments[i].v[0], m.segments[i].v[1]};
      grid->InsertNextCell(VTK_LINE, 2, ids);
      blocks->InsertNextValue(id);
    }
  }
  grid->GetCellData()->AddArray(blocks);
  // The writer finds the elements of the side sets through the global element ids (and writes
  // both id maps): 1..n in file order.
  vtkNew<vtkIdTypeArray> element_ids, node_ids;
  element_ids->SetName("GlobalElementId");
  element_ids->SetNumberOfValues(grid->GetNumberOfCells());
  for (vtkIdType i = 0; i < element_ids->GetNumberOfValues(); ++i) element_ids->SetValue(i, i + 1);
  grid->GetCellData()->SetGlobalIds(element_ids);
  node_ids->SetName("GlobalNodeId");
  node_ids->SetNumberOfValues(static_cast<vtkIdType>(m.positions.size()));
  for (vtkIdType i = 0; i < node_ids->GetNumberOfValues(); ++i) node_ids->SetValue(i, i + 1);
  grid->GetPointData()->SetGlobalIds(node_ids);
  // Fields: scalars and 3-vectors as they are (VTK's reader glues NAME_X/Y/Z back together);
  // other component counts as scalars "NAME[k]" (VTK's reader would split a 6-component array
  // into a vector and three scalars), which read_vtk_mesh joins again.
  const std::size_t nv = m.positions.size();
  for (const VertexField& f : m.fields) {
    const bool whole = f.components == 1 || f.components == 3;
    for (int k = 0; k < (whole ? 1 : f.components); ++k) {
      vtkNew<vtkDoubleArray> a;
      a->SetName((whole ? f.name : f.name + "[" + std::to_string(k) + "]").c_str());
      a->SetNumberOfComponents(whole ? f.components : 1);
      a->SetNumberOfTuples(static_cast<vtkIdType>(nv));
      if (whole) {
        std::copy(f.values.begin(), f.values.end(), a->GetPointer(0));
      } else {
        for (std::size_t v = 0; v < nv; ++v) a->SetValue(static_cast<vtkIdType>(v), f.values[v * f.components + k]);
      }
      grid->GetPointData()->AddArray(a);
    }
  }

  // Cell fields as element variables, the same way (scalars, 3-vectors, else "NAME[k]"); the listed
  // edges' line cells get 0. Exodus stores reals: labels come back as intensive arrays.
  const auto cell_count = static_cast<vtkIdType>(grid->GetNumberOfCells());
  for (const CellField& f : m.cell_fields) {
    const bool whole = f.components == 1 || f.components == 3;
    const auto c = static_cast<std::size_t>(f.components);
    for (int k = 0; k < (whole ? 1 : f.components); ++k) {
      vtkNew<vtkDoubleArray> a;
      a->SetName((whole ? f.name : f.name + "[" + std::to_string(k) + "]").c_str());
      a->SetNumberOfComponents(whole ? f.components : 1);
      a->SetNumberOfTuples(cell_count);
      a->Fill(0.0);
      for (std::size_t i = 0; i < order.size(); ++i) {
        if (whole) {
          for (std::size_t x = 0; x < c; ++x) a->SetComponent(static_cast<vtkIdType>(i), static_cast<int>(x), f.values[order[i] * c + x]);
        } else {
          a->SetValue(static_cast<vtkIdType>(i), f.values[order[i] * c + static_cast<std::size_t>(k)]);
        }
      }
      grid->GetCellData()->AddArray(a);
    }
  }

  // Side sets: one per triangle ref, each face found as a side of a tet.
  std::unordered_map<FaceKey, std::pair<std::int64_t, int>, FaceKeyHash> sides;
  if (!m.triangles.empty()) {
    sides.reserve(4 * m.tets.size());
    for (std::size_t i = 0; i < order.size(); ++i) {
      const auto& t = m.tets[order[i]];
      for (int s = 0; s < 4; ++s)
        sides.try_emplace(sorted({t[kTetSides[s][0]], t[kTetSides[s][1]], t[kTetSides[s][2]]}),
                          static_cast<std::int64_t>(i), s);
    }
  }
  std::vector<std::int32_t> materials;
  for (std::size_t t : order)
    if (materials.empty() || materials.back() != material(t)) materials.push_back(material(t));
  std::map<std::int32_t, std::vector<std::size_t>> by_ref;
  for (std::size_t i = 0; i < m.triangles.size(); ++i) by_ref[m.triangles[i].ref].push_back(i);

  vtkNew<vtkMultiBlockDataSet> root, element_blocks, side_sets;
  element_blocks->SetNumberOfBlocks(1);
  element_blocks->SetBlock(0, grid);
  set_name(element_blocks, 0, "");  // no name: the writer would give it to every block
  side_sets->SetNumberOfBlocks(static_cast<unsigned>(by_ref.size()));
  unsigned k = 0;
  for (const auto& [ref, triangles] : by_ref) {
    vtkNew<vtkUnstructuredGrid> set;
    set->SetPoints(points);
    set->AllocateExact(static_cast<vtkIdType>(triangles.size()), 3);
    vtkNew<vtkIdTypeArray> element;
    element->SetName("SourceElementId");
    vtkNew<vtkIntArray> side;
    side->SetName("SourceElementSide");
    for (std::size_t i : triangles) {
      const auto& v = m.triangles[i].v;
      const auto at = sides.find(sorted(v));
      if (at == sides.end())
        throw InputError(path + ": cannot write triangle " + std::to_string(i) +
                         ": it is not a face of any tet (Exodus side sets list faces of elements)");
      const vtkIdType ids[3] = {v[0], v[1], v[2]};
      set->InsertNextCell(VTK_TRIANGLE, 3, ids);
      element->InsertNextValue(at->second.first);
      side->InsertNextValue(at->second.second);
    }
    set->GetCellData()->AddArray(element);
    set->GetCellData()->AddArray(side);
    side_sets->SetBlock(k, set);
    set_name(side_sets, k, "Unnamed set ID: " + std::to_string(ref));  // the writer takes the id from the name
    ++k;
  }
  // Pinned vertices: node sets the reader knows by name.
  vtkNew<vtkMultiBlockDataSet> node_sets;
  const auto add_node_set = [&](const std::vector<VertId>& vertices, const char* name) {
    if (vertices.empty()) return;
    vtkNew<vtkUnstructuredGrid> set;
    set->SetPoints(points);
    set->AllocateExact(static_cast<vtkIdType>(vertices.size()), 1);
    for (VertId v : vertices) {
      const vtkIdType id = v;
      set->InsertNextCell(VTK_VERTEX, 1, &id);
    }
    set->GetPointData()->AddArray(node_ids);  // the writer lists each vertex by its global node id
    const unsigned i = node_sets->GetNumberOfBlocks();
    node_sets->SetNumberOfBlocks(i + 1);
    node_sets->SetBlock(i, set);
    set_name(node_sets, i, std::string(name) + " ID: " + std::to_string(i + 1));
  };
  add_node_set(m.corners, kCornersName);
  add_node_set(m.required_vertices, kRequiredName);
  root->SetNumberOfBlocks(3);
  root->SetBlock(0, element_blocks);
  set_name(root, 0, "Element Blocks");
  root->SetBlock(1, side_sets);
  set_name(root, 1, "Side Sets");
  root->SetBlock(2, node_sets);
  set_name(root, 2, "Node Sets");

  // To a temporary name beside `path`, renamed at the end (netCDF writes by name, so the atomic
  // file is only the name holder: closed empty, then written over by VTK).
  if (io::is_direct_output(path)) throw InputError(path + ": Exodus II cannot be written to a stream or device");
  io::AtomicFile file(path);
  file.close();
  vtkNew<io::vtk::VtkMessages> messages;
  {
    io::vtk::QuietVtk quiet(messages);
    vtkNew<io::vtk::ExodusWriter> writer;
    messages->watch(writer);
    writer->SetFileName(file.temp_path().c_str());
    writer->SetInputData(root);
    writer->SetBlockIdArrayName("ElementBlockIds");
    writer->WriteOutBlockIdArrayOff();
    writer->WriteAllTimeStepsOff();
    writer->SetStoreDoubles(1);
    const int ok = writer->Write();
    if (!ok || messages->has_errors() || writer->GetErrorCode() != 0) {
      const std::string why = messages->first_error();
      throw InputError(path + ": cannot write: " + (why.empty() ? std::string("VTK's Exodus writer failed") : why));
    }
  }
  // The names: materials' and surfaces' from group_names, the edge blocks' by convention.
  std::vector<std::tuple<ex_entity_type, std::int32_t, std::string>> names;
  for (const GroupName& g : m.group_names) {
    if (g.name.empty()) continue;
    if (g.dim == 3 && std::binary_search(materials.begin(), materials.end(), g.ref)) names.emplace_back(EX_ELEM_BLOCK, g.ref, g.name);
    if (g.dim == 2 && by_ref.count(g.ref)) names.emplace_back(EX_SIDE_SET, g.ref, g.name);
  }
  for (const auto& [ref, id] : edge_block) names.emplace_back(EX_ELEM_BLOCK, id, kEdgesPrefix + std::to_string(ref));
  if (!names.empty()) {
    io::vtk::ExodusQuiet quiet;
    int cpu_word_size = 8, io_word_size = 0;
    float version = 0.0f;
    const int exo = ex_open(file.temp_path().c_str(), EX_WRITE, &cpu_word_size, &io_word_size, &version);
    bool ok = exo >= 0;
    for (const auto& [type, id, name] : names)
      if (ok) ok = ex_put_name(exo, type, id, name.c_str()) >= 0;
    if (exo >= 0) ok = ex_close(exo) >= 0 && ok;
    if (!ok) throw InputError(path + ": cannot write: the Exodus library could not name the blocks and sets");
  }
  file.commit();
}

void write_any_mesh(const std::string& path, const MeshData& mesh, const WriteOptions& options) {
  if (!options.format && is_exodus_path(path)) return write_exodus(path, mesh);
  write_mesh(path, mesh, options);
}

}  // namespace topotet
