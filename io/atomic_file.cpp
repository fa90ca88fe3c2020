#include "io/atomic_file.h"

#include <fcntl.h>
#include <limits.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <random>

#include "io/signal_safe_paths.h"
#include "topotet/error.h"
#include "topotet/io.h"

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

// Temporary files in progress, for remove_temporary_files() in a signal handler.
SignalSafePaths<64> g_temporaries;

bool starts_with(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

// The final target of a chain of symlinks (at most 40, like the kernel), or `path` itself.
// The last link may dangle: the target is then created.
std::string follow_symlinks(std::string path) {
  for (int hop = 0; hop < 40; ++hop) {
    struct stat st;
    if (::lstat(path.c_str(), &st) != 0 || !S_ISLNK(st.st_mode)) return path;
    std::error_code ec;
    const std::filesystem::path link = std::filesystem::read_symlink(path, ec);
    if (ec) return path;
    path = (link.is_absolute() ? link : std::filesystem::path(path).parent_path() / link).string();
  }
  throw InputError(path + ": too many levels of symbolic links");
}

// The descriptor to write straight through to, or -1 when `path` is an ordinary file target.
int open_direct(const std::string& path, const std::string& target) {
  if (path == "-" || path == "/dev/stdout" || path == "/dev/stderr") {
    const int fd = ::fcntl(path == "/dev/stderr" ? 2 : 1, F_DUPFD_CLOEXEC, 3);
    if (fd < 0) throw InputError(path + ": cannot write: " + std::strerror(errno));
    return fd;
  }
  struct stat st;
  const bool exists = ::stat(target.c_str(), &st) == 0;
  if (exists && S_ISDIR(st.st_mode)) throw InputError(path + ": cannot write: is a directory");
  const bool special = (exists && !S_ISREG(st.st_mode)) || starts_with(path, "/dev/") || starts_with(path, "/proc/") ||
                       starts_with(target, "/dev/") || starts_with(target, "/proc/");
  if (!special) return -1;
  // A FIFO blocks here until a reader opens it, as a shell redirection does.
  const int flags = O_WRONLY | O_CLOEXEC | (exists && S_ISREG(st.st_mode) ? O_TRUNC : 0);
  int fd;
  do {
    fd = ::open(path.c_str(), flags | (exists ? 0 : O_CREAT), 0666);
  } while (fd < 0 && errno == EINTR);
  if (fd < 0) throw InputError(path + ": cannot open: " + std::strerror(errno));
  return fd;
}

}  // namespace

bool is_direct_output(const std::string& path) {
  if (path == "-" || starts_with(path, "/dev/") || starts_with(path, "/proc/")) return true;
  const std::string target = follow_symlinks(path);
  struct stat st;
  return starts_with(target, "/dev/") || starts_with(target, "/proc/") ||
         (::stat(target.c_str(), &st) == 0 && !S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode));
}

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)) {
  target_ = path_ == "-" ? path_ : follow_symlinks(path_);
  fd_ = open_direct(path_, target_);
  if (fd_ >= 0) {
    direct_ = true;
    buf_.resize(kBufferSize);
    return;
  }
  // O_EXCL on a fresh random name instead of mkstemp: mkstemp creates mode 0600, while a plain
  // open() with 0666 lets the umask decide, as for any ordinary file.
  for (int attempt = 0; attempt < 100; ++attempt) {
    temp_path_ = target_ + ".tmp-" + random_suffix();
    fd_ = ::open(temp_path_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd_ >= 0) break;
    if (errno != EEXIST) {
      const int err = errno;
      temp_path_.clear();
      throw InputError(path_ + ": cannot create file: " + std::strerror(err));
    }
  }
  if (fd_ < 0) throw InputError(path_ + ": cannot create a unique temporary file");
  registry_slot_ = g_temporaries.add(temp_path_);
  buf_.resize(kBufferSize);
}

AtomicFile::~AtomicFile() {
  if (fd_ >= 0) ::close(fd_);
  if (!committed_) remove_temp();
  g_temporaries.remove(registry_slot_);
}

void AtomicFile::remove_temp() noexcept {
  if (!temp_path_.empty()) ::unlink(temp_path_.c_str());
  temp_path_.clear();
  g_temporaries.remove(registry_slot_);
  registry_slot_ = -1;
}

void AtomicFile::fail(const std::string& what, int err) {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  remove_temp();
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
    remove_temp();
    throw InputError(path_ + ": close failed: " + std::strerror(err));
  }
}

void AtomicFile::commit() {
  if (committed_) return;
  if (direct_) {
    close();
    committed_ = true;
    return;
  }
  if (temp_path_.empty()) throw InputError(path_ + ": commit after a failed write");
  close();
  std::error_code ec;
  std::filesystem::rename(temp_path_, target_, ec);
  if (ec) {
    remove_temp();
    throw InputError(path_ + ": cannot replace file: " + ec.message());
  }
  temp_path_.clear();
  g_temporaries.remove(registry_slot_);
  registry_slot_ = -1;
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

namespace topotet {

void remove_temporary_files() noexcept {
  io::g_temporaries.for_each([](const char* path) { ::unlink(path); });
}

void write_text_file(const std::string& path, std::string_view text) {
  io::AtomicFile f(path);
  f.put(text);
  f.commit();
}

}  // namespace topotet
