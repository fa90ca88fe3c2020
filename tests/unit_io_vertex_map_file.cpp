// The vertex map file (topotet/vertex_map_file.h): .npy and .txt round trips, the NumPy header as
// numpy writes it, and clear errors for what is not a map.
#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "io_test_files.h"
#include "topotet/error.h"
#include "topotet/vertex_map_file.h"

namespace topotet {
namespace {

std::string error_of(const std::string& path) {
  try {
    read_vertex_map(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(VertexMapFile, NpyAndTextRoundTrip) {
  test::TempDir folder;
  const std::vector<VertId> map = {0, 0, 1, kInvalid, 2, 1, 4000000000u};
  const std::vector<std::int64_t> expected = {0, 0, 1, -1, 2, 1, 4000000000};
  for (const char* name : {"m.npy", "m.txt", "M.NPY"}) {
    write_vertex_map(folder.file(name), map);
    EXPECT_EQ(read_vertex_map(folder.file(name)), expected) << name;
  }
  write_vertex_map(folder.file("empty.npy"), {});
  EXPECT_TRUE(read_vertex_map(folder.file("empty.npy")).empty());
  // NumPy's layout: magic, version 1.0, a header padded so that the data starts at a multiple of 64 bytes.
  const std::string bytes = test::read_text(folder.file("m.npy"));
  const std::size_t data = bytes.size() - 8 * map.size();
  EXPECT_EQ(data % 64, 0u);
  EXPECT_EQ(data, 10u + static_cast<unsigned char>(bytes[8]) + 256u * static_cast<unsigned char>(bytes[9]));
  EXPECT_EQ(bytes.substr(0, 8), std::string("\x93NUMPY\x01\x00", 8));
  EXPECT_EQ(bytes[data - 1], '\n');
  EXPECT_NE(bytes.find("{'descr': '<i8', 'fortran_order': False, 'shape': (7,), }"), std::string::npos);
  const std::string text = test::read_text(folder.file("m.txt"));
  EXPECT_EQ(text.substr(text.find('\n') + 1), "0\n0\n1\n-1\n2\n1\n4000000000\n");
  for (const std::string& e : folder.entries()) EXPECT_EQ(e.find(".tmp-"), std::string::npos) << e;
}

TEST(VertexMapFile, WhatIsNotAMapIsAClearError) {
  test::TempDir folder;
  EXPECT_THROW(check_vertex_map_path("map.csv"), InputError);
  EXPECT_THROW(write_vertex_map(folder.file("map.bin"), {0}), InputError);
  std::ofstream(folder.file("bad.txt")) << "# comment\n0\n1\nseven\n";
  EXPECT_NE(error_of(folder.file("bad.txt")).find("bad.txt:4"), std::string::npos) << error_of(folder.file("bad.txt"));
  std::ofstream(folder.file("neg.txt")) << "0\n-2\n";
  EXPECT_NE(error_of(folder.file("neg.txt")).find("neg.txt:2"), std::string::npos) << error_of(folder.file("neg.txt"));
  write_vertex_map(folder.file("m.npy"), {0, 1, 2, 3});
  const std::string good = test::read_text(folder.file("m.npy"));
  std::ofstream(folder.file("cut.npy"), std::ios::binary) << good.substr(0, good.size() - 3);
  EXPECT_NE(error_of(folder.file("cut.npy")).find("cut.npy"), std::string::npos);
  std::string float64 = good;
  float64.replace(float64.find("<i8"), 3, "<f8");
  std::ofstream(folder.file("f8.npy"), std::ios::binary) << float64;
  EXPECT_NE(error_of(folder.file("f8.npy")).find("int64"), std::string::npos) << error_of(folder.file("f8.npy"));
  std::ofstream(folder.file("text.npy"), std::ios::binary) << "0\n1\n2\n3\n4\n5\n";
  EXPECT_NE(error_of(folder.file("text.npy")).find("not a NumPy"), std::string::npos);
  // A count is checked when the writer commits.
  VertexMapWriter short_writer(folder.file("short.npy"), 3);
  short_writer.add(0);
  EXPECT_THROW(short_writer.commit(), std::logic_error);
}

}  // namespace
}  // namespace topotet
