// A raw scalar volume as a tet mesh, for the field-accuracy benchmarks (bench_vtk_peer,
// raw_to_mesh): the Bucky ball of paper 001, table 7.1(a) (../shared/data/volume/Bucky.raw).
//
// The file holds nx*ny*nz unsigned bytes, x fastest (the cuda-samples layout). Every sample is a
// vertex at its integer lattice position (spacing 1: the cells have 6V = 1, far from VTK's
// absolute volume threshold, see bench_vtk_peer.cpp); every cube of 8 neighbouring samples is
// split into the 6 tets of the Kuhn paths around its main diagonal (generate/'s
// FreudenthalGrid), which makes the mesh conforming. One material (0), nothing listed, no pinned
// vertex; one scalar field named `field_name` holding the byte values as doubles.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "topotet/mesh_data.h"

namespace topotet::bench {

// dims = {0, 0, 0}: a cube, the side being the cube root of the file size. Throws InputError
// when the file cannot be read, its size is not nx*ny*nz, or a side is below 2.
MeshData read_raw_volume(const std::string& path, std::array<std::uint32_t, 3> dims = {0, 0, 0},
                         const std::string& field_name = "density");

// True for a path ending in ".raw".
bool is_raw_volume(const std::string& path);

}  // namespace topotet::bench
