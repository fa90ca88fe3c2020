// vtkTopotetSimplify (vtkTopotetSimplify.h): the grid becomes MeshData (io/vtk/vtk_grid.h), the
// library simplifies it, the checker compares, and the result goes back into a grid.
#include "vtkTopotetSimplify.h"

#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
#include <vtkInformationVector.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkStringArray.h>
#include <vtkUnstructuredGrid.h>

#include <exception>
#include <sstream>
#include <string>

#include "io/vtk/vtk_grid.h"
#include "topotet/cell_fields.h"
#include "topotet/io.h"
#include "topotet/metrics/topology.h"
#include "topotet/simplify.h"
#include "topotet/tet_mesh.h"

vtkStandardNewMacro(vtkTopotetSimplify)

namespace {

// Above this many tets the checker runs in its fast mode (Euler characteristics and components),
// as `topotet simplify` does (cli/simplify.cpp, kFastCheckTets): the full Betti numbers of a huge
// mesh would cost more than the simplification.
constexpr std::size_t kFastCheckTets = 2'000'000;

void add_string(vtkFieldData* fd, const char* name, const std::string& value) {
  vtkNew<vtkStringArray> a;
  a->SetName(name);
  a->InsertNextValue(value);
  fd->AddArray(a);
}

void add_pair(vtkFieldData* fd, const char* name, std::uint64_t before, std::uint64_t after) {
  vtkNew<vtkIdTypeArray> a;
  a->SetName(name);
  a->InsertNextValue(static_cast<vtkIdType>(before));
  a->InsertNextValue(static_cast<vtkIdType>(after));
  fd->AddArray(a);
}

}  // namespace

vtkTopotetSimplify::vtkTopotetSimplify() {
  // The library's defaults, read from its own structs (never restated here).
  const topotet::SimplifyOptions defaults;
  this->TargetRatio = defaults.target_vertex_ratio;
  this->TargetVertices = static_cast<vtkIdType>(defaults.target_vertices);
  this->ToleranceRel = defaults.tolerance_rel;
  this->Tolerance = defaults.tolerance;
  this->FeatureAngle = defaults.feature_angle;
  this->MinQuality = defaults.min_quality;
  this->MinDihedral = defaults.min_dihedral;
  this->RelaxLimits = defaults.relax_tolerance && defaults.relax_quality && defaults.relax_features;
  this->MaxCost = defaults.max_cost;
  this->MaxFieldErrorRel = defaults.max_field_error_rel;
  this->Optimize = static_cast<int>(defaults.optimize);
  this->Sequential = defaults.engine == topotet::Engine::kSequential;
  this->NumberOfThreads = defaults.num_threads;
  const topotet::ReadOptions read_defaults;
  this->MaterialArrayName = read_defaults.material_array;
  this->TetsOnly = read_defaults.tets_only;
  this->Verify = true;
}

void vtkTopotetSimplify::SetMaterialArrayName(const char* name) {
  const std::string value = name ? name : "";
  if (value == this->MaterialArrayName) return;
  this->MaterialArrayName = value;
  this->Modified();
}

int vtkTopotetSimplify::RequestData(vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector) {
  vtkUnstructuredGrid* input = vtkUnstructuredGrid::GetData(inputVector[0]);
  vtkUnstructuredGrid* output = vtkUnstructuredGrid::GetData(outputVector);
  output->Initialize();  // an error leaves it empty, not holding the previous run's mesh
  try {
    topotet::ReadOptions read;
    read.material_array = this->MaterialArrayName;
    read.tets_only = this->TetsOnly;
    topotet::ReadNotes read_notes;
    topotet::MeshData before = topotet::io::vtk::mesh_from_grid(input, "input", read, &read_notes);
    this->UpdateProgress(0.05);

    // As the CLI builds: substructures that are not faces or edges of a tet describe nothing the
    // simplified mesh could carry; they are left out, and of the checker's reference too.
    topotet::BuildOptions build;
    build.skip_detached_substructures = true;
    topotet::BuildNotes build_notes;
    topotet::TetMesh mesh = topotet::build_tet_mesh(before, build, &build_notes);
    topotet::drop_noted_substructures(before, build_notes);

    topotet::SimplifyOptions options;
    options.target_vertex_ratio = this->TargetRatio;
    options.target_vertices = this->TargetVertices > 0 ? static_cast<std::uint64_t>(this->TargetVertices) : 0;
    options.tolerance_rel = this->ToleranceRel;
    options.tolerance = this->Tolerance;
    options.feature_angle = this->FeatureAngle;
    options.min_quality = this->MinQuality;
    options.min_dihedral = this->MinDihedral;
    options.relax_tolerance = options.relax_quality = options.relax_features = this->RelaxLimits != 0;
    options.max_cost = this->MaxCost;
    options.max_field_error_rel = this->MaxFieldErrorRel;
    options.optimize = static_cast<topotet::Optimize>(this->Optimize);
    options.engine = this->Sequential ? topotet::Engine::kSequential : topotet::Engine::kParallel;
    options.num_threads = this->NumberOfThreads;
    // No on_progress: it may run on a worker thread, and VTK's progress observers (ParaView's
    // progress bar) expect the thread that runs the pipeline.
    const topotet::Report report = topotet::simplify(mesh, options);
    if (report.status != topotet::Status::kOk && report.status != topotet::Status::kStoppedEarly) {
      vtkErrorMacro(<< "topotet: " << topotet::to_string(report.status) << ": " << report.message);
      return 0;
    }
    this->UpdateProgress(0.8);
    topotet::MeshData after = mesh.to_mesh_data();
    // The input's numeric cell arrays onto the output's tets (integer arrays as labels, the others
    // averaged by volume: topotet/cell_fields.h).
    topotet::remap_cell_fields(before, after);

    std::string verdict = "not checked", differences;
    if (this->Verify) {
      topotet::TopologyOptions check;
      check.fast = before.tets.size() > kFastCheckTets;
      const bool same = topotet::same_topology(topotet::compute_topology(before, check),
                                               topotet::compute_topology(after, check), &differences);
      verdict = same ? "PASS" : "FAIL";
    }

    output->ShallowCopy(topotet::io::vtk::grid_from_mesh(after, read_notes.material_array));
    std::ostringstream summary;
    summary << "vertices " << report.vertices_before << " -> " << report.vertices_after << ", tets "
            << report.tets_before << " -> " << report.tets_after << ", tolerance " << report.tolerance
            << " (mesh units; 0 = off), " << report.seconds << " s, " << topotet::to_string(report.status);
    if (!report.message.empty()) summary << ": " << report.message;
    if (!report.stop.suggestion.empty()) summary << " (" << report.stop.suggestion << ")";
    vtkFieldData* fd = output->GetFieldData();
    add_string(fd, "topotet_status", topotet::to_string(report.status));
    add_string(fd, "topotet_topology", verdict);
    if (!differences.empty()) add_string(fd, "topotet_topology_differences", differences);
    add_string(fd, "topotet_summary", summary.str());
    add_pair(fd, "topotet_vertices", report.vertices_before, report.vertices_after);
    add_pair(fd, "topotet_tets", report.tets_before, report.tets_after);
    vtkDebugMacro(<< "topotet: " << summary.str() << "; topology " << verdict);
    if (verdict == "FAIL") vtkWarningMacro(<< "topotet: the topology checker found a difference:\n" << differences);
    return 1;
  } catch (const std::exception& e) {
    // InputError from the conversion or the build (the message names the cell or vertex),
    // std::bad_alloc; simplify() itself never throws.
    output->Initialize();
    vtkErrorMacro(<< "topotet: " << e.what());
    return 0;
  }
}

void vtkTopotetSimplify::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "TargetRatio: " << this->TargetRatio << "\n"
     << indent << "TargetVertices: " << this->TargetVertices << "\n"
     << indent << "ToleranceRel: " << this->ToleranceRel << "\n"
     << indent << "Tolerance: " << this->Tolerance << "\n"
     << indent << "FeatureAngle: " << this->FeatureAngle << "\n"
     << indent << "MinQuality: " << this->MinQuality << "\n"
     << indent << "MinDihedral: " << this->MinDihedral << "\n"
     << indent << "RelaxLimits: " << this->RelaxLimits << "\n"
     << indent << "MaxCost: " << this->MaxCost << "\n"
     << indent << "MaxFieldErrorRel: " << this->MaxFieldErrorRel << "\n"
     << indent << "Optimize: " << this->Optimize << "\n"
     << indent << "Sequential: " << this->Sequential << "\n"
     << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n"
     << indent << "MaterialArrayName: " << this->MaterialArrayName << "\n"
     << indent << "TetsOnly: " << this->TetsOnly << "\n"
     << indent << "Verify: " << this->Verify << "\n";
}
