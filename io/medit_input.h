// Where the MEDIT reader (io/medit.cpp) takes its numbers from: the tokens of an ASCII .mesh / .sol,
// or the words of a binary .meshb / .solb (libMeshb's Gamma Mesh Format, GMF), so that one parser
// reads both with the same checks and messages.
//
// Binary GMF (libMeshb 7, little-endian): int32 1, int32 version, then keywords. A keyword is its
// int32 code, the absolute file position of the next keyword (int32 in versions 1-2, int64 in 3-4;
// 0 after the last), then for a section with entries its count (int32 in versions 1-3, int64 in 4)
// and the entries: integers (indices, refs) int32 in versions 1-3 and int64 in 4, reals float32 in
// version 1 and float64 after. Solution sections (SolAt...) put int32 words between the count and
// the values: the number of solutions and their types. Dimension's value is one int32 word. The
// next-keyword position is checked at every keyword (a section that read more or fewer bytes
// than the file says it holds is an error naming it) and lets any section be skipped, known or not.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "io/line_reader.h"

namespace topotet::io {

class MeditInput {
 public:
  // binary: a .meshb / .solb (by extension); throws InputError for a bad header.
  MeditInput(const std::string& path, bool binary);

  bool binary() const { return binary_; }

  // The next section's keyword (ASCII spelling: "Vertices", "SolAtTetrahedra", "Code 77" for a
  // binary code without a name); empty at the end (End, or in ASCII the end of the file; a
  // binary file must end with its End keyword: without it, it was cut).
  std::string keyword();

  // An entry's integer (index, ref, count): a token, or an int32/int64 word by version.
  std::int64_t read_int(std::string_view what);
  std::int64_t read_int(std::string_view what, std::int64_t lo, std::int64_t hi);
  // A header word: Dimension's value, a solution section's number of solutions and types (always
  // int32 in binary).
  std::int64_t read_word(std::string_view what, std::int64_t lo, std::int64_t hi);
  // A finite real.
  double read_double(std::string_view what);
  // Skips the rest of the current section (binary: to the next keyword's position); ASCII needs
  // the caller to know the section's size (io/medit.cpp's skip_section).
  void skip_to_next_keyword(std::string_view keyword);

  std::size_t line() const { return r_.line(); }
  std::size_t reserve_hint(std::uint64_t count, std::size_t min_bytes) const { return r_.reserve_hint(count, min_bytes); }
  [[noreturn]] void fail(std::string_view message) const { r_.fail(message); }
  [[noreturn]] void fail_at_line(std::size_t line, std::string_view message) const { r_.fail_at_line(line, message); }
  LineReader& tokens() { return r_; }  // ASCII only

 private:
  void check_section_end();

  LineReader r_;
  bool binary_ = false;
  int version_ = 0;
  std::uint64_t next_keyword_ = 0;  // binary: where the current section must end (0 = unknown)
  std::string section_;             // binary: the current section's keyword, for messages
};

}  // namespace topotet::io
