// AtomicFile: a buffered output file that appears at its final path only when complete.
//
// Data goes to "<target>.tmp-XXXXXXXX" (unique, same folder, so the final rename stays on one file
// system and is atomic). commit() flushes, closes, checks every error and renames the temporary
// over the target. If anything fails, or the object is destroyed before commit(), the temporary
// file is removed, so a failed or interrupted write never leaves a partial file or litter. Errors
// are InputError naming the path. (No fsync: this protects against failed runs, not power loss.)
//
// The target is `path`, except:
//  - a symlink is followed to its final target (which may not exist yet): the target is replaced
//    atomically and the link stays a link;
//  - "-", /dev/stdout and /dev/stderr write straight to the process's stdout / stderr, and an
//    existing FIFO, character device or socket (or any path under /dev or /proc) is opened and
//    written straight through: renaming over such a path would replace it with a regular file.
//    is_direct() is then true and there is no temporary file (a failure mid-write cannot be undone).
// Temporary files in progress are registered so that remove_temporary_files() (topotet/io.h), from
// a signal handler, can delete them before the process exits.
//
// Numbers are formatted with std::to_chars: doubles in their shortest round-trip form, so a
// write -> read cycle reproduces every coordinate bit for bit.
#pragma once

#include <charconv>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

namespace topotet::io {

class AtomicFile {
 public:
  explicit AtomicFile(std::string path);  // creates the temporary file; throws InputError
  ~AtomicFile();                          // removes the temporary file unless committed
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  const std::string& path() const { return path_; }
  const std::string& temp_path() const { return temp_path_; }  // empty when is_direct()
  bool is_direct() const { return direct_; }

  void put(std::string_view s) {
    if (s.size() > buf_.size() - len_) return put_slow(s.data(), s.size());
    std::char_traits<char>::copy(buf_.data() + len_, s.data(), s.size());
    len_ += s.size();
  }
  void put(char c) {
    if (len_ == buf_.size()) flush();
    buf_[len_++] = c;
  }
  template <class Int>
  void put_int(Int v) {
    reserve(24);
    len_ = static_cast<std::size_t>(std::to_chars(buf_.data() + len_, buf_.data() + buf_.size(), v).ptr - buf_.data());
  }
  // Shortest representation that reads back to the same double.
  void put_double(double v) {
    reserve(32);
    len_ = static_cast<std::size_t>(std::to_chars(buf_.data() + len_, buf_.data() + buf_.size(), v).ptr - buf_.data());
  }
  // Raw bytes (binary formats); little-endian hosts only, like the formats we write.
  void put_bytes(const void* data, std::size_t n) { put_slow(static_cast<const char*>(data), n); }
  template <class T>
  void put_raw(const T& v) {
    put_bytes(&v, sizeof v);
  }

  // Flushes and closes the temporary file (checking errors) without renaming it yet; lets a
  // writer finish several files (.mesh + .sol) before making any of them visible.
  void close();
  // close() if needed, then rename over `path`.
  void commit();

 private:
  void reserve(std::size_t n) {
    if (buf_.size() - len_ < n) flush();
  }
  void put_slow(const char* data, std::size_t n);
  void flush();
  [[noreturn]] void fail(const std::string& what, int err);

  void remove_temp() noexcept;

  std::string path_;
  std::string target_;  // path_ with symlinks followed: what the rename replaces
  std::string temp_path_;
  int fd_ = -1;
  int registry_slot_ = -1;
  bool direct_ = false;
  bool committed_ = false;
  std::vector<char> buf_;
  std::size_t len_ = 0;
};

// Commits several files: closes all of them first (any error leaves none renamed), then renames.
void commit_all(std::initializer_list<AtomicFile*> files);

// True when AtomicFile(path) would write straight through (see above): such a path has no
// folder of its own to put companion files in.
bool is_direct_output(const std::string& path);

}  // namespace topotet::io
