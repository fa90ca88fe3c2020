// The vertex map file (topotet/vertex_map_file.h): .npy (NumPy format 1.0, '<i8', one dimension)
// or text, written through AtomicFile, read back with LineReader.
#include "topotet/vertex_map_file.h"

#include <algorithm>
#include <charconv>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string_view>

#include "io/atomic_file.h"
#include "io/formats.h"
#include "io/line_reader.h"
#include "topotet/error.h"

namespace topotet {
namespace {

constexpr char kNpyMagic[] = "\x93NUMPY";  // 6 bytes, then the version bytes 1, 0
constexpr std::size_t kNpyPreamble = 10;   // magic, version, uint16 header length

bool is_npy(const std::string& path) { return io::iends_with(path, ".npy"); }

// NumPy's header: a Python dict literal, padded with spaces and ended by '\n' so that the data
// starts at a multiple of 64 bytes (what numpy itself writes, for aligned memory maps).
std::string npy_header(std::uint64_t count) {
  std::string dict = "{'descr': '<i8', 'fortran_order': False, 'shape': (" + std::to_string(count) + ",), }";
  const std::size_t total = (kNpyPreamble + dict.size() + 1 + 63) / 64 * 64;
  dict.append(total - kNpyPreamble - dict.size() - 1, ' ');
  dict.push_back('\n');
  return dict;
}

std::vector<std::int64_t> read_npy(const std::string& path) {
  io::LineReader in(path);
  in.set_binary_file(true);
  char preamble[kNpyPreamble];
  in.read_bytes(preamble, sizeof preamble, "the .npy preamble");
  if (std::memcmp(preamble, kNpyMagic, 6) != 0) in.fail("not a NumPy .npy file (no \\x93NUMPY magic)");
  if (preamble[6] != 1 || preamble[7] != 0) in.fail("NumPy format version " + std::to_string(preamble[6]) + "." + std::to_string(preamble[7]) + ": only 1.0 is read (what topotet writes)");
  const std::size_t header_size = static_cast<unsigned char>(preamble[8]) | static_cast<std::size_t>(static_cast<unsigned char>(preamble[9])) << 8;
  std::string header(header_size, '\0');
  in.read_bytes(header.data(), header.size(), "the .npy header");
  const auto has = [&](std::string_view s) { return header.find(s) != std::string::npos; };
  if (!has("'descr': '<i8'") || !has("'fortran_order': False"))
    in.fail("expected a little-endian int64 array in C order ('<i8'), as topotet writes; got " + header);
  const std::size_t shape = header.find("'shape': (");
  if (shape == std::string::npos) in.fail("no shape in the .npy header");
  const std::size_t first = shape + std::strlen("'shape': (");
  const std::size_t close = header.find(')', first);
  const std::string dims = header.substr(first, close == std::string::npos ? 0 : close - first);
  std::uint64_t count = 0;
  std::size_t used = 0;
  try {
    count = std::stoull(dims, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || dims.substr(used) != ",") in.fail("expected a one-dimensional array, shape (N,); got (" + dims + ")");
  // In chunks, reserving no more than the file can hold: a lying header cannot force a huge allocation.
  std::vector<std::int64_t> map, chunk;
  map.reserve(in.reserve_hint(count, sizeof(std::int64_t)));
  for (std::uint64_t done = 0; done < count;) {
    chunk.resize(static_cast<std::size_t>(std::min<std::uint64_t>(count - done, 1 << 16)));
    in.read_bytes(chunk.data(), chunk.size() * sizeof(std::int64_t), "the vertex map's entries");
    map.insert(map.end(), chunk.begin(), chunk.end());
    done += chunk.size();
  }
  if (!in.next_token().empty()) in.fail("data after the " + std::to_string(count) + " entries the header declares");
  return map;
}

std::vector<std::int64_t> read_text(const std::string& path) {
  io::LineReader in(path);
  in.set_comment_char('#');
  std::vector<std::int64_t> map;
  while (true) {
    const std::string_view token = in.next_token();
    if (token.empty()) break;
    std::int64_t value = 0;
    const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), value);
    if (error != std::errc() || end != token.data() + token.size() || value < -1)
      in.fail("expected an output vertex index (>= 0) or -1, got '" + std::string(token) + "'");
    map.push_back(value);
  }
  return map;
}

}  // namespace

void check_vertex_map_path(const std::string& path) {
  if (!is_npy(path) && !io::iends_with(path, ".txt"))
    throw InputError(path + ": a vertex map is written as .npy (NumPy int64) or .txt (one index per line)");
}

struct VertexMapWriter::State {
  io::AtomicFile file;
  bool npy;
  std::uint64_t count, added = 0;
  State(const std::string& path, std::uint64_t n) : file(path), npy(is_npy(path)), count(n) {}
};

VertexMapWriter::VertexMapWriter(const std::string& path, std::uint64_t count) {
  check_vertex_map_path(path);
  state_ = std::make_unique<State>(path, count);
  if (state_->npy) {
    state_->file.put_bytes(kNpyMagic, 6);
    state_->file.put('\x01');
    state_->file.put('\x00');
    const std::string header = npy_header(count);
    if (header.size() > std::numeric_limits<std::uint16_t>::max()) throw std::logic_error("npy header too long");
    state_->file.put(static_cast<char>(header.size() & 0xff));
    state_->file.put(static_cast<char>(header.size() >> 8));
    state_->file.put(header);
  } else {
    state_->file.put("# topotet vertex map: one line per input vertex, in input order: the 0-based index of the "
                     "output vertex it became or merged into (-1: used by no tet)\n");
  }
}

VertexMapWriter::~VertexMapWriter() = default;

void VertexMapWriter::add(std::int64_t output_vertex) {
  ++state_->added;
  if (state_->npy) {
    state_->file.put_raw(output_vertex);
  } else {
    state_->file.put_int(output_vertex);
    state_->file.put('\n');
  }
}

void VertexMapWriter::commit() {
  if (state_->added != state_->count)
    throw std::logic_error("VertexMapWriter: " + std::to_string(state_->added) + " entries added, " +
                           std::to_string(state_->count) + " declared");
  state_->file.commit();
}

void write_vertex_map(const std::string& path, const std::vector<VertId>& map) {
  VertexMapWriter writer(path, map.size());
  for (VertId o : map) writer.add(o == kInvalid ? -1 : static_cast<std::int64_t>(o));
  writer.commit();
}

std::vector<std::int64_t> read_vertex_map(const std::string& path) {
  check_vertex_map_path(path);
  return is_npy(path) ? read_npy(path) : read_text(path);
}

}  // namespace topotet
