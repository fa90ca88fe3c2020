// Files for the reader and writer tests (unit_io*.cpp): a fresh temporary folder per test, text
// in and out, and the check that a bad file is refused with a message that says where.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "topotet/error.h"
#include "topotet/mesh_data.h"

namespace topotet::test {

// A small mesh with every kind of data MeshData holds.
inline MeshData two_tets() {
  MeshData m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
  m.tets = {{0, 1, 2, 3}, {1, 2, 3, 4}};
  m.tet_material = {1, 2};
  m.triangles = {{{1, 2, 3}, 9}};
  m.segments = {{{0, 1}, -1}, {{1, 2}, 0}};
  m.ridges = {1};
  m.corners = {0};
  m.required_vertices = {0, 4};
  m.vertex_refs = {0, 3, 0, 0, 0};
  m.fields = {{"s", 1, {0.1, 0.2, 0.3, 0.4, -0.0}}, {"t", 6, std::vector<double>(30, 1.0 / 3.0)}};
  return m;
}

// A fresh folder, removed with everything in it at the end of the test.
class TempDir {
 public:
  TempDir() {
    std::random_device rd;
    path_ = std::filesystem::temp_directory_path() / ("topotet_test_" + std::to_string(rd()) + std::to_string(rd()));
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  std::vector<std::string> entries() const {
    std::vector<std::string> out;
    for (const auto& e : std::filesystem::directory_iterator(path_)) out.push_back(e.path().filename().string());
    std::sort(out.begin(), out.end());
    return out;
  }

 private:
  std::filesystem::path path_;
};

inline void write_text(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

inline std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// Calls read(), expecting an InputError whose message contains each of `needles` (the file, the
// line or element, what is wrong).
template <class Read>
void expect_input_error(Read&& read, const std::vector<std::string>& needles) {
  try {
    read();
    ADD_FAILURE() << "expected an InputError containing '" << needles.back() << "'";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    for (const std::string& needle : needles) EXPECT_NE(msg.find(needle), std::string::npos) << "expected '" << needle << "' in: " << msg;
  }
}

}  // namespace topotet::test
