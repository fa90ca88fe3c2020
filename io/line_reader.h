// LineReader: the fast tokenizer every mesh reader is built on.
//
// Reads plain and gzip'd files the same way (zlib's gzread passes plain files through), in large
// chunks, and hands out whitespace-separated tokens as string_views into its buffer; numbers are
// parsed with std::from_chars. It tracks line numbers so that every error reads
// "FILE:LINE: message" (InputError). Gmsh binary files mix text headers with raw blocks: the
// read_bytes() family reads raw data from the same buffer; once a file has binary parts, errors
// name the byte offset instead of a line (line numbers mean nothing inside binary data).
//
// Token views stay valid only until the next call that reads from the reader.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace topotet::io {

class LineReader {
 public:
  // Throws InputError "PATH: cannot open: REASON".
  explicit LineReader(const std::string& path);
  ~LineReader();
  LineReader(const LineReader&) = delete;
  LineReader& operator=(const LineReader&) = delete;

  const std::string& path() const { return path_; }
  // Line of the last token returned (1-based).
  std::size_t line() const { return token_line_; }
  // Offset of the read position in the (uncompressed) stream.
  std::uint64_t byte_offset() const { return consumed_ + pos_; }

  // Text from this character to the end of the line is skipped as whitespace ('\0' = none).
  void set_comment_char(char c) { comment_ = c; }
  // Report byte offsets instead of lines in errors (set by readers of binary files).
  void set_binary_file(bool b) { binary_file_ = b; }

  // Next token; an empty view at end of file.
  std::string_view next_token();
  // Next token; fails "unexpected end of file while reading WHAT" at end of file.
  std::string_view token(std::string_view what);
  // Next integer / finite double; fails naming WHAT and the offending token otherwise.
  std::int64_t read_int(std::string_view what);
  std::int64_t read_int(std::string_view what, std::int64_t lo, std::int64_t hi);
  double read_double(std::string_view what);
  // Any double including inf/nan (Gmsh entity bounding boxes, which we do not use).
  double read_double_any(std::string_view what);

  // Skips whitespace and newlines, then returns the text up to the end of that line (without the
  // newline, trailing whitespace trimmed) and moves past it. Used for quoted names in Gmsh files.
  std::string_view next_line_text(std::string_view what);
  // Skips the rest of the current line including its newline (only whitespace allowed unless
  // `anything` is true); fails at end of file. Gmsh binary data starts right after such a newline.
  void skip_line(bool anything = false);
  // Skips whatever is left of the current line, if anything (TetGen rows may carry extra columns);
  // end of file is fine.
  void skip_rest_of_line();

  // True when no byte is left (binary formats, whose sections are not tokens).
  bool at_end() { return pos_ == end_ && !refill(); }
  // Raw bytes (Gmsh binary); fails at end of file.
  void read_bytes(void* dst, std::size_t n, std::string_view what);
  std::int32_t read_i32(std::string_view what);
  std::uint64_t read_u64(std::string_view what);
  double read_f64(std::string_view what);  // finite

  // How many entries of `count` to reserve when each entry needs at least `min_bytes` of input:
  // bounded by the bytes left in a plain file (so a lying count cannot force a huge allocation),
  // and by a fixed cap for gzip'd input whose size is unknown.
  std::size_t reserve_hint(std::uint64_t count, std::size_t min_bytes) const;

  // Throws InputError "PATH:LINE: message" (or "PATH: byte N: message" for binary files).
  [[noreturn]] void fail(std::string_view message) const;
  [[noreturn]] void fail_at_line(std::size_t line, std::string_view message) const;

 private:
  bool refill();  // keeps [pos_, end_) and reads more; false when nothing more could be read
  [[noreturn]] void fail_eof(std::string_view what) const;
  [[noreturn]] void fail_token(std::string_view what, std::string_view tok, const char* expected) const;

  std::string path_;
  void* gz_ = nullptr;  // gzFile
  std::vector<char> buf_;
  std::size_t pos_ = 0;
  std::size_t end_ = 0;
  std::uint64_t consumed_ = 0;   // stream offset of buf_[0]
  std::uint64_t file_size_ = 0;  // plain files only; 0 when unknown (gzip)
  bool eof_ = false;
  bool binary_file_ = false;
  char comment_ = '\0';
  std::size_t line_ = 1;        // line at pos_
  std::size_t token_line_ = 1;  // line of the last token
};

}  // namespace topotet::io
