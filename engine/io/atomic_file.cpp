#include "io/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <random>

#include "topotet/error.h"

namespace topotet::io {
namespace {

constexpr std::size_t kBufferSize = std::size_t{1} << 20;

// Random suffix: unique across threads and processes writing next to the same target.
std::string random_suffix() {
  static std::atomic<std::uint64_t> counter{0};
  thread_local std::mt19937_64 rng{std::random_device{}() ^
                                   static_cast<std::uint64_t>(std::chrono::steady_clock::now().time_since_epoch().count())};
  const std::uint64_t x = rng() ^ (counter.fetch_add(1) * 0x9E3779B97F4A7C15ull) ^ static_cast<std::uint64_t>(::getpid());
  static const char* hex = "0123456789abcdef";
  std::string s(8, '0');
  for (int i = 0; i < 8; ++i) s[static_cast<std::size_t>(i)] = hex[(x >> (4 * i)) & 15];
  return s;
}

}  // namespace

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)) {
  // O_EXCL on a fresh random name instead of mkstemp: mkstemp creates mode 0600, while a plain
  // open() with 0666 lets the umask decide, as for any ordinary file.
  for (int attempt = 0; attempt < 100; ++attempt) {
    temp_path_ = path_ + ".tmp-" + random_suffix();
    fd_ = ::open(temp_path_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd_ >= 0) break;
    if (errno != EEXIST) {
      const int err = errno;
      temp_path_.clear();
      throw InputError(path_ + ": cannot create file: " + std::strerror(err));
    }
  }
  if (fd_ < 0) throw InputError(path_ + ": cannot create a unique temporary file");
  buf_.resize(kBufferSize);
}

AtomicFile::~AtomicFile() {
  if (fd_ >= 0) ::close(fd_);
  if (!committed_ && !temp_path_.empty()) ::unlink(temp_path_.c_str());
}

void AtomicFile::fail(const std::string& what, int err) {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  ::unlink(temp_path_.c_str());
  temp_path_.clear();
  throw InputError(path_ + ": " + what + ": " + std::strerror(err));
}

void AtomicFile::flush() {
  if (fd_ < 0) throw InputError(path_ + ": write after close");
  std::size_t done = 0;
  while (done < len_) {
    const ssize_t n = ::write(fd_, buf_.data() + done, len_ - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      fail("write failed", errno);
    }
    done += static_cast<std::size_t>(n);
  }
  len_ = 0;
}

void AtomicFile::put_slow(const char* data, std::size_t n) {
  while (n > 0) {
    if (len_ == buf_.size()) flush();
    const std::size_t k = std::min(n, buf_.size() - len_);
    std::memcpy(buf_.data() + len_, data, k);
    len_ += k;
    data += k;
    n -= k;
  }
}

void AtomicFile::close() {
  if (fd_ < 0) return;
  flush();
  const int fd = fd_;
  fd_ = -1;
  // close() reports deferred write errors (e.g. on network file systems): check it.
  if (::close(fd) != 0) {
    const int err = errno;
    ::unlink(temp_path_.c_str());
    temp_path_.clear();
    throw InputError(path_ + ": close failed: " + std::strerror(err));
  }
}

void AtomicFile::commit() {
  if (committed_) return;
  if (temp_path_.empty()) throw InputError(path_ + ": commit after a failed write");
  close();
  std::error_code ec;
  std::filesystem::rename(temp_path_, path_, ec);
  if (ec) {
    ::unlink(temp_path_.c_str());
    temp_path_.clear();
    throw InputError(path_ + ": cannot replace file: " + ec.message());
  }
  committed_ = true;
}

void commit_all(std::initializer_list<AtomicFile*> files) {
  for (AtomicFile* f : files) f->close();
  // A rename fails in practice when the target is a directory: check every target first, so
  // that one bad target leaves none of the files replaced.
  for (AtomicFile* f : files) {
    std::error_code ec;
    if (std::filesystem::is_directory(f->path(), ec)) throw InputError(f->path() + ": cannot replace file: is a directory");
  }
  for (AtomicFile* f : files) f->commit();
}

}  // namespace topotet::io
