// The VTK formats for the command-line tools, as a module loaded only when a VTK path is read or
// written (cli/vtk_loader.cpp). Linking VTK into the tools themselves cost every run ~24 MB of
// resident memory at start-up (78 shared libraries loaded and relocated), +24 bytes per tet at 1M
// tets, whatever the file format. The functions have C linkage and let no exception out: the
// loader turns the returned message back into the exception.
#include <exception>
#include <string>

#include "topotet/error.h"
#include "topotet/io_vtk.h"

namespace {

// 0: done; 1: InputError (message in *error); 2: another error (message in *error).
template <class F>
int guarded(std::string* error, F&& f) {
  try {
    f();
    return 0;
  } catch (const topotet::InputError& e) {
    *error = e.what();
    return 1;
  } catch (const std::exception& e) {
    *error = e.what();
    return 2;
  } catch (...) {
    *error = "unknown error in the VTK component";
    return 2;
  }
}

}  // namespace

extern "C" __attribute__((visibility("default"))) int topotet_vtk_read(const std::string* path,
                                                                        const topotet::ReadOptions* options,
                                                                        topotet::ReadNotes* notes,
                                                                        topotet::MeshData* out, std::string* error) {
  return guarded(error, [&] { *out = topotet::read_vtk_mesh(*path, *options, notes); });
}

extern "C" __attribute__((visibility("default"))) int topotet_vtk_write_exodus(const std::string* path,
                                                                                const topotet::MeshData* mesh,
                                                                                std::string* error) {
  return guarded(error, [&] { topotet::write_exodus(*path, *mesh); });
}
