// vtkTopotetSimplify: topotet's simplification as a VTK filter (ParaView: "Simplify
// (topology-preserving)", paraview/TopotetSimplify.xml).
//
// Input: a vtkUnstructuredGrid of tets, read as topotet reads a .vtu (docs/formats.md, "VTK
// formats"): the materials from an integer cell array (MaterialArrayName, or the first of
// "material", "gmsh:physical", "ObjectId", ...), listed surfaces from triangle cells and polylines
// from line cells (refs from the same array), pinned vertices from vertex cells, numeric point
// arrays as fields. Output: the simplified grid in the same form, the material array under the
// input's name, the fields as double arrays; other cell arrays are not carried.
//
// The topology of the mesh, of every material, interface, listed surface and polyline is kept
// (docs/guarantees.md). With Verify on (the default, as in `topotet simplify`), the independent
// checker compares input and output; the verdict and a summary go to the output's field data:
//   topotet_status    "ok" or "stopped_early" (topotet::to_string(Status))
//   topotet_topology  "PASS", "FAIL" or "not checked"; on FAIL also topotet_topology_differences
//   topotet_summary   one line: vertices and tets before -> after, tolerance, time, why it stopped
//   topotet_vertices, topotet_tets   [before, after]
// and to vtkDebugMacro. A failed verdict is also a warning. Bad input, or a library error, is a
// vtkErrorMacro and an empty output (RequestData returns 0).
//
// Every option starts at the library's default (topotet::SimplifyOptions{}, ReadOptions{}); the
// ParaView proxy reads these defaults back through information properties, so no default is
// written twice.
#ifndef vtkTopotetSimplify_h
#define vtkTopotetSimplify_h

#include <vtkUnstructuredGridAlgorithm.h>

#include <string>

#include "TopotetFiltersModule.h"  // TOPOTETFILTERS_EXPORT

class TOPOTETFILTERS_EXPORT vtkTopotetSimplify : public vtkUnstructuredGridAlgorithm {
 public:
  static vtkTopotetSimplify* New();
  vtkTypeMacro(vtkTopotetSimplify, vtkUnstructuredGridAlgorithm)
  void PrintSelf(ostream& os, vtkIndent indent) override;

  // Keep this fraction of the input vertices, in (0, 1] (SimplifyOptions::target_vertex_ratio).
  vtkSetMacro(TargetRatio, double);
  vtkGetMacro(TargetRatio, double);
  // Stop at this many vertices instead; 0 = use TargetRatio (SimplifyOptions::target_vertices).
  vtkSetMacro(TargetVertices, vtkIdType);
  vtkGetMacro(TargetVertices, vtkIdType);
  // Surfaces and polylines stay within ToleranceRel x the bounding box diagonal of the original
  // ones; 0 = off (SimplifyOptions::tolerance_rel).
  vtkSetMacro(ToleranceRel, double);
  vtkGetMacro(ToleranceRel, double);
  // The same in mesh units; wins over ToleranceRel when > 0 (SimplifyOptions::tolerance).
  vtkSetMacro(Tolerance, double);
  vtkGetMacro(Tolerance, double);
  // Surface edges turning by more than this many degrees are kept as feature curves; 180 = off
  // (SimplifyOptions::feature_angle).
  vtkSetMacro(FeatureAngle, double);
  vtkGetMacro(FeatureAngle, double);
  // Refuse collapses creating tets below this mean ratio (SimplifyOptions::min_quality).
  vtkSetMacro(MinQuality, double);
  vtkGetMacro(MinQuality, double);
  // Refuse collapses and optimisation steps creating tets with a dihedral angle below this, in
  // degrees, unless the tets they replace were already worse; 0 = off (SimplifyOptions::min_dihedral).
  vtkSetMacro(MinDihedral, double);
  vtkGetMacro(MinDihedral, double);
  // Where the default tolerance or quality floors would stop the run before its target, relax them
  // (H doubled, floors halved, feature curves dropped) and go on; off = hard limits
  // (SimplifyOptions::relax_tolerance, relax_quality and relax_features together).
  vtkSetMacro(RelaxLimits, vtkTypeBool);
  vtkGetMacro(RelaxLimits, vtkTypeBool);
  vtkBooleanMacro(RelaxLimits, vtkTypeBool);
  // Stop when the cheapest collapse costs more; 0 = no limit (SimplifyOptions::max_cost).
  vtkSetMacro(MaxCost, double);
  vtkGetMacro(MaxCost, double);
  // Keep every field within this fraction of its range at the original vertices; 0 = no limit
  // (SimplifyOptions::max_field_error_rel).
  vtkSetMacro(MaxFieldErrorRel, double);
  vtkGetMacro(MaxFieldErrorRel, double);
  // Mesh improvement after the collapses: 0 none, 1 light, 2 full (SimplifyOptions::optimize).
  vtkSetClampMacro(Optimize, int, 0, 2);
  vtkGetMacro(Optimize, int);
  // The sequential reference engine instead of the parallel one (SimplifyOptions::engine).
  vtkSetMacro(Sequential, vtkTypeBool);
  vtkGetMacro(Sequential, vtkTypeBool);
  vtkBooleanMacro(Sequential, vtkTypeBool);
  // Threads; 0 = all (SimplifyOptions::num_threads). The output is the same for every value.
  vtkSetMacro(NumberOfThreads, int);
  vtkGetMacro(NumberOfThreads, int);
  // The integer cell array with the materials; empty = the first default present
  // (ReadOptions::material_array).
  void SetMaterialArrayName(const char* name);
  const char* GetMaterialArrayName() const { return this->MaterialArrayName.c_str(); }
  // Leave hexahedra, prisms and pyramids out instead of refusing a mixed grid (ReadOptions::tets_only).
  vtkSetMacro(TetsOnly, vtkTypeBool);
  vtkGetMacro(TetsOnly, vtkTypeBool);
  vtkBooleanMacro(TetsOnly, vtkTypeBool);
  // Run the independent topology checker on input and output (`topotet simplify` does by default).
  vtkSetMacro(Verify, vtkTypeBool);
  vtkGetMacro(Verify, vtkTypeBool);
  vtkBooleanMacro(Verify, vtkTypeBool);

 protected:
  vtkTopotetSimplify();
  ~vtkTopotetSimplify() override = default;
  int RequestData(vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector) override;

 private:
  vtkTopotetSimplify(const vtkTopotetSimplify&) = delete;
  void operator=(const vtkTopotetSimplify&) = delete;

  double TargetRatio;
  vtkIdType TargetVertices;
  double ToleranceRel;
  double Tolerance;
  double FeatureAngle;
  double MinQuality;
  double MinDihedral;
  double MaxCost;
  double MaxFieldErrorRel;
  int Optimize;
  vtkTypeBool Sequential;
  vtkTypeBool RelaxLimits;
  int NumberOfThreads;
  std::string MaterialArrayName;
  vtkTypeBool TetsOnly;
  vtkTypeBool Verify;
};

#endif
