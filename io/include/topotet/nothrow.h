// Non-throwing forms of reading, writing and building, for callers that do not use exceptions
// (the C API is built on them). Each returns kOk, or kInvalidInput with the InputError's one-line
// message (file and line or element at fault), kOutOfMemory, or kInternalError; `out` is
// unspecified unless kOk is returned.
#pragma once

#include <string>

#include "topotet/io.h"
#include "topotet/simplify.h"
#include "topotet/tet_mesh.h"

namespace topotet {

Status try_read_mesh(const std::string& path, MeshData& out, std::string& message) noexcept;
Status try_write_mesh(const std::string& path, const MeshData& mesh, std::string& message,
                      const WriteOptions& options = {}) noexcept;
// num_threads bounds the build like SimplifyOptions::num_threads (0 = the caller's arena).
Status try_build_tet_mesh(const MeshData& data, TetMesh& out, std::string& message, const BuildOptions& options = {},
                          int num_threads = 0) noexcept;

}  // namespace topotet
