// VTK's Exodus II writer without its leak.
//
// VTK 9.1's vtkExodusIIWriter allocates two id maps (LocalNodeIdMap, LocalElementIdMap: an entry
// per node and element it looks up while writing side sets) and its destructor never frees them
// (still so in VTK's master): every Exodus file written leaks them. That matters to a simulation
// that writes a file per step, and the ASan job reports it. They are protected members, so this
// subclass frees them; it writes exactly what vtkExodusIIWriter writes. Internal to io/vtk/ (and
// its test, which writes "third-party" files with it).
#pragma once

#include <vtkExodusIIWriter.h>
#include <vtkObjectFactory.h>

namespace topotet::io::vtk {

class ExodusWriter : public vtkExodusIIWriter {
 public:
  static ExodusWriter* New() { VTK_STANDARD_NEW_BODY(ExodusWriter); }
  vtkTypeMacro(ExodusWriter, vtkExodusIIWriter)  // (the macro ends in a function body: no ";")

 protected:
  ExodusWriter() = default;
  ~ExodusWriter() override {
    delete LocalNodeIdMap;
    delete LocalElementIdMap;
    LocalNodeIdMap = nullptr;
    LocalElementIdMap = nullptr;
  }
};

}  // namespace topotet::io::vtk
