#include "scratch.h"

#include <fcntl.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <climits>
#include <cstring>

#include "io/signal_safe_paths.h"
#include "topotet/error.h"

namespace topotet::ooc {

namespace {

constexpr const char* kFixedNames[] = {"tets.bin", "vertex-fields.bin", "tet-fields.bin", "vertex-map.bin", "node-data.bin",
                                       "element-data.bin",
                                       // the hierarchy file's sections (hierarchy_spool.h)
                                       "tth-original.bin", "tth-u.bin", "tth-v.bin", "tth-u-before.bin", "tth-u-after.bin",
                                       "tth-v-position.bin", "tth-fields-before.bin", "tth-fields-after.bin", "tth-cost.bin",
                                       "tth-bound.bin", "tth-offsets.bin", "tth-parents.bin"};

// Live scratch folders, for remove_scratch_folders() in a signal handler; 32 bytes are kept for
// the names the handler appends.
io::SignalSafePaths<8> g_folders;

// "<folder>/<prefix><n>" into buf, without allocating (the handler's only formatting).
void format_numbered(char* buf, const char* folder, const char* prefix, std::uint32_t n) {
  std::size_t len = std::strlen(folder);
  std::memcpy(buf, folder, len);
  buf[len++] = '/';
  for (const char* p = prefix; *p; ++p) buf[len++] = *p;
  char digits[12];
  int d = 0;
  do {
    digits[d++] = static_cast<char>('0' + n % 10);
    n /= 10;
  } while (n != 0);
  while (d > 0) buf[len++] = digits[--d];
  buf[len] = '\0';
}

void remove_folder_contents(const char* folder) noexcept {
  char buf[PATH_MAX];
  for (std::uint32_t i = 0; i < kMaxPieces; ++i) {
    format_numbered(buf, folder, "piece-", i);
    ::unlink(buf);
    format_numbered(buf, folder, "bucket-", i);
    ::unlink(buf);
  }
  for (const char* name : kFixedNames) {
    const std::size_t len = std::strlen(folder);
    std::memcpy(buf, folder, len);
    buf[len] = '/';
    std::strcpy(buf + len + 1, name);
    ::unlink(buf);
  }
  ::rmdir(folder);
}

std::string errno_text() { return std::strerror(errno); }

}  // namespace

ScratchFolder::ScratchFolder(const std::string& parent) {
  std::string templ = (parent.empty() ? std::string(".") : parent) + "/.topotet-scratch-XXXXXX";
  if (::mkdtemp(templ.data()) == nullptr)
    throw InputError("cannot create a scratch folder in " + (parent.empty() ? std::string(".") : parent) + ": " +
                     errno_text() + " (choose another with --scratch DIR)");
  path_ = templ;
  slot_ = g_folders.add(path_, 32);
}

ScratchFolder::~ScratchFolder() {
  remove_folder_contents(path_.c_str());
  g_folders.remove(slot_);
}

std::string ScratchFolder::piece_path(std::uint32_t piece) const { return path_ + "/piece-" + std::to_string(piece); }
std::string ScratchFolder::bucket_path(std::uint32_t bucket) const {
  return path_ + "/bucket-" + std::to_string(bucket);
}
std::string ScratchFolder::file_path(const char* name) const {
  for (const char* fixed : kFixedNames)
    if (std::strcmp(fixed, name) == 0) return path_ + "/" + name;
  throw std::logic_error(std::string("scratch file name not in the fixed set: ") + name);
}

ScratchWriter::ScratchWriter(const std::string& path) : path_(path) {
  file_ = std::fopen(path.c_str(), "wb");
  if (file_ == nullptr) fail("cannot create");
  std::setvbuf(file_, nullptr, _IOFBF, 1 << 16);
}

ScratchWriter::~ScratchWriter() {
  if (file_ != nullptr) std::fclose(file_);
}

void throw_scratch_error(const std::string& path, const char* what) {
  std::string why = errno_text();
  if (errno == ENOSPC) why = "no space left on the device (choose another folder with --scratch DIR)";
  if (errno == EFBIG) why = "file size limit exceeded (ulimit -f)";
  const std::string::size_type slash = path.rfind('/');
  throw InputError("scratch folder " + path.substr(0, slash) + ": " + what + " " + path.substr(slash + 1) + ": " + why);
}

void ScratchWriter::fail(const char* what) const { throw_scratch_error(path_, what); }

void ScratchWriter::write(const void* data, std::size_t bytes) {
  if (bytes == 0) return;
  if (std::fwrite(data, 1, bytes, file_) != bytes) fail("cannot write");
  bytes_ += bytes;
}

void ScratchWriter::close() {
  if (file_ == nullptr) return;
  const bool flushed = std::fflush(file_) == 0;
  const int saved = errno;
  const bool closed = std::fclose(file_) == 0;
  file_ = nullptr;
  if (!flushed || !closed) {
    errno = flushed ? errno : saved;
    fail("cannot write");
  }
}

ScratchFile::ScratchFile(const std::string& path) : path_(path) {
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
  if (fd_ < 0) throw_scratch_error(path_, "cannot create");
}

ScratchFile::~ScratchFile() {
  if (fd_ >= 0) ::close(fd_);
}

void ScratchFile::resize(std::uint64_t bytes) {
  if (::ftruncate(fd_, static_cast<off_t>(bytes)) != 0) throw_scratch_error(path_, "cannot size");
}

void ScratchFile::write_at(const void* data, std::size_t bytes, std::uint64_t offset) {
  const ssize_t wrote = ::pwrite(fd_, data, bytes, static_cast<off_t>(offset));
  if (wrote == static_cast<ssize_t>(bytes)) return;
  if (wrote >= 0) errno = ENOSPC;  // a short write: the disk filled up
  throw_scratch_error(path_, "cannot write");
}

void ScratchFile::read_at(void* data, std::size_t bytes, std::uint64_t offset) const {
  if (::pread(fd_, data, bytes, static_cast<off_t>(offset)) != static_cast<ssize_t>(bytes)) throw_scratch_error(path_, "cannot read");
}

ScratchReader::ScratchReader(const std::string& path) : path_(path) {
  file_ = std::fopen(path.c_str(), "rb");
  if (file_ == nullptr) throw InputError("scratch file " + path + ": cannot open: " + errno_text());
  std::setvbuf(file_, nullptr, _IOFBF, 1 << 16);
}

ScratchReader::~ScratchReader() {
  if (file_ != nullptr) std::fclose(file_);
}

void ScratchReader::read(void* data, std::size_t bytes) {
  if (bytes != 0 && std::fread(data, 1, bytes, file_) != bytes)
    throw InputError("scratch file " + path_ + ": truncated (was it changed while the run went on?)");
}

bool ScratchReader::try_read(void* data, std::size_t bytes) {
  const std::size_t got = std::fread(data, 1, bytes, file_);
  if (got == 0 && std::feof(file_)) return false;
  if (got != bytes) throw InputError("scratch file " + path_ + ": truncated (was it changed while the run went on?)");
  return true;
}

void remove_scratch_folders() noexcept {
  g_folders.for_each([](const char* path) { remove_folder_contents(path); });
}

}  // namespace topotet::ooc
