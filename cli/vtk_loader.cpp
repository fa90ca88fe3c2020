// Loads cli/vtk_plugin.cpp's module once, the first time a VTK format is read or written. It sits
// beside the executable in the build tree and in TOPOTET_VTK_MODULE_DIR (relative to the
// executable's folder) once installed.
#include "vtk_loader.h"

#include <dlfcn.h>
#include <unistd.h>

#include <climits>
#include <mutex>
#include <stdexcept>
#include <string>

#include "topotet/error.h"

namespace topotet::cli {
namespace {

constexpr const char* kModuleName = "topotet_vtk.so";

using ReadFn = int (*)(const std::string*, const ReadOptions*, ReadNotes*, MeshData*, std::string*);
using WriteFn = int (*)(const std::string*, const MeshData*, std::string*);

struct Module {
  ReadFn read = nullptr;
  WriteFn write = nullptr;
  std::string error;  // why it could not be loaded
};

std::string executable_folder() {
  char buffer[PATH_MAX];
  const ssize_t n = readlink("/proc/self/exe", buffer, sizeof buffer - 1);
  if (n <= 0) return ".";
  std::string path(buffer, static_cast<std::size_t>(n));
  const std::size_t slash = path.rfind('/');
  return slash == std::string::npos ? "." : path.substr(0, slash);
}

const Module& module() {
  static Module m;
  static std::once_flag once;
  std::call_once(once, [] {
    const std::string folder = executable_folder();
    std::string tried;
    for (const std::string& candidate :
         {folder + "/" + kModuleName, folder + "/" + TOPOTET_VTK_MODULE_DIR + "/" + kModuleName}) {
      void* handle = dlopen(candidate.c_str(), RTLD_NOW | RTLD_LOCAL);
      if (handle == nullptr) {
        const char* why = dlerror();
        tried += (tried.empty() ? "" : "; ") + (why != nullptr ? std::string(why) : candidate);
        continue;
      }
      m.read = reinterpret_cast<ReadFn>(dlsym(handle, "topotet_vtk_read"));
      m.write = reinterpret_cast<WriteFn>(dlsym(handle, "topotet_vtk_write_exodus"));
      if (m.read != nullptr && m.write != nullptr) return;  // kept loaded until exit
      tried += (tried.empty() ? "" : "; ") + candidate + ": not topotet's VTK module";
      m.read = nullptr;
      m.write = nullptr;
    }
    m.error = "cannot load topotet's VTK module (" + tried + ")";
  });
  return m;
}

void rethrow(int code, const std::string& message) {
  if (code == 1) throw InputError(message);
  throw std::runtime_error(message);
}

}  // namespace

MeshData read_vtk_via_module(const std::string& path, const ReadOptions& options, ReadNotes* notes) {
  const Module& m = module();
  if (m.read == nullptr) throw InputError(path + ": " + m.error);
  MeshData out;
  std::string error;
  if (const int code = m.read(&path, &options, notes, &out, &error); code != 0) rethrow(code, error);
  return out;
}

void write_exodus_via_module(const std::string& path, const MeshData& mesh) {
  const Module& m = module();
  if (m.write == nullptr) throw InputError(path + ": " + m.error);
  std::string error;
  if (const int code = m.write(&path, &mesh, &error); code != 0) rethrow(code, error);
}

}  // namespace topotet::cli
