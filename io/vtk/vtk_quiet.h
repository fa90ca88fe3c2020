// Private to io/vtk/: VTK's messages captured instead of printed, for the duration of one call.
//
// VTK reports errors in three ways: an ErrorEvent on the object when it has an observer, else
// its logger (loguru, to stderr) and then the global vtkOutputWindow. VtkMessages observes the
// objects we create (reader, executive, XML parser); QuietVtk catches the rest (VTK objects we
// cannot reach, e.g. the Exodus reader's internals) by swapping the output window for a
// capturing one and turning the logger's stderr output off, and restores both when it goes out
// of scope. The swap is process-wide: QuietVtk holds one mutex, so the calls of topotet/io_vtk.h
// are serialized (VTK's readers are not meant to be run concurrently with shared output anyway).
#pragma once

#include <mutex>
#include <string>
#include <vector>

#include <vtkCommand.h>

class vtkAlgorithm;
class vtkObject;
class vtkOutputWindow;

namespace topotet::io::vtk {

// Collects the text of the ErrorEvent / WarningEvent of every object it observes.
class VtkMessages final : public vtkCommand {
 public:
  static VtkMessages* New() { return new VtkMessages; }
  void Execute(vtkObject* caller, unsigned long event, void* data) override;
  void add(bool error, const char* text);

  // Observes `algorithm` and its executive (and, for XML readers, their parser).
  void watch(vtkAlgorithm* algorithm);
  void watch_object(vtkObject* object);

  bool has_errors() const { return !errors_.empty(); }
  // The most telling error, cleaned of VTK's "ERROR: In file, line N / Class (0x...): " prefix;
  // empty when there is none.
  std::string first_error() const;
  void clear() { errors_.clear(); }

 private:
  std::vector<std::string> errors_;
};

class QuietVtk {
 public:
  explicit QuietVtk(VtkMessages* sink);
  ~QuietVtk();
  QuietVtk(const QuietVtk&) = delete;
  QuietVtk& operator=(const QuietVtk&) = delete;

 private:
  std::unique_lock<std::recursive_mutex> lock_;
  vtkOutputWindow* previous_window_ = nullptr;
  int previous_verbosity_ = 0;
};

}  // namespace topotet::io::vtk
