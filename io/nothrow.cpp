// The non-throwing forms (see topotet/nothrow.h): one catch block maps exceptions to statuses.
#include "topotet/nothrow.h"

#include <exception>
#include <new>

#include "topotet/error.h"
#include "topotet/threads.h"

namespace topotet {
namespace {

template <class F>
Status guarded(std::string& message, F&& body) noexcept {
  try {
    body();
    message.clear();
    return Status::kOk;
  } catch (const InputError& e) {
    message = e.what();
    return Status::kInvalidInput;
  } catch (const std::bad_alloc&) {
    message = "out of memory";
    return Status::kOutOfMemory;
  } catch (const std::exception& e) {
    message = std::string("internal error: ") + e.what();
    return Status::kInternalError;
  } catch (...) {
    message = "internal error: unknown exception";
    return Status::kInternalError;
  }
}

}  // namespace

Status try_read_mesh(const std::string& path, MeshData& out, std::string& message) noexcept {
  return guarded(message, [&] { out = read_mesh(path); });
}

Status try_write_mesh(const std::string& path, const MeshData& mesh, std::string& message,
                      const WriteOptions& options) noexcept {
  return guarded(message, [&] { write_mesh(path, mesh, options); });
}

Status try_build_tet_mesh(const MeshData& data, TetMesh& out, std::string& message, const BuildOptions& options,
                          int num_threads) noexcept {
  if (num_threads < 0) {
    message = "num_threads must be >= 0";
    return Status::kInvalidInput;
  }
  return guarded(message, [&] { run_with_thread_limit(num_threads, [&] { out = build_tet_mesh(data, options); }); });
}

}  // namespace topotet
