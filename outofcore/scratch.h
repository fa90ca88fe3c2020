// The scratch folder of an out-of-core run: its segments' files live there between levels.
//
// ScratchFolder creates a fresh folder (mkdtemp "<parent>/.topotet-scratch-XXXXXX") and removes
// it, with everything in it, when destroyed: after a finished run and after a failed one (an
// exception unwinds through it). Files in it are named by the folder (piece_path, file_path) from
// a fixed set of names, so that remove_scratch_folders() can delete them from a signal handler
// without listing the folder (opendir allocates; a handler may only unlink, rmdir and write):
// `topotet` calls it on SIGINT/SIGTERM next to io's remove_temporary_files().
//
// Writes check every error: a full disk or a file-size limit is an InputError that names the
// scratch folder and says what ran out, never a truncated segment read back later.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace topotet::ooc {

// The most pieces a run may have at once (their names are fixed: see the file comment).
inline constexpr std::uint32_t kMaxPieces = 4096;

class ScratchFolder {
 public:
  // parent: an existing folder; the new folder is created inside it. Throws InputError.
  explicit ScratchFolder(const std::string& parent);
  ~ScratchFolder();
  ScratchFolder(const ScratchFolder&) = delete;
  ScratchFolder& operator=(const ScratchFolder&) = delete;

  const std::string& path() const { return path_; }
  std::string piece_path(std::uint32_t piece) const;    // piece < kMaxPieces
  std::string bucket_path(std::uint32_t bucket) const;  // the cut's per-segment tet buckets
  std::string file_path(const char* name) const;        // one of kFixedNames (scratch.cpp)

 private:
  std::string path_;
  int slot_ = -1;
};

// A binary file in the scratch folder written through a large buffer; close() (or the destructor,
// which cannot report) flushes. Every failure throws InputError naming the folder.
class ScratchWriter {
 public:
  explicit ScratchWriter(const std::string& path);
  ~ScratchWriter();
  ScratchWriter(const ScratchWriter&) = delete;
  ScratchWriter& operator=(const ScratchWriter&) = delete;
  void write(const void* data, std::size_t bytes);
  template <class T>
  void put(const T& value) {
    write(&value, sizeof value);
  }
  template <class T>
  void put_array(const std::vector<T>& v) {
    write(v.data(), v.size() * sizeof(T));
  }
  template <class T>
  void put_counted(const std::vector<T>& v) {  // its size (u64), then its elements
    put<std::uint64_t>(v.size());
    put_array(v);
  }
  void close();
  std::uint64_t bytes() const { return bytes_; }

 private:
  [[noreturn]] void fail(const char* what) const;
  std::string path_;
  std::FILE* file_ = nullptr;
  std::uint64_t bytes_ = 0;
};

// Reads what a ScratchWriter wrote; a short read (a file cut by someone else) throws InputError.
class ScratchReader {
 public:
  explicit ScratchReader(const std::string& path);
  ~ScratchReader();
  ScratchReader(const ScratchReader&) = delete;
  ScratchReader& operator=(const ScratchReader&) = delete;
  void read(void* data, std::size_t bytes);
  // false at a clean end of file (no byte of the record read).
  bool try_read(void* data, std::size_t bytes);
  template <class T>
  T get() {
    T value;
    read(&value, sizeof value);
    return value;
  }
  template <class T>
  void get_counted(std::vector<T>& v) {  // what put_counted wrote
    v.resize(get<std::uint64_t>());
    read(v.data(), v.size() * sizeof(T));
  }

 private:
  std::string path_;
  std::FILE* file_ = nullptr;
};

// A scratch file written and read in place (pwrite / pread): the vertex map and the field views,
// whose entries come in another order than they are read. Created empty; resize() extends it
// sparse (unwritten bytes read 0 and take no disk). Every failure throws InputError naming the folder.
class ScratchFile {
 public:
  explicit ScratchFile(const std::string& path);
  ~ScratchFile();
  ScratchFile(const ScratchFile&) = delete;
  ScratchFile& operator=(const ScratchFile&) = delete;
  void resize(std::uint64_t bytes);
  void write_at(const void* data, std::size_t bytes, std::uint64_t offset);
  void read_at(void* data, std::size_t bytes, std::uint64_t offset) const;

 private:
  std::string path_;
  int fd_ = -1;
};

// InputError "scratch folder DIR: WHAT NAME: why" for the errno of a failed call on `path` (a full
// disk and a file-size limit said in words).
[[noreturn]] void throw_scratch_error(const std::string& path, const char* what);

// Async-signal-safe: unlinks the fixed names in every live scratch folder and removes the folders.
void remove_scratch_folders() noexcept;

}  // namespace topotet::ooc
