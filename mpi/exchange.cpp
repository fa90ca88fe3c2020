#include "exchange.h"

#include <climits>

namespace topotet::mpi::detail {

int rank_of(MPI_Comm comm) {
  int r = 0;
  MPI_Comm_rank(comm, &r);
  return r;
}

int size_of(MPI_Comm comm) {
  int n = 1;
  MPI_Comm_size(comm, &n);
  return n;
}

std::uint64_t sum_over_ranks(MPI_Comm comm, std::uint64_t value) {
  std::uint64_t sum = 0;
  MPI_Allreduce(&value, &sum, 1, MPI_UINT64_T, MPI_SUM, comm);
  return sum;
}

double max_over_ranks(MPI_Comm comm, double value) {
  double m = 0;
  MPI_Allreduce(&value, &m, 1, MPI_DOUBLE, MPI_MAX, comm);
  return m;
}

std::vector<std::vector<char>> exchange(MPI_Comm comm, std::vector<std::vector<char>>& outgoing,
                                        std::uint64_t* bytes_sent) {
  const int ranks = size_of(comm), me = rank_of(comm);
  // MPI counts are int: one message per pair must stay below 2 GB (a part of ~20M tets). Larger
  // parts would need MPI_Type_contiguous chunks; refused clearly rather than truncated.
  std::vector<int> send_counts(ranks), recv_counts(ranks), send_displs(ranks), recv_displs(ranks);
  bool fits = true;
  for (int r = 0; r < ranks; ++r) {
    if (outgoing[r].size() > static_cast<std::size_t>(INT_MAX)) fits = false;
    send_counts[r] = static_cast<int>(outgoing[r].size());
  }
  agree_or_throw(comm, fits, "a message between two ranks exceeds 2 GB (use more ranks)");
  MPI_Alltoall(send_counts.data(), 1, MPI_INT, recv_counts.data(), 1, MPI_INT, comm);
  long long send_total = 0, recv_total = 0;
  for (int r = 0; r < ranks; ++r) {
    send_displs[r] = static_cast<int>(send_total);
    recv_displs[r] = static_cast<int>(recv_total);
    send_total += send_counts[r];
    recv_total += recv_counts[r];
  }
  agree_or_throw(comm, send_total <= INT_MAX && recv_total <= INT_MAX,
                 "one rank's messages exceed 2 GB in one exchange (use more ranks)");
  std::vector<char> send(static_cast<std::size_t>(send_total)), recv(static_cast<std::size_t>(recv_total));
  for (int r = 0; r < ranks; ++r) {
    std::copy(outgoing[r].begin(), outgoing[r].end(), send.begin() + send_displs[r]);
    if (bytes_sent != nullptr && r != me) *bytes_sent += outgoing[r].size();
    std::vector<char>().swap(outgoing[r]);
  }
  MPI_Alltoallv(send.data(), send_counts.data(), send_displs.data(), MPI_BYTE, recv.data(), recv_counts.data(),
                recv_displs.data(), MPI_BYTE, comm);
  std::vector<std::vector<char>> incoming(ranks);
  for (int r = 0; r < ranks; ++r)
    incoming[r].assign(recv.begin() + recv_displs[r], recv.begin() + recv_displs[r] + recv_counts[r]);
  return incoming;
}

void agree_or_throw(MPI_Comm comm, bool local_ok, const std::string& message) {
  const int ranks = size_of(comm), me = rank_of(comm);
  int first_failing = local_ok ? ranks : me;
  int lowest = ranks;
  MPI_Allreduce(&first_failing, &lowest, 1, MPI_INT, MPI_MIN, comm);
  if (lowest == ranks) return;
  // The lowest failing rank's message, so that every rank reports the same error.
  std::uint64_t length = lowest == me ? message.size() : 0;
  MPI_Bcast(&length, 1, MPI_UINT64_T, lowest, comm);
  std::string text = lowest == me ? message : std::string(length, '\0');
  MPI_Bcast(text.data(), static_cast<int>(length), MPI_CHAR, lowest, comm);
  throw std::runtime_error("rank " + std::to_string(lowest) + ": " + text);
}

}  // namespace topotet::mpi::detail
