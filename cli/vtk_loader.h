// The VTK formats in the command-line tools, through the module cli/vtk_plugin.cpp, loaded on the
// first VTK path (see there why it is not linked in). Only when the build has the VTK component
// (TOPOTET_HAVE_VTK).
#pragma once

#include <string>

#include "topotet/io.h"
#include "topotet/mesh_data.h"

namespace topotet::cli {

// topotet::read_vtk_mesh / write_exodus through the module. Throws InputError (the component's
// own, or "cannot load the VTK module" naming the path tried) or std::runtime_error.
MeshData read_vtk_via_module(const std::string& path, const ReadOptions& options, ReadNotes* notes);
void write_exodus_via_module(const std::string& path, const MeshData& mesh);

}  // namespace topotet::cli
