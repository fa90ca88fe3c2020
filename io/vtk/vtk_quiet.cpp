#include "io/vtk/vtk_quiet.h"

#include <vtkAlgorithm.h>
#include <vtkExecutive.h>
#include <vtkLogger.h>
#include <vtkObjectFactory.h>
#include <vtkOutputWindow.h>
#include <vtkSmartPointer.h>
#include <vtkXMLReader.h>

#include <cstring>

namespace topotet::io::vtk {
namespace {

// VTK's text: "ERROR: In ./IO/XML/vtkXMLReader.cxx, line 306\nvtkXMLUnstructuredGridReader
// (0x55...): Error opening file x.vtu\n\n". Keeps the message, on one line.
std::string clean(const char* text) {
  std::string s = text ? text : "";
  if (s.rfind("ERROR: In ", 0) == 0 || s.rfind("Warning: In ", 0) == 0 || s.rfind("Generic Warning: In ", 0) == 0) {
    const std::size_t nl = s.find('\n');
    s = nl == std::string::npos ? std::string() : s.substr(nl + 1);
  }
  // "ClassName (0x1234): " prefix
  const std::size_t open = s.find(" (0x");
  if (open != std::string::npos && open < 80 && s.find(' ') == open) {
    const std::size_t close = s.find("): ", open);
    if (close != std::string::npos) s = s.substr(close + 3);
  }
  std::string out;
  for (char c : s) {
    if (c == '\n' || c == '\r' || c == '\t') c = ' ';
    if (c == ' ' && (out.empty() || out.back() == ' ')) continue;
    out += c;
  }
  while (!out.empty() && out.back() == ' ') out.pop_back();
  return out;
}

// The output window while a call runs: everything goes to the call's VtkMessages.
class CaptureWindow final : public vtkOutputWindow {
 public:
  static CaptureWindow* New();
  vtkTypeMacro(CaptureWindow, vtkOutputWindow)
  VtkMessages* sink = nullptr;
  void DisplayText(const char*) override {}
  void DisplayErrorText(const char* text) override {
    if (sink) sink->add(true, text);
  }
  void DisplayWarningText(const char*) override {}
  void DisplayGenericWarningText(const char*) override {}
  void DisplayDebugText(const char*) override {}
};
vtkStandardNewMacro(CaptureWindow)

std::recursive_mutex& vtk_mutex() {
  static std::recursive_mutex m;
  return m;
}

}  // namespace

void VtkMessages::Execute(vtkObject*, unsigned long event, void* data) {
  add(event == vtkCommand::ErrorEvent, static_cast<const char*>(data));
}

void VtkMessages::add(bool error, const char* text) {
  if (!error) return;  // warnings are VTK's remarks; what matters is checked on the data itself
  std::string s = clean(text);
  if (!s.empty()) errors_.push_back(std::move(s));
}

void VtkMessages::watch_object(vtkObject* object) {
  if (!object) return;
  object->AddObserver(vtkCommand::ErrorEvent, this);
  object->AddObserver(vtkCommand::WarningEvent, this);
}

void VtkMessages::watch(vtkAlgorithm* algorithm) {
  watch_object(algorithm);
  watch_object(algorithm->GetExecutive());
  if (auto* xml = vtkXMLReader::SafeDownCast(algorithm)) {
    xml->SetReaderErrorObserver(this);
    xml->SetParserErrorObserver(this);
  }
}

std::string VtkMessages::first_error() const {
  // The executive's "Algorithm ... returned failure for request" only repeats that a reader failed.
  for (const std::string& e : errors_)
    if (e.rfind("Algorithm ", 0) != 0) return e;
  return errors_.empty() ? std::string() : errors_.front();
}

QuietVtk::QuietVtk(VtkMessages* sink) : lock_(vtk_mutex()) {
  previous_window_ = vtkOutputWindow::GetInstance();
  previous_window_->Register(nullptr);  // SetInstance releases the current one
  vtkSmartPointer<CaptureWindow> window = vtkSmartPointer<CaptureWindow>::New();
  window->sink = sink;
  vtkOutputWindow::SetInstance(window);
  // The logger has no getter for its stderr level: the cutoff is that level unless a log file
  // or callback asks for more.
  previous_verbosity_ = static_cast<int>(vtkLogger::GetCurrentVerbosityCutoff());
  vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);
}

QuietVtk::~QuietVtk() {
  vtkLogger::SetStderrVerbosity(static_cast<vtkLogger::Verbosity>(previous_verbosity_));
  vtkOutputWindow::SetInstance(previous_window_);
  previous_window_->UnRegister(nullptr);
}

}  // namespace topotet::io::vtk
