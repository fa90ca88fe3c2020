#include "io/line_reader.h"

#include <fcntl.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "topotet/error.h"

namespace topotet::io {
namespace {

// Up to 4 MiB chunks: large enough that refills are rare and the per-chunk overhead is negligible,
// small enough to stay in L2/L3-friendly territory while a chunk is tokenized.
constexpr std::size_t kBufferSize = std::size_t{4} << 20;
constexpr std::size_t kMinBufferSize = std::size_t{64} << 10;  // also the longest token we accept
constexpr std::uint64_t kZlibBuffer = std::uint64_t{256} << 10;
// Deflate cannot expand by more than ~1032:1, which bounds the uncompressed size of a gzip file.
constexpr std::uint64_t kMaxDeflateRatio = 1032;

inline bool is_blank(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

inline bool is_space(char c) { return c == '\n' || is_blank(c); }

std::string printable(std::string_view tok) {
  // Error messages quote the offending token; keep them short and free of control bytes.
  std::string out;
  for (char c : tok.substr(0, 40)) {
    const auto u = static_cast<unsigned char>(c);
    out += (u >= 32 && u < 127) ? c : '?';
  }
  if (tok.size() > 40) out += "...";
  return out;
}

}  // namespace

LineReader::LineReader(const std::string& path) : path_(path == "-" ? "<stdin>" : path) {
  std::error_code ec;
  const bool is_stdin = path == "-";
  if (!is_stdin && std::filesystem::is_directory(path, ec)) throw InputError(path + ": cannot open: is a directory");
  const std::uint64_t size = is_stdin ? 0 : std::filesystem::file_size(path, ec);
  const bool size_known = !is_stdin && !ec;
  // Small files get small buffers: tests and fuzzing open thousands of tiny files.
  buf_.resize(kMinBufferSize);
  errno = 0;
  // stdin: a duplicate descriptor, so that gzclose leaves the process's stdin open.
  const int stdin_fd = is_stdin ? ::fcntl(0, F_DUPFD_CLOEXEC, 3) : -1;
  if (is_stdin && stdin_fd < 0) throw InputError(path_ + ": cannot open: " + std::strerror(errno));
  gzFile gz = is_stdin ? gzdopen(stdin_fd, "rb") : gzopen(path.c_str(), "rb");
  if (gz == nullptr) {
    if (stdin_fd >= 0) ::close(stdin_fd);
    throw InputError(path_ + ": cannot open: " + (errno != 0 ? std::strerror(errno) : "out of memory"));
  }
  gz_ = gz;
  // zlib's own input buffer; its default 8 KiB costs many read() calls on large files.
  gzbuffer(gz, static_cast<unsigned>(std::clamp<std::uint64_t>(size_known ? size : kZlibBuffer, 8192, kZlibBuffer)));
  try {
    refill();  // gzdirect() needs the first bytes to know whether the file is compressed
  } catch (...) {
    gzclose(gz);  // the destructor does not run when a constructor throws
    throw;
  }
  if (size_known) file_size_ = gzdirect(gz) ? size : std::max<std::uint64_t>(size, 1) * kMaxDeflateRatio;
  const std::uint64_t want = size_known ? file_size_ + 1 : kBufferSize;
  if (want > buf_.size()) buf_.resize(static_cast<std::size_t>(std::min<std::uint64_t>(want, kBufferSize)));
}

LineReader::~LineReader() {
  if (gz_ != nullptr) gzclose(static_cast<gzFile>(gz_));
}

bool LineReader::refill() {
  if (eof_) return false;
  if (pos_ > 0) {
    std::memmove(buf_.data(), buf_.data() + pos_, end_ - pos_);
    consumed_ += pos_;
    end_ -= pos_;
    pos_ = 0;
  }
  const std::size_t room = buf_.size() - end_;
  if (room == 0) return false;
  const int got = gzread(static_cast<gzFile>(gz_), buf_.data() + end_, static_cast<unsigned>(room));
  int errnum = Z_OK;
  const char* msg = gzerror(static_cast<gzFile>(gz_), &errnum);
  if (got < 0 || (errnum != Z_OK && errnum != Z_STREAM_END)) {
    // Z_BUF_ERROR here means the gzip stream stopped in the middle: a truncated download.
    std::string reason = errnum == Z_BUF_ERROR ? "truncated gzip data" : std::string(msg ? msg : "read error");
    // zlib puts the path in front of its message: the error names the file once, here.
    if (reason.rfind(path_ + ": ", 0) == 0) reason.erase(0, path_.size() + 2);
    // The position that means something in a corrupt .gz is in the compressed file (what a hex
    // dump shows); zlib knows it to within its input buffer.
    const long compressed = gzoffset(static_cast<gzFile>(gz_));
    const std::string where = gzdirect(static_cast<gzFile>(gz_)) || compressed < 0
                                  ? "byte " + std::to_string(consumed_ + end_)
                                  : "gzip data before compressed byte " + std::to_string(compressed);
    throw InputError(path_ + ": " + where + ": " + reason);
  }
  if (got == 0) {
    eof_ = true;
    return false;
  }
  end_ += static_cast<std::size_t>(got);
  return true;
}

std::string_view LineReader::next_token() {
  bool in_comment = false;  // survives refills: a comment may straddle two chunks
  for (;;) {
    const char* b = buf_.data();
    std::size_t p = pos_;
    // Skip whitespace and comments, counting lines.
    while (p < end_) {
      if (in_comment) {
        const void* nl = std::memchr(b + p, '\n', end_ - p);
        if (nl == nullptr) {
          p = end_;
          break;
        }
        p = static_cast<std::size_t>(static_cast<const char*>(nl) - b);  // the newline is counted below
        in_comment = false;
        continue;
      }
      const char c = b[p];
      if (c == '\n') {
        ++line_;
        ++p;
      } else if (is_blank(c)) {
        ++p;
      } else if (c == comment_ && c != '\0') {
        in_comment = true;
      } else {
        break;
      }
    }
    pos_ = p;
    if (p == end_) {
      if (!refill()) {
        token_line_ = line_;
        return {};
      }
      continue;
    }
    std::size_t q = p;
    while (q < end_ && !is_space(b[q]) && !(b[q] == comment_ && comment_ != '\0')) ++q;
    if (q == end_ && !eof_) {
      // The token may continue in the next chunk: move it to the front and read more.
      if (pos_ == 0 && end_ == buf_.size()) fail("token longer than " + std::to_string(buf_.size()) + " bytes");
      refill();
      continue;
    }
    pos_ = q;
    token_line_ = line_;
    return {b + p, q - p};
  }
}

std::string_view LineReader::token(std::string_view what) {
  const std::string_view tok = next_token();
  if (tok.empty()) fail_eof(what);
  return tok;
}

std::int64_t LineReader::read_int(std::string_view what) {
  const std::string_view tok = token(what);
  const char* s = tok.data();
  const char* e = s + tok.size();
  if (*s == '+' && e - s > 1) ++s;  // from_chars does not accept a leading '+'
  std::int64_t v = 0;
  const auto [ptr, ec] = std::from_chars(s, e, v);
  if (ec == std::errc::result_out_of_range) fail(std::string(what) + ": integer out of range '" + printable(tok) + "'");
  if (ec != std::errc() || ptr != e) fail_token(what, tok, "an integer");
  return v;
}

std::int64_t LineReader::read_int(std::string_view what, std::int64_t lo, std::int64_t hi) {
  const std::int64_t v = read_int(what);
  if (v < lo || v > hi) {
    fail(std::string(what) + ": " + std::to_string(v) + " out of range [" + std::to_string(lo) + ", " +
         std::to_string(hi) + "]");
  }
  return v;
}

double LineReader::read_double(std::string_view what) {
  const double v = read_double_any(what);
  if (!std::isfinite(v)) fail(std::string(what) + ": non-finite value (nan or inf)");
  return v;
}

double LineReader::read_double_any(std::string_view what) {
  const std::string_view tok = token(what);
  const char* s = tok.data();
  const char* e = s + tok.size();
  if (*s == '+' && e - s > 1) ++s;
  double v = 0;
  auto [ptr, ec] = std::from_chars(s, e, v);
  if (ec == std::errc::result_out_of_range && ptr == e) {
    // Overflow is an error; underflow (e.g. 1e-400) is a legitimate tiny value. strtod tells them apart.
    const std::string copy(s, e);
    v = std::strtod(copy.c_str(), nullptr);
    if (!std::isfinite(v)) fail(std::string(what) + ": number out of range '" + printable(tok) + "'");
    ec = std::errc();
  }
  if (ec != std::errc() || ptr != e) fail_token(what, tok, "a number");
  return v;
}

std::string_view LineReader::next_line_text(std::string_view what) {
  for (;;) {
    while (pos_ < end_ && is_space(buf_[pos_])) {
      if (buf_[pos_] == '\n') ++line_;
      ++pos_;
    }
    if (pos_ == end_) {
      if (!refill()) fail_eof(what);
      continue;
    }
    const char* b = buf_.data();
    const void* nl = std::memchr(b + pos_, '\n', end_ - pos_);
    if (nl == nullptr && !eof_) {
      if (pos_ == 0 && end_ == buf_.size()) fail(std::string(what) + ": line too long");
      refill();
      continue;
    }
    const std::size_t stop = nl ? static_cast<std::size_t>(static_cast<const char*>(nl) - b) : end_;
    std::size_t last = stop;
    while (last > pos_ && is_space(b[last - 1])) --last;
    const std::string_view text(b + pos_, last - pos_);
    token_line_ = line_;
    pos_ = stop;
    if (nl != nullptr) {
      ++pos_;
      ++line_;
    }
    return text;
  }
}

void LineReader::skip_line(bool anything) {
  for (;;) {
    while (pos_ < end_) {
      const char c = buf_[pos_++];
      if (c == '\n') {
        ++line_;
        return;
      }
      if (!anything && !is_blank(c)) {
        token_line_ = line_;
        fail("unexpected text '" + printable(std::string_view(&buf_[pos_ - 1], std::min<std::size_t>(end_ - pos_ + 1, 20))) +
             "' at end of line");
      }
    }
    // Callers skip lines to reach data that must follow: running out is an error (and keeps a
    // loop over a lying line count from spinning at end of file).
    if (!refill()) fail_eof("the end of a line");
  }
}

void LineReader::skip_rest_of_line() {
  for (;;) {
    while (pos_ < end_) {
      if (buf_[pos_++] == '\n') {
        ++line_;
        return;
      }
    }
    if (!refill()) return;
  }
}

void LineReader::read_bytes(void* dst, std::size_t n, std::string_view what) {
  auto* out = static_cast<char*>(dst);
  while (n > 0) {
    if (pos_ == end_ && !refill()) fail_eof(what);
    const std::size_t k = std::min(n, end_ - pos_);
    std::memcpy(out, buf_.data() + pos_, k);
    pos_ += k;
    out += k;
    n -= k;
  }
}

std::int32_t LineReader::read_i32(std::string_view what) {
  std::int32_t v;
  read_bytes(&v, sizeof v, what);
  return v;
}

std::uint64_t LineReader::read_u64(std::string_view what) {
  std::uint64_t v;
  read_bytes(&v, sizeof v, what);
  return v;
}

double LineReader::read_f64(std::string_view what) {
  double v;
  read_bytes(&v, sizeof v, what);
  if (!std::isfinite(v)) fail(std::string(what) + ": non-finite value");
  return v;
}

std::size_t LineReader::reserve_hint(std::uint64_t count, std::size_t min_bytes) const {
  std::uint64_t bound = std::uint64_t{1} << 22;
  if (file_size_ > 0) {
    const std::uint64_t done = byte_offset();
    bound = (file_size_ > done ? file_size_ - done : 0) / std::max<std::size_t>(min_bytes, 1) + 1;
  }
  return static_cast<std::size_t>(std::min(count, bound));
}

void LineReader::fail(std::string_view message) const { fail_at_line(token_line_, message); }

void LineReader::fail_at_line(std::size_t line, std::string_view message) const {
  if (binary_file_) {
    throw InputError(path_ + ": byte " + std::to_string(byte_offset()) + ": " + std::string(message));
  }
  throw InputError(path_ + ":" + std::to_string(line) + ": " + std::string(message));
}

void LineReader::fail_eof(std::string_view what) const {
  fail_at_line(line_, "unexpected end of file while reading " + std::string(what));
}

void LineReader::fail_token(std::string_view what, std::string_view tok, const char* expected) const {
  fail(std::string(what) + ": expected " + expected + ", got '" + printable(tok) + "'");
}

}  // namespace topotet::io
