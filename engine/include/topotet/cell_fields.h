// Per-tet fields (MeshData::cell_fields) carried from a mesh onto its simplified version.
//
// simplify() works on a TetMesh, which holds no cell data; the remap is a separate call made with
// the original MeshData once the simplified one exists (TetMesh::to_mesh_data, a hierarchy level,
// any engine's output: it only looks at the geometry):
//
//   MeshData input = read_mesh("in.vtu");            // input.cell_fields: density, region, mass
//   TetMesh mesh = build_tet_mesh(input);
//   simplify(mesh, options);
//   MeshData output = mesh.to_mesh_data();
//   CellRemapOptions remap;
//   remap.extensive = {"mass"};
//   remap_cell_fields(input, output, remap);          // output.cell_fields: the same three arrays
//
// How (docs/formats.md#cell-data): a conservative remap by exact overlap volume. Every new tet is
// intersected with the original tets of the same material that its bounding box meets (a uniform
// grid over the original tets; the intersection of two tets is one clipped by the other's four
// planes), and each array gets its rule (mesh_data.h, CellFieldKind):
//  - intensive:   sum(overlap * value) / sum(overlap)               (volume-weighted average)
//  - categorical: the value with the largest sum of overlaps, ties to the smaller value
//  - extensive:   sum(value_i * overlap_i / covered_i) where covered_i is the part of original
//                 tet i that new tets of its material cover, so every original tet's amount is
//                 shared out completely and the total is conserved to rounding.
// Near a surface that moved (by at most the tolerance), a new tet may overlap no original tet of
// its material (intensive and categorical: it takes the value of the original tet of its material
// whose centroid is nearest its own), and an original tet may be covered by none of its material
// (extensive: its amount goes to the new tet of its material whose centroid is nearest).
// Multi-component arrays are remapped component by component.
//
// Deterministic: the output is bit-identical for every thread count (each new tet sums its
// overlaps in the order of the original tets' ids). Runs in the caller's thread limit
// (topotet/threads.h).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "topotet/mesh_data.h"

namespace topotet {

struct CellRemapOptions {
  // Arrays to conserve as sums (their kind becomes kExtensive); `--extensive NAME` on the CLI.
  std::vector<std::string> extensive;
  // Arrays to treat as labels even when the file stored them as reals (.sol, Gmsh: every value is
  // a real there); `--categorical NAME` on the CLI.
  std::vector<std::string> categorical;
};

struct CellRemapReport {
  std::uint64_t overlap_pairs = 0;         // (new tet, original tet) pairs with a positive overlap
  std::uint64_t nearest_new_tets = 0;      // new tets with no overlap of their material: nearest original
  std::uint64_t nearest_original_tets = 0; // original tets covered by no new tet of their material
  double covered_volume_fraction = 0;      // sum of overlaps / volume of the original tets
  double seconds = 0;
};

// Fills simplified.cell_fields (replacing what it held) with every array of original.cell_fields,
// in the same order, with the kinds `options` give. Throws InputError when an array's size does not
// match original.tets (the message names the array) or when `options` names an array that
// original does not have. Nothing to do (and no cost) when original has no cell fields.
CellRemapReport remap_cell_fields(const MeshData& original, MeshData& simplified, const CellRemapOptions& options = {});

// The kinds `options` give to `fields` (used by remap_cell_fields; the CLI reports them before the run).
void apply_cell_kinds(std::vector<CellField>& fields, const CellRemapOptions& options);

// The name of a kind, as the reports and docs spell it: "intensive", "categorical", "extensive".
const char* cell_kind_name(CellFieldKind kind);

}  // namespace topotet
