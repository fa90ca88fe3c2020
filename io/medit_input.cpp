#include "io/medit_input.h"

#include <array>
#include <cmath>
#include <cstring>

#include "io/formats.h"

namespace topotet::io {
namespace {

constexpr std::int32_t kEndCode = 54;

// The GMF keyword codes the reader knows by name (libMeshb's GmfKwdCod); any other is skipped by
// its position, named "Code N".
std::string keyword_name(std::int32_t code) {
  switch (code) {
    case 1: return "MeshVersionFormatted";
    case 3: return "Dimension";
    case 4: return "Vertices";
    case 5: return "Edges";
    case 6: return "Triangles";
    case 7: return "Quadrilaterals";
    case 8: return "Tetrahedra";
    case 9: return "Prisms";
    case 10: return "Hexahedra";
    case 13: return "Corners";
    case 14: return "Ridges";
    case 15: return "RequiredVertices";
    case 24: return "TrianglesP2";
    case 25: return "EdgesP2";
    case 27: return "QuadrilateralsQ2";
    case 30: return "TetrahedraP2";
    case 33: return "HexahedraQ2";
    case 49: return "Pyramids";
    case 62: return "SolAtVertices";
    case 66: return "SolAtTetrahedra";
    default: return "Code " + std::to_string(code);
  }
}

bool is_keyword_token(std::string_view tok) {
  const char c = tok.empty() ? '\0' : tok[0];
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z');
}

}  // namespace

MeditInput::MeditInput(const std::string& path, bool binary) : r_(path), binary_(binary) {
  if (!binary_) {
    r_.set_comment_char('#');
    return;
  }
  r_.set_binary_file(true);
  const std::int32_t code = r_.read_i32("the .meshb header");
  if (code == 16777216) r_.fail("a big-endian .meshb: only little-endian files are read (convert it on its machine)");
  if (code != 1) r_.fail("not a binary MEDIT (GMF) file: first word " + std::to_string(code) + ", expected 1");
  version_ = r_.read_i32("the .meshb version");
  if (version_ < 1 || version_ > 4) r_.fail("GMF version " + std::to_string(version_) + " is not supported (expected 1 to 4)");
}

void MeditInput::check_section_end() {
  if (next_keyword_ == 0 || r_.byte_offset() == next_keyword_) return;
  r_.fail(section_ + ": its entries end at byte " + std::to_string(r_.byte_offset()) + ", but the file puts the next keyword at byte " +
          std::to_string(next_keyword_) + " (a count or a type that does not match its data)");
}

std::string MeditInput::keyword() {
  if (!binary_) {
    const std::string_view tok = r_.next_token();
    if (tok.empty() || iequals(tok, "End")) return {};
    if (!is_keyword_token(tok)) r_.fail("expected a section keyword, got '" + std::string(tok.substr(0, 40)) + "'");
    return std::string(tok);
  }
  check_section_end();
  // Every GMF writer ends with End: a file without it was cut at a section boundary.
  if (r_.at_end()) r_.fail("the file ends before its End keyword (truncated?)");
  const std::int32_t code = r_.read_i32("a keyword code");
  if (code == kEndCode) return {};
  section_ = keyword_name(code);
  const std::uint64_t here = r_.byte_offset();
  const std::int64_t next = version_ >= 3 ? static_cast<std::int64_t>(r_.read_u64("the next keyword's position"))
                                          : r_.read_i32("the next keyword's position");
  if (next != 0 && (next < 0 || static_cast<std::uint64_t>(next) <= here))
    r_.fail(section_ + ": the next keyword's position " + std::to_string(next) + " is not after this one");
  next_keyword_ = static_cast<std::uint64_t>(next);
  return section_;
}

std::int64_t MeditInput::read_int(std::string_view what) {
  if (!binary_) return r_.read_int(what);
  return version_ <= 3 ? r_.read_i32(what) : static_cast<std::int64_t>(r_.read_u64(what));
}

std::int64_t MeditInput::read_int(std::string_view what, std::int64_t lo, std::int64_t hi) {
  if (!binary_) return r_.read_int(what, lo, hi);
  const std::int64_t v = read_int(what);
  if (v < lo || v > hi)
    r_.fail(std::string(what) + ": " + std::to_string(v) + " out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return v;
}

std::int64_t MeditInput::read_word(std::string_view what, std::int64_t lo, std::int64_t hi) {
  if (!binary_) return r_.read_int(what, lo, hi);
  const std::int32_t v = r_.read_i32(what);
  if (v < lo || v > hi)
    r_.fail(std::string(what) + ": " + std::to_string(v) + " out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return v;
}

double MeditInput::read_double(std::string_view what) {
  if (!binary_) return r_.read_double(what);
  if (version_ >= 2) return r_.read_f64(what);
  float v;
  r_.read_bytes(&v, sizeof v, what);
  if (!std::isfinite(v)) r_.fail(std::string(what) + ": non-finite value");
  return v;
}

void MeditInput::skip_to_next_keyword(std::string_view keyword) {
  if (next_keyword_ == 0) r_.fail(std::string(keyword) + ": cannot skip it (the file gives no position after it)");
  std::array<char, 1 << 14> sink;
  while (r_.byte_offset() < next_keyword_) {
    const std::uint64_t left = next_keyword_ - r_.byte_offset();
    r_.read_bytes(sink.data(), static_cast<std::size_t>(std::min<std::uint64_t>(left, sink.size())), keyword);
  }
}

}  // namespace topotet::io
