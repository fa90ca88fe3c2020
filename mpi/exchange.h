// Byte messages between ranks: a packer/unpacker for plain values and one all-to-all exchange of
// variable-size messages (MPI_Alltoall of the sizes, then MPI_Alltoallv of the bytes). Everything
// the distributed simplifier sends goes through here, so that the bytes sent are counted once.
#pragma once

#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include <mpi.h>

namespace topotet::mpi::detail {

class Packer {
 public:
  template <class T>
  void put(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto* p = reinterpret_cast<const char*>(&value);
    bytes_.insert(bytes_.end(), p, p + sizeof(T));
  }
  template <class T>
  void put_array(const T* values, std::size_t n) {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto* p = reinterpret_cast<const char*>(values);
    bytes_.insert(bytes_.end(), p, p + n * sizeof(T));
  }
  void put_string(const std::string& s) {
    put<std::uint64_t>(s.size());
    put_array(s.data(), s.size());
  }
  std::vector<char>& bytes() { return bytes_; }

 private:
  std::vector<char> bytes_;
};

class Unpacker {
 public:
  Unpacker(const char* data, std::size_t size) : data_(data), size_(size) {}
  template <class T>
  T get() {
    T value;
    get_array(&value, 1);
    return value;
  }
  template <class T>
  void get_array(T* out, std::size_t n) {
    static_assert(std::is_trivially_copyable_v<T>);
    if (n * sizeof(T) > size_ - pos_) throw std::runtime_error("topotet-mpi: truncated message");
    std::memcpy(static_cast<void*>(out), data_ + pos_, n * sizeof(T));
    pos_ += n * sizeof(T);
  }
  std::string get_string() {
    std::string s(get<std::uint64_t>(), '\0');
    get_array(s.data(), s.size());
    return s;
  }
  bool done() const { return pos_ == size_; }

 private:
  const char* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

// Sends outgoing[r] to rank r (outgoing.size() == ranks) and returns what every rank sent here,
// indexed by source. Adds the bytes sent to other ranks to *bytes_sent when given.
std::vector<std::vector<char>> exchange(MPI_Comm comm, std::vector<std::vector<char>>& outgoing,
                                        std::uint64_t* bytes_sent);

// Every rank's `local_ok` is agreed on; when any is false, every rank throws runtime_error with
// the message of the lowest failing rank.
void agree_or_throw(MPI_Comm comm, bool local_ok, const std::string& message);

int rank_of(MPI_Comm comm);
int size_of(MPI_Comm comm);
std::uint64_t sum_over_ranks(MPI_Comm comm, std::uint64_t value);
double max_over_ranks(MPI_Comm comm, double value);

}  // namespace topotet::mpi::detail
