// Reading the VTK formats with VTK's own readers, then one conversion of their datasets into
// MeshData (docs/formats.md has the mapping; topotet/io_vtk.h the contract).
//
// Every format becomes a list of pieces (a dataset each, with a role and a default ref):
//   .vtu / .vtk       one piece (+ the pieces of <stem>_substructures.vtp: surfaces);
//   .pvtu             the reader's appended pieces (+ each piece's _substructures.vtp);
//   Exodus II         one piece per element block (ref: block id) and per side set (ref: set id),
//                     all on the file's node list (the reader does not "squeeze" the points);
//   CGNS              one piece per zone (ref: zone number) and per boundary patch (ref: the patch
//                     name's number).
// Pieces on one node list share it; the others (pvtu pieces, CGNS zones, companion .vtp files) are
// joined by point ids (a global-ids array: VTK's GlobalIds attribute or topotet-mpi's "global_id")
// or by identical coordinates.
#include <vtkAbstractArray.h>
#include <vtkCGNSReader.h>
#include <vtkCellData.h>
#include <vtkCellTypes.h>
#include <vtkCompositeDataSet.h>
#include <vtkDataArray.h>
#include <vtkDataSet.h>
#include <vtkDataSetAttributes.h>
#include <vtkExecutive.h>
#include <vtkExodusIIReader.h>
#include <vtkIdList.h>
#include <vtkInformation.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkMultiPieceDataSet.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkUnstructuredGridReader.h>
#include <vtkXMLPUnstructuredGridReader.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <iterator>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <unordered_map>

#include "io/formats.h"
#include "io/vtk/vtk_check.h"
#include "io/vtk/vtk_grid.h"
#include "io/vtk/vtk_quiet.h"
#include "topotet/error.h"
#include "topotet/io_vtk.h"

namespace topotet {
namespace {

using io::iends_with;
using io::vtk::QuietVtk;
using io::vtk::VtkMessages;

enum class Kind { kVtu, kPvtu, kLegacy, kExodus, kCgns };

std::optional<Kind> kind_of_path(std::string_view path) {
  if (iends_with(path, ".vtu")) return Kind::kVtu;
  if (iends_with(path, ".pvtu")) return Kind::kPvtu;
  if (iends_with(path, ".vtk")) return Kind::kLegacy;
  if (io::is_exodus_extension(path)) return Kind::kExodus;
  if (iends_with(path, ".cgns")) return Kind::kCgns;
  return std::nullopt;
}

// The names write_exodus gives what Exodus has no place for (vtk_write.cpp).
constexpr const char* kEdgesPrefix = "topotet:edges ref=";
constexpr const char* kCornersName = "topotet:corners";
constexpr const char* kRequiredName = "topotet:required_vertices";

// The default material arrays, in order of preference ("CellEntityIds": Gmsh's own .vtk output,
// its physical tags with -setnumber Mesh.SaveElementTagType 2, else its entity tags).
constexpr std::array<const char*, 5> kMaterialArrays = {"material", "gmsh:physical", "ObjectId", "ElementBlockIds",
                                                        "CellEntityIds"};

// Arrays that readers and writers add for their own bookkeeping: never fields, never reported.
bool is_bookkeeping(const std::string& name) {
  static const std::set<std::string> kNames = {
      "vtkGhostType",    "vtkOriginalPointIds", "vtkOriginalCellIds", "vtkValidPointMask", "vtkCompositeIndex",
      "ObjectId",        "GlobalNodeId",        "PedigreeNodeId",     "GlobalElementId",   "PedigreeElementId",
      "SourceElementId", "SourceElementSide",   "ImplicitNodeId",     "ImplicitElementId", "FileId",
      "ElementBlockIds", "global_id"};
  return kNames.count(name) != 0;
}

// ---- reading the file with VTK ----

enum class Role { kVolume, kSurface };  // kSurface: side sets, boundary patches, companion .vtp

struct Piece {
  vtkSmartPointer<vtkDataSet> data;
  Role role = Role::kVolume;
  std::optional<std::int32_t> ref;  // the piece's own ref (block id, set id, zone / patch number)
  bool fixed_ref = false;           // `ref` holds whatever the arrays say (write_exodus's edge blocks)
  bool required = false;            // its vertex cells are required vertices, not corners
  std::string label;                // "element block 3", "zone 'Fluid'": "" for a lone dataset
  std::string file;                 // the file it came from (companions are other files)
  // How its points join the others: kShared = the node list of the first piece (Exodus),
  // kJoin = by global id or identical coordinates, kFirst = it is the first piece.
  enum class Points { kFirst, kShared, kJoin } points = Points::kFirst;
};

struct Source {
  std::vector<Piece> pieces;
  std::vector<GroupName> names;  // from block / set / zone / patch names
  bool join_components = false;  // Exodus: scalars "NAME[0]", "NAME[1]", ... are one field
  bool named_refs = false;       // the refs above are the pieces' own (not an array's)
};

[[noreturn]] void fail(const std::string& path, const std::string& message) { throw InputError(path + ": " + message); }

// Opens the file ourselves first: "no such file" and "permission denied" say more than VTK's
// "cannot read", and the Exodus and CGNS libraries print to stderr (CGNS's ADF layer even exits
// the process) on a file they do not recognize, so their signature is checked before VTK sees it.
void check_file(const std::string& path, Kind kind) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) fail(path, "cannot open: is a directory");
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) fail(path, std::string("cannot open: ") + std::strerror(errno));
  std::array<unsigned char, 2056> head{};
  const std::size_t n = std::fread(head.data(), 1, head.size(), f);
  std::fclose(f);
  if (n == 0) fail(path, "empty file");
  static constexpr unsigned char kHdf5[8] = {0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n'};
  const auto hdf5 = [&] {
    for (std::size_t at : {0, 512, 1024, 2048})
      if (n >= at + 8 && std::memcmp(head.data() + at, kHdf5, 8) == 0) return true;
    return false;
  };
  if (kind == Kind::kExodus) {
    const bool netcdf = n >= 4 && head[0] == 'C' && head[1] == 'D' && head[2] == 'F' &&
                        (head[3] == 1 || head[3] == 2 || head[3] == 5);
    if (!netcdf && !hdf5()) fail(path, "not an Exodus II file (neither a NetCDF nor an HDF5 file)");
  }
  if (kind == Kind::kCgns && !hdf5() && !(n >= 4 && std::memcmp(head.data(), "@(#)", 4) == 0))
    fail(path, "not a CGNS file (neither an HDF5 nor an ADF file)");
}

// VTK's XML reader can crash on a file cut short inside its appended data (VTK 9.1): a complete
// file ends with </VTKFile>.
void check_xml_complete(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) fail(path, std::string("cannot open: ") + std::strerror(errno));
  std::array<char, 256> tail{};
  std::size_t n = 0;
  if (std::fseek(f, 0, SEEK_END) == 0) {
    const long size = std::ftell(f);
    const long from = size > static_cast<long>(tail.size()) ? size - static_cast<long>(tail.size()) : 0;
    if (std::fseek(f, from, SEEK_SET) == 0) n = std::fread(tail.data(), 1, tail.size(), f);
  }
  std::fclose(f);
  std::string_view t(tail.data(), n);
  while (!t.empty() && (t.back() == ' ' || t.back() == '\n' || t.back() == '\r' || t.back() == '\t')) t.remove_suffix(1);
  if (!t.ends_with("</VTKFile>")) fail(path, "incomplete VTK XML file (it does not end with </VTKFile>: cut short?)");
}

// Runs `reader` and turns any error it (or VTK below it) reported into an InputError.
void run(vtkAlgorithm* reader, VtkMessages* messages, const std::string& path) {
  const int ok = reader->GetExecutive()->Update();
  if (!ok || messages->has_errors() || reader->GetErrorCode() != 0) {
    std::string why = messages->first_error();
    if (why.empty()) why = "the reader failed";
    fail(path, "VTK cannot read it: " + why);
  }
}

// An Exodus or VTK default name ("Unnamed block ID: 3", "Unnamed set ID: 7") says nothing; a name
// ending in " ID: <id>" (as write_exodus's side sets are named) loses that suffix.
std::string user_name(std::string name, std::int32_t id) {
  if (name.rfind("Unnamed ", 0) == 0) return {};
  const std::string suffix = " ID: " + std::to_string(id);
  if (name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0)
    name.resize(name.size() - suffix.size());
  return name;
}

class PvtuReader final : public vtkXMLPUnstructuredGridReader {
 public:
  static PvtuReader* New();
  vtkTypeMacro(PvtuReader, vtkXMLPUnstructuredGridReader)
  std::vector<std::string> piece_files() const {
    std::vector<std::string> files;
    for (int i = 0; i < this->NumberOfPieces; ++i) {
      const char* f = this->PieceReaders && this->PieceReaders[i] ? this->PieceReaders[i]->GetFileName() : nullptr;
      if (f) files.emplace_back(f);
    }
    return files;
  }
};
vtkStandardNewMacro(PvtuReader)

std::string read_stdin() {
  std::ostringstream s;
  s << std::cin.rdbuf();
  return s.str();
}

// <stem>_substructures.vtp beside a .vtu that topotet wrote: its triangles, edges and refs.
void add_companion(Source& source, const std::string& vtu_path) {
  std::string stem = vtu_path;
  if (iends_with(stem, ".vtu")) stem.resize(stem.size() - 4);
  const std::string vtp = stem + "_substructures.vtp";
  std::error_code ec;
  if (!std::filesystem::is_regular_file(vtp, ec)) return;
  vtkNew<VtkMessages> messages;
  check_xml_complete(vtp);
  vtkNew<vtkXMLPolyDataReader> reader;
  messages->watch(reader);
  reader->SetFileName(vtp.c_str());
  run(reader, messages, vtp);
  Piece p;
  p.data = reader->GetOutput();
  p.role = Role::kSurface;
  p.file = vtp;
  p.points = Piece::Points::kJoin;
  source.pieces.push_back(std::move(p));
}

Source read_xml(const std::string& path, Kind kind, VtkMessages* messages) {
  Source source;
  Piece p;
  p.file = path;
  if (kind == Kind::kPvtu) {
    vtkNew<PvtuReader> reader;
    messages->watch(reader);
    reader->SetFileName(path.c_str());
    reader->UpdateInformation();
    if (messages->has_errors()) fail(path, "VTK cannot read it: " + messages->first_error());
    for (const std::string& piece : reader->piece_files()) {
      std::error_code ec;
      if (!std::filesystem::is_regular_file(piece, ec)) fail(path, "its piece " + piece + " is missing");
      check_xml_complete(piece);
    }
    run(reader, messages, path);
    p.data = reader->GetOutput();
    source.pieces.push_back(p);
    for (const std::string& piece : reader->piece_files()) add_companion(source, piece);
    return source;
  }
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  messages->watch(reader);
  if (path == "-") {
    reader->ReadFromInputStringOn();
    reader->SetInputString(read_stdin());
  } else {
    reader->SetFileName(path.c_str());
  }
  run(reader, messages, path == "-" ? "<stdin>" : path);
  p.data = reader->GetOutput();
  source.pieces.push_back(p);
  if (path != "-") add_companion(source, path);
  return source;
}

Source read_legacy(const std::string& path, VtkMessages* messages) {
  vtkNew<vtkUnstructuredGridReader> reader;
  messages->watch(reader);
  reader->SetFileName(path.c_str());
  if (!reader->OpenVTKFile() || !reader->ReadHeader()) {
    reader->CloseVTKFile();
    std::string why = messages->first_error();
    fail(path, "VTK cannot read it: " + (why.empty() ? std::string("not a legacy VTK file") : why));
  }
  reader->CloseVTKFile();
  if (!reader->IsFileUnstructuredGrid()) {
    const char* type = reader->IsFilePolyData()          ? "POLYDATA"
                       : reader->IsFileStructuredGrid()   ? "STRUCTURED_GRID"
                       : reader->IsFileStructuredPoints() ? "STRUCTURED_POINTS"
                       : reader->IsFileRectilinearGrid()  ? "RECTILINEAR_GRID"
                                                          : "not a dataset";
    fail(path, std::string("not an unstructured grid (DATASET ") + type + "): topotet reads tetrahedral meshes");
  }
  run(reader, messages, path);
  Source source;
  Piece p;
  p.data = reader->GetOutput();
  p.file = path;
  source.pieces.push_back(p);
  return source;
}

Source read_exodus(const std::string& path, VtkMessages* messages) {
  io::vtk::ExodusQuiet quiet;
  io::vtk::check_exodus(path);
  vtkNew<vtkExodusIIReader> reader;
  messages->watch(reader);
  reader->SetFileName(path.c_str());
  reader->UpdateInformation();
  quiet.again();
  if (messages->has_errors()) fail(path, "VTK cannot read it: " + messages->first_error());
  // The file's own coordinates and node list: no displacement applied, every node kept (so that
  // all blocks and sets index one node list), no generated id arrays but the block / set ids.
  reader->SetSqueezePoints(false);
  reader->ApplyDisplacementsOff();
  reader->GenerateObjectIdCellArrayOn();
  reader->GenerateGlobalNodeIdArrayOff();
  reader->GenerateGlobalElementIdArrayOff();
  reader->GenerateImplicitNodeIdArrayOff();
  reader->GenerateImplicitElementIdArrayOff();
  reader->GenerateFileIdArrayOff();
  for (int type : {vtkExodusIIReader::ELEM_BLOCK, vtkExodusIIReader::SIDE_SET})
    for (int i = 0; i < reader->GetNumberOfObjects(type); ++i) reader->SetObjectStatus(type, i, 1);
  // Node sets are boundary-condition node lists, except the pinned vertices write_exodus writes.
  for (int i = 0; i < reader->GetNumberOfObjects(vtkExodusIIReader::NODE_SET); ++i) {
    const char* name = reader->GetObjectName(vtkExodusIIReader::NODE_SET, i);
    const std::string n = user_name(name ? name : "", reader->GetObjectId(vtkExodusIIReader::NODE_SET, i));
    reader->SetObjectStatus(vtkExodusIIReader::NODE_SET, i, n == kCornersName || n == kRequiredName);
  }
  for (int type : {vtkExodusIIReader::NODAL, vtkExodusIIReader::ELEM_BLOCK}) reader->SetAllArrayStatus(type, 1);
  run(reader, messages, path);

  Source source;
  source.named_refs = true;
  source.join_components = true;
  const auto add_names = [&](int type, int dim) {
    for (int i = 0; i < reader->GetNumberOfObjects(type); ++i) {
      const std::int32_t id = reader->GetObjectId(type, i);
      const char* name = reader->GetObjectName(type, i);
      std::string n = user_name(name ? name : "", id);
      if (!n.empty()) source.names.push_back({dim, id, std::move(n)});
    }
  };
  add_names(vtkExodusIIReader::ELEM_BLOCK, 3);
  add_names(vtkExodusIIReader::SIDE_SET, 2);
  std::erase_if(source.names, [](const GroupName& g) { return g.name.rfind(kEdgesPrefix, 0) == 0; });

  vtkMultiBlockDataSet* root = reader->GetOutput();
  for (unsigned b = 0; root && b < root->GetNumberOfBlocks(); ++b) {
    const char* group = root->HasMetaData(b) ? root->GetMetaData(b)->Get(vtkCompositeDataSet::NAME()) : nullptr;
    const bool blocks = group && std::strcmp(group, "Element Blocks") == 0;
    const bool sides = group && std::strcmp(group, "Side Sets") == 0;
    const bool nodes = group && std::strcmp(group, "Node Sets") == 0;
    if (!blocks && !sides && !nodes) continue;  // face / edge blocks, element / face / edge sets
    auto* children = vtkMultiBlockDataSet::SafeDownCast(root->GetBlock(b));
    for (unsigned c = 0; children && c < children->GetNumberOfBlocks(); ++c) {
      auto* ds = vtkDataSet::SafeDownCast(children->GetBlock(c));
      if (!ds || ds->GetNumberOfCells() == 0) continue;
      Piece p;
      p.data = ds;
      p.file = path;
      p.role = blocks ? Role::kVolume : Role::kSurface;
      if (auto* ids = vtkDataArray::SafeDownCast(ds->GetCellData()->GetAbstractArray("ObjectId")))
        p.ref = static_cast<std::int32_t>(ids->GetComponent(0, 0));
      p.label = (blocks ? "element block " : sides ? "side set " : "node set ") +
                (p.ref ? std::to_string(*p.ref) : std::to_string(c));
      const char* leaf = children->HasMetaData(c) ? children->GetMetaData(c)->Get(vtkCompositeDataSet::NAME()) : nullptr;
      const std::string name = user_name(leaf ? leaf : "", p.ref.value_or(0));
      if (blocks && name.rfind(kEdgesPrefix, 0) == 0) {
        // write_exodus's listed edges: the ref is in the name, the id only keeps blocks apart.
        char* end = nullptr;
        const long ref = std::strtol(name.c_str() + std::strlen(kEdgesPrefix), &end, 10);
        if (end && *end == '\0' && ref >= std::numeric_limits<std::int32_t>::min() && ref <= std::numeric_limits<std::int32_t>::max()) {
          p.ref = static_cast<std::int32_t>(ref);
          p.fixed_ref = true;
        }
      }
      if (nodes) {
        p.role = Role::kSurface;
        p.fixed_ref = true;
        p.required = name == kRequiredName;
      }
      p.points = source.pieces.empty() ? Piece::Points::kFirst : Piece::Points::kShared;
      source.pieces.push_back(std::move(p));
    }
  }
  return source;
}

// The leaves of a composite dataset with the names of the blocks above them (root first).
void collect_leaves(vtkDataObject* object, std::vector<std::string>& trail,
                    std::vector<std::pair<vtkDataSet*, std::vector<std::string>>>& out) {
  if (auto* ds = vtkDataSet::SafeDownCast(object)) {
    out.emplace_back(ds, trail);
    return;
  }
  if (auto* mb = vtkMultiBlockDataSet::SafeDownCast(object)) {
    for (unsigned i = 0; i < mb->GetNumberOfBlocks(); ++i) {
      const char* n = mb->HasMetaData(i) ? mb->GetMetaData(i)->Get(vtkCompositeDataSet::NAME()) : nullptr;
      trail.emplace_back(n ? n : "");
      collect_leaves(mb->GetBlock(i), trail, out);
      trail.pop_back();
    }
  } else if (auto* mp = vtkMultiPieceDataSet::SafeDownCast(object)) {
    for (unsigned i = 0; i < mp->GetNumberOfPieces(); ++i) collect_leaves(mp->GetPiece(i), trail, out);
  }
}

Source read_cgns(const std::string& path, VtkMessages* messages) {
  io::vtk::check_cgns(path);
  vtkNew<vtkCGNSReader> reader;
  messages->watch(reader);
  reader->SetFileName(path.c_str());
  reader->UpdateInformation();
  if (messages->has_errors()) fail(path, "VTK cannot read it: " + messages->first_error());
  reader->EnableAllBases();
  reader->EnableAllFamilies();
  reader->EnableAllPointArrays();
  reader->EnableAllCellArrays();
  reader->LoadMeshOn();
  reader->LoadBndPatchOn();
  run(reader, messages, path);

  // Base / Zone / Internal (the zone's cells) and Base / Zone / Patches / <BC> (its boundary
  // patches); a zone without patches may be the leaf itself.
  std::vector<std::pair<vtkDataSet*, std::vector<std::string>>> leaves;
  std::vector<std::string> trail;
  collect_leaves(reader->GetOutput(), trail, leaves);
  Source source;
  source.named_refs = true;
  std::map<std::string, std::int32_t> patch_refs;
  std::int32_t zones = 0;
  for (auto& [ds, names] : leaves) {
    if (!ds || ds->GetNumberOfCells() == 0) continue;
    const std::string leaf = names.empty() ? std::string() : names.back();
    Piece p;
    p.data = ds;
    p.file = path;
    p.points = source.pieces.empty() ? Piece::Points::kFirst : Piece::Points::kJoin;
    if (names.size() >= 2 && names[names.size() - 2] == "Patches") {
      auto [at, fresh] = patch_refs.try_emplace(leaf, static_cast<std::int32_t>(patch_refs.size() + 1));
      if (fresh && !leaf.empty()) source.names.push_back({2, at->second, leaf});
      p.role = Role::kSurface;
      p.ref = at->second;
      p.label = "boundary patch '" + leaf + "'";
    } else {
      const std::string zone = leaf == "Internal" && names.size() >= 2 ? names[names.size() - 2] : leaf;
      p.ref = ++zones;
      if (!zone.empty()) source.names.push_back({3, *p.ref, zone});
      p.label = "zone '" + zone + "'";
      if (!vtkUnstructuredGrid::SafeDownCast(ds)) p.label += " (structured)";
    }
    source.pieces.push_back(std::move(p));
  }
  return source;
}

// ---- the conversion into MeshData ----

struct PositionHash {
  std::size_t operator()(const std::array<double, 3>& p) const {
    std::size_t h = 0;
    for (double x : p) {
      std::uint64_t bits;
      const double y = x == 0.0 ? 0.0 : x;  // -0 == 0
      std::memcpy(&bits, &y, 8);
      h = h * 0x9E3779B97F4A7C15ull ^ (bits + (h >> 7));
    }
    return h;
  }
};

// An integer id array as int32 values (integral floats are accepted: ParaView's filters often
// turn ids into doubles). Throws naming the array and the cell.
std::vector<std::int32_t> int_values(const std::string& path, const Piece& piece, vtkDataArray* a, const std::string& name) {
  const std::string where = piece.label.empty() ? "" : piece.label + ", ";
  if (a->GetNumberOfComponents() != 1)
    fail(path, where + "cell array '" + name + "' has " + std::to_string(a->GetNumberOfComponents()) +
                   " components; a material array has one");
  const vtkIdType n = a->GetNumberOfTuples();
  std::vector<std::int32_t> out(static_cast<std::size_t>(n));
  for (vtkIdType i = 0; i < n; ++i) {
    const double v = a->GetComponent(i, 0);
    if (!(v == std::floor(v)) || v < std::numeric_limits<std::int32_t>::min() || v > std::numeric_limits<std::int32_t>::max()) {
      std::ostringstream s;
      s << v;
      fail(path, where + "cell " + std::to_string(i) + ": cell array '" + name + "' value " + s.str() +
                     " is not an integer id (choose the material array with --material-array)");
    }
    out[static_cast<std::size_t>(i)] = static_cast<std::int32_t>(v);
  }
  return out;
}

class Converter {
 public:
  Converter(std::string path, const ReadOptions& options, ReadNotes& notes)
      : path_(std::move(path)), options_(options), notes_(notes) {}

  MeshData convert(const Source& source) {
    for (const Piece& p : source.pieces) {
      add_piece(p);
      check_cell_arrays();
    }
    finish(source);
    return std::move(m_);
  }

 private:
  std::string where(const Piece& p, const char* what, vtkIdType i) const {
    return (p.label.empty() ? std::string() : p.label + ", ") + what + " " + std::to_string(i);
  }
  std::string prefix(const Piece& p) const { return p.label.empty() ? std::string() : p.label + ": "; }
  const std::string& file_of(const Piece& p) const { return p.file.empty() || p.file == "-" ? path_ : p.file; }
  bool is_companion(const Piece& p) const { return file_of(p) != path_; }

  VertId append(const std::array<double, 3>& x, const Piece& p) {
    if (m_.positions.size() + 1 >= kInvalid) fail(file_of(p), "too many points");
    const auto v = static_cast<VertId>(m_.positions.size());
    m_.positions.push_back(x);
    if (indexed_) by_position_.try_emplace(x, v);
    return v;
  }

  // The vertex of each point of `p` in m_.
  std::vector<VertId> place_points(const Piece& p) {
    vtkDataSet* ds = p.data;
    const vtkIdType n = ds->GetNumberOfPoints();
    std::vector<VertId> map(static_cast<std::size_t>(n));
    if (p.points == Piece::Points::kShared) {  // Exodus: every block and set on the file's node list
      if (static_cast<std::size_t>(n) != m_.positions.size())
        fail(file_of(p), prefix(p) + std::to_string(n) + " points where the file has " + std::to_string(m_.positions.size()));
      for (vtkIdType i = 0; i < n; ++i) map[static_cast<std::size_t>(i)] = static_cast<VertId>(i);
      return map;
    }
    // The appended pieces of a .pvtu repeat the points they share: joined by global id when the
    // file has one (VTK's GlobalIds attribute, topotet-mpi's "global_id"), else by coordinates.
    const bool first = p.points == Piece::Points::kFirst;
    const bool pvtu = first && iends_with(path_, ".pvtu");
    vtkDataArray* gid = nullptr;
    if (pvtu) {
      gid = ds->GetPointData()->GetGlobalIds();
      if (!gid) gid = vtkDataArray::SafeDownCast(ds->GetPointData()->GetAbstractArray("global_id"));
      if (gid && gid->GetNumberOfComponents() != 1) gid = nullptr;
    }
    if ((pvtu && !gid) || !first) index_positions();
    std::unordered_map<std::int64_t, VertId> by_id;
    for (vtkIdType i = 0; i < n; ++i) {
      std::array<double, 3> x;
      ds->GetPoint(i, x.data());
      for (double c : x)
        if (!std::isfinite(c)) fail(file_of(p), where(p, "point", i) + ": coordinate is not finite (nan or inf)");
      VertId v = kInvalid;
      if (gid) {
        const auto [at, fresh] = by_id.try_emplace(static_cast<std::int64_t>(gid->GetComponent(i, 0)), kInvalid);
        if (fresh) at->second = append(x, p);
        v = at->second;
      } else if (indexed_) {
        const auto at = by_position_.find(x);
        if (at != by_position_.end()) {
          v = at->second;
        } else if (is_companion(p)) {
          fail(file_of(p), where(p, "point", i) + " is not a point of " + path_);
        } else {
          v = append(x, p);
        }
      } else {
        v = append(x, p);
      }
      map[static_cast<std::size_t>(i)] = v;
    }
    return map;
  }

  void index_positions() {
    if (indexed_) return;
    indexed_ = true;
    by_position_.reserve(m_.positions.size());
    for (std::size_t i = 0; i < m_.positions.size(); ++i) by_position_.try_emplace(m_.positions[i], static_cast<VertId>(i));
  }

  // The material / ref of each cell of `p`, from the chosen array, else the piece's own id.
  std::vector<std::int32_t> cell_refs(const Piece& p, std::string& used) {
    if (p.fixed_ref) return {};
    vtkCellData* cd = p.data->GetCellData();
    const auto numeric = [&](const std::string& name) -> vtkDataArray* {
      vtkAbstractArray* a = cd->GetAbstractArray(name.c_str());
      if (a && !vtkDataArray::SafeDownCast(a))
        fail(file_of(p), prefix(p) + "cell array '" + name + "' is not numeric (" + a->GetClassName() + ")");
      return vtkDataArray::SafeDownCast(a);
    };
    if (!options_.material_array.empty()) {
      if (vtkDataArray* a = numeric(options_.material_array)) {
        used = options_.material_array;
        if (p.role == Role::kVolume && used != "ObjectId") own_ids_ = false;
        return int_values(file_of(p), p, a, used);
      }
      if (p.role == Role::kVolume) {
        std::string present;
        for (int i = 0; i < cd->GetNumberOfArrays(); ++i)
          if (const char* name = cd->GetArrayName(i)) present += std::string(present.empty() ? "" : ", ") + "'" + name + "'";
        fail(file_of(p), prefix(p) + "no cell array '" + options_.material_array + "' (--material-array); its cell arrays: " +
                             (present.empty() ? "none" : present));
      }
    } else {
      for (const char* name : kMaterialArrays) {
        if (vtkDataArray* a = numeric(name)) {
          used = name;
          if (p.role == Role::kVolume && used != "ObjectId") own_ids_ = false;
          return int_values(file_of(p), p, a, used);
        }
      }
    }
    if (p.ref) return {};
    // topotet's companion .vtp names its refs "ref".
    if (p.role == Role::kSurface) {
      if (vtkDataArray* a = numeric("ref")) {
        used = "ref";
        return int_values(file_of(p), p, a, used);
      }
    }
    return {};
  }

  void add_piece(const Piece& p) {
    const std::vector<VertId> vmap = place_points(p);
    if (p.role == Role::kVolume) volume_pieces_.emplace_back(&p, vmap);

    vtkDataSet* ds = p.data;
    vtkCellData* cd = ds->GetCellData();
    std::string used;
    const std::vector<std::int32_t> refs = cell_refs(p, used);
    if (p.role == Role::kVolume && !used.empty()) notes_.material_array = used;
    const std::int32_t fallback = p.ref.value_or(0);
    const auto ref_of = [&](vtkIdType c) { return refs.empty() ? fallback : refs[static_cast<std::size_t>(c)]; };
    // The numeric cell arrays of a volume piece are carried for its tets (cell_arrays_), the
    // others are noted as not read.
    std::vector<std::pair<std::size_t, vtkDataArray*>> carried;  // (index in cell_arrays_, array)
    const std::size_t tets_before = m_.tets.size();
    for (int i = 0; i < cd->GetNumberOfArrays(); ++i) {
      vtkAbstractArray* a = cd->GetAbstractArray(i);
      const std::string name = a && a->GetName() ? a->GetName() : "";
      if (name.empty() || name == used || is_bookkeeping(name) || (is_companion(p) && name == "ref")) continue;
      if (name == vtkDataSetAttributes::GhostArrayName()) continue;
      auto* numeric = vtkDataArray::SafeDownCast(a);
      if (p.role != Role::kVolume || !numeric) {
        unread_.insert("cell array '" + name + "'" + (numeric ? "" : std::string(" (not numeric: ") + a->GetClassName() + ")"));
        continue;
      }
      carried.emplace_back(cell_array(name, numeric, tets_before), numeric);
    }

    // Duplicated cells of a parallel file (ghost cells) belong to another piece.
    auto* ghosts = vtkUnsignedCharArray::SafeDownCast(cd->GetAbstractArray(vtkDataSetAttributes::GhostArrayName()));
    auto* ug = vtkUnstructuredGrid::SafeDownCast(ds);
    vtkNew<vtkIdList> ids;
    const vtkIdType ncells = ds->GetNumberOfCells();
    const auto npoints = static_cast<vtkIdType>(vmap.size());
    for (vtkIdType c = 0; c < ncells; ++c) {
      if (ghosts && (ghosts->GetValue(c) & vtkDataSetAttributes::DUPLICATECELL)) continue;
      const int type = ds->GetCellType(c);
      vtkIdType n = 0;
      const vtkIdType* pts = nullptr;
      if (ug) {
        ug->GetCellPoints(c, n, pts);
      } else {
        ds->GetCellPoints(c, ids);
        n = ids->GetNumberOfIds();
        pts = ids->GetPointer(0);
      }
      for (vtkIdType k = 0; k < n; ++k)
        if (pts[k] < 0 || pts[k] >= npoints)
          fail(file_of(p), where(p, "cell", c) + ": point index " + std::to_string(pts[k]) + " out of range (" +
                               std::to_string(npoints) + " points)");
      const auto v = [&](vtkIdType k) { return vmap[static_cast<std::size_t>(pts[k])]; };
      const auto need = [&](vtkIdType count) {
        if (n != count)
          fail(file_of(p), where(p, "cell", c) + ": " + std::to_string(n) + " points for a " +
                               vtkCellTypes::GetClassNameFromTypeId(type));
      };
      switch (type) {
        case VTK_EMPTY_CELL:
          break;
        case VTK_TETRA:
          need(4);
          if (p.role != Role::kVolume) fail(file_of(p), where(p, "cell", c) + ": a tetrahedron among surface cells");
          if (m_.tets.size() + 1 >= kInvalid) fail(file_of(p), "too many tetrahedra");
          m_.tets.push_back({v(0), v(1), v(2), v(3)});
          m_.tet_material.push_back(ref_of(c));
          for (const auto& [index, array] : carried) append_cell_values(p, c, index, array);
          break;
        case VTK_TRIANGLE:
          need(3);
          m_.triangles.push_back({{v(0), v(1), v(2)}, ref_of(c)});
          break;
        case VTK_TRIANGLE_STRIP:
          for (vtkIdType k = 0; k + 2 < n; ++k) m_.triangles.push_back({{v(k), v(k + 1), v(k + 2)}, ref_of(c)});
          break;
        case VTK_POLYGON:
          if (n == 3)
            m_.triangles.push_back({{v(0), v(1), v(2)}, ref_of(c)});
          else
            ++notes_.quadrilaterals;  // like a quadrilateral, never a face of a tet
          break;
        case VTK_LINE:
          need(2);
          m_.segments.push_back({{v(0), v(1)}, ref_of(c)});
          break;
        case VTK_POLY_LINE:
          for (vtkIdType k = 0; k + 1 < n; ++k) m_.segments.push_back({{v(k), v(k + 1)}, ref_of(c)});
          break;
        case VTK_VERTEX:
        case VTK_POLY_VERTEX:
          for (vtkIdType k = 0; k < n; ++k) (p.required ? m_.required_vertices : m_.corners).push_back(v(k));
          break;
        case VTK_QUAD:
        case VTK_PIXEL:
          ++notes_.quadrilaterals;
          break;
        case VTK_HEXAHEDRON:
        case VTK_VOXEL:
          volume_cell(p, c, "hexahedron", notes_.hexahedra);
          break;
        case VTK_WEDGE:
          volume_cell(p, c, "prism", notes_.prisms);
          break;
        case VTK_PYRAMID:
          volume_cell(p, c, "pyramid", notes_.pyramids);
          break;
        case VTK_PENTAGONAL_PRISM:
        case VTK_HEXAGONAL_PRISM:
        case VTK_POLYHEDRON:
          volume_cell(p, c, vtkCellTypes::GetClassNameFromTypeId(type), notes_.polyhedra);
          break;
        default:
          fail(file_of(p), where(p, "cell", c) + ": VTK cell type " + std::to_string(type) + " (" +
                               vtkCellTypes::GetClassNameFromTypeId(type) +
                               ") is not supported: topotet reads linear tetrahedra, triangles, lines and vertices");
      }
    }
  }

  // The cell array `name` of the pieces read so far (created with this piece when new): one that
  // the pieces before it, which gave tets, did not have is not carried (it is on some blocks only).
  std::size_t cell_array(const std::string& name, vtkDataArray* a, std::size_t tets_before) {
    for (std::size_t k = 0; k < cell_arrays_.size(); ++k)
      if (cell_arrays_[k].field.name == name) {
        if (cell_arrays_[k].field.components != a->GetNumberOfComponents()) cell_arrays_[k].partial = true;
        return k;
      }
    CellArray added;
    added.field.name = name;
    added.field.components = a->GetNumberOfComponents();
    // VTK's integer types are labels; float and double are intensive values (mesh_data.h).
    const int type = a->GetDataType();
    added.field.kind = type == VTK_FLOAT || type == VTK_DOUBLE ? CellFieldKind::kIntensive : CellFieldKind::kCategorical;
    added.partial = tets_before != 0;
    cell_arrays_.push_back(std::move(added));
    return cell_arrays_.size() - 1;
  }

  void append_cell_values(const Piece& p, vtkIdType c, std::size_t index, vtkDataArray* a) {
    CellArray& target = cell_arrays_[index];
    if (target.partial) return;
    for (int k = 0; k < target.field.components; ++k) {
      const double x = a->GetComponent(c, k);
      if (!std::isfinite(x))
        fail(file_of(p), where(p, "cell", c) + ": cell array '" + target.field.name + "': value is not finite (nan or inf)");
      target.field.values.push_back(x);
    }
  }

  // After a piece: an array it did not have, while it gave tets, is on some blocks only.
  void check_cell_arrays() {
    for (CellArray& a : cell_arrays_)
      if (!a.partial && a.field.values.size() != m_.tets.size() * static_cast<std::size_t>(a.field.components)) a.partial = true;
  }

  void volume_cell(const Piece& p, vtkIdType c, const std::string& what, std::uint64_t& count) {
    if (!options_.tets_only)
      throw InputError(io::mixed_mesh_message(file_of(p) + ": " + where(p, "cell", c) + " (" + what + ")"));
    ++count;
  }

  // The numeric point arrays of the volume pieces become the fields.
  void finish(const Source& source) {
    if (m_.tets.empty()) {
      std::string why = "the file has no tetrahedra";
      if (notes_.volume_cells() != 0) why += " (--tets-only left out every volume cell)";
      if (iends_with(path_, ".cgns")) why += "; topotet reads the TETRA_4 elements of unstructured zones";
      fail(path_, why);
    }
    const std::size_t nv = m_.positions.size();
    if (!volume_pieces_.empty()) {
      const Piece& model = *volume_pieces_.front().first;
      vtkPointData* pd = model.data->GetPointData();
      for (int i = 0; i < pd->GetNumberOfArrays(); ++i) {
        vtkAbstractArray* a = pd->GetAbstractArray(i);
        const std::string name = a && a->GetName() ? a->GetName() : "";
        if (!a || a == pd->GetGlobalIds() || name.empty() || is_bookkeeping(name)) continue;
        if (!vtkDataArray::SafeDownCast(a)) {
          unread_.insert("point array '" + name + "' (not numeric: " + a->GetClassName() + ")");
          continue;
        }
        VertexField f;
        f.name = name;
        f.components = a->GetNumberOfComponents();
        f.values.assign(nv * static_cast<std::size_t>(f.components), 0.0);
        std::vector<char> seen(nv, 0);
        bool complete = true;
        for (const auto& [piece, vmap] : volume_pieces_) {
          if (piece != &model && piece->points == Piece::Points::kShared) continue;  // the same node list
          auto* pa = vtkDataArray::SafeDownCast(piece->data->GetPointData()->GetAbstractArray(name.c_str()));
          if (!pa || pa->GetNumberOfComponents() != f.components) {
            complete = false;
            break;
          }
          for (vtkIdType k = 0; k < pa->GetNumberOfTuples() && k < static_cast<vtkIdType>(vmap.size()); ++k) {
            const VertId v = vmap[static_cast<std::size_t>(k)];
            if (seen[v]) continue;
            seen[v] = 1;
            for (int c = 0; c < f.components; ++c) {
              const double x = pa->GetComponent(k, c);
              if (!std::isfinite(x))
                fail(file_of(*piece), where(*piece, "point", k) + ": point array '" + name + "': value is not finite (nan or inf)");
              f.values[static_cast<std::size_t>(v) * static_cast<std::size_t>(f.components) + static_cast<std::size_t>(c)] = x;
            }
          }
        }
        if (!complete) {
          unread_.insert("point array '" + name + "' (not on every zone)");
          continue;
        }
        m_.fields.push_back(std::move(f));
      }
    }
    for (CellArray& a : cell_arrays_) {
      if (a.partial) {
        unread_.insert("cell array '" + a.field.name + "' (not on every block)");
      } else {
        m_.cell_fields.push_back(std::move(a.field));
      }
    }
    if (source.join_components) {
      join_components(m_.fields, m_.positions.size());
      join_components(m_.cell_fields, m_.tets.size());
    }
    // Block, set, zone and patch names name the refs only when the refs are those ids.
    if (source.named_refs && own_ids_) {
      std::vector<GroupName> names = source.names;
      std::sort(names.begin(), names.end());
      for (const GroupName& g : names)
        if (m_.group_names.empty() || m_.group_names.back().dim != g.dim || m_.group_names.back().ref != g.ref)
          m_.group_names.push_back(g);
    }
    notes_.unread_arrays.assign(unread_.begin(), unread_.end());
  }

  // Scalars "NAME[0]" .. "NAME[n-1]" (write_exodus's fields of other than 1 or 3 components),
  // consecutive, become one field NAME of n components where the first one was.
  template <class Field>
  static void join_components(std::vector<Field>& fields, std::size_t count) {
    std::vector<Field> out;
    for (std::size_t i = 0; i < fields.size();) {
      const std::string& name = fields[i].name;
      std::size_t n = 0;
      if (name.size() > 3 && name.ends_with("[0]")) {
        const std::string base = name.substr(0, name.size() - 3);
        while (i + n < fields.size() && fields[i + n].components == 1 &&
               fields[i + n].name == base + "[" + std::to_string(n) + "]")
          ++n;
        if (n >= 2) {
          Field f = fields[i];
          f.name = base;
          f.components = static_cast<int>(n);
          f.values.assign(count * n, 0.0);
          for (std::size_t k = 0; k < n; ++k)
            for (std::size_t v = 0; v < count; ++v) f.values[v * n + k] = fields[i + k].values[v];
          out.push_back(std::move(f));
          i += n;
          continue;
        }
      }
      out.push_back(std::move(fields[i]));
      ++i;
    }
    fields = std::move(out);
  }

  // A cell array as read so far; `partial` when some piece with tets lacked it (then it is dropped).
  struct CellArray {
    CellField field;
    bool partial = false;
  };

  std::string path_;
  const ReadOptions& options_;
  ReadNotes& notes_;
  MeshData m_;
  bool indexed_ = false;
  std::unordered_map<std::array<double, 3>, VertId, PositionHash> by_position_;
  std::vector<std::pair<const Piece*, std::vector<VertId>>> volume_pieces_;
  std::set<std::string> unread_;
  std::vector<CellArray> cell_arrays_;
  bool own_ids_ = true;  // every material is a piece's own id (block, zone), not an array's value
};

}  // namespace


MeshData read_vtk_mesh(const std::string& path, const ReadOptions& options, ReadNotes* notes) {
  ReadNotes local;
  ReadNotes& n = notes ? *notes : local;
  n = {};
  std::optional<Kind> kind = kind_of_path(path);
  if (options.format == MeshFormat::kVtu) kind = Kind::kVtu;
  if (options.format && *options.format != MeshFormat::kVtu)
    throw InputError(path + ": read_vtk_mesh reads VTK formats; ReadOptions::format names another one");
  if (!kind) {
    if (path == "-") throw InputError("<stdin>: the input format must be given (--format vtu)");
    throw InputError(path + ": not a VTK format (expected .vtu, .pvtu, .vtk, .exo, .e, .ex2 or .cgns)");
  }
  if (path == "-" && *kind != Kind::kVtu)
    throw InputError("<stdin>: only .vtu can be read from standard input");
  if (path != "-") check_file(path, *kind);
  if (path != "-" && (*kind == Kind::kVtu || *kind == Kind::kPvtu)) check_xml_complete(path);

  vtkNew<VtkMessages> messages;
  QuietVtk quiet(messages);
  Source source;
  switch (*kind) {
    case Kind::kVtu:
    case Kind::kPvtu:
      source = read_xml(path, *kind, messages);
      break;
    case Kind::kLegacy:
      source = read_legacy(path, messages);
      break;
    case Kind::kExodus:
      source = read_exodus(path, messages);
      break;
    case Kind::kCgns:
      source = read_cgns(path, messages);
      break;
  }
  Converter converter(path == "-" ? "<stdin>" : path, options, n);
  return converter.convert(source);
}

MeshData read_any_mesh(const std::string& path, const ReadOptions& options, ReadNotes* notes) {
  const bool vtk = options.format ? *options.format == MeshFormat::kVtu : path != "-" && is_vtk_path(path);
  return vtk ? read_vtk_mesh(path, options, notes) : read_mesh(path, options, notes);
}

}  // namespace topotet

namespace topotet::io::vtk {

// A dataset in memory (a VTK filter's input) as one lone piece: the conversion of a .vtu without
// its companion file.
MeshData mesh_from_grid(vtkDataSet* grid, const std::string& name, const ReadOptions& options, ReadNotes* notes) {
  ReadNotes local;
  ReadNotes& n = notes ? *notes : local;
  n = {};
  if (!grid) throw InputError(name + ": no dataset");
  Source source;
  Piece p;
  p.data = grid;
  p.file = name;
  source.pieces.push_back(std::move(p));
  Converter converter(name, options, n);
  return converter.convert(source);
}

}  // namespace topotet::io::vtk
