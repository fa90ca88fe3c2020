#include "directory.h"

#include <algorithm>

#include "exchange.h"

namespace topotet::mpi::detail {

namespace {

int home_of(GlobalId g, int ranks) { return static_cast<int>(g % static_cast<GlobalId>(ranks)); }

// The ids of `ids` grouped by home rank, keeping for each the positions they came from.
std::vector<std::vector<std::size_t>> by_home(const std::vector<GlobalId>& ids, int ranks) {
  std::vector<std::vector<std::size_t>> positions(ranks);
  for (std::size_t i = 0; i < ids.size(); ++i) positions[home_of(ids[i], ranks)].push_back(i);
  return positions;
}

}  // namespace

Sharing find_sharing(MPI_Comm comm, const std::vector<GlobalId>& global_ids, std::uint64_t* bytes_sent) {
  const int ranks = size_of(comm);
  const auto positions = by_home(global_ids, ranks);
  std::vector<std::vector<char>> out(ranks);
  for (int r = 0; r < ranks; ++r) {
    Packer p;
    for (std::size_t i : positions[r]) p.put(global_ids[i]);
    out[r] = std::move(p.bytes());
  }
  const auto asked = exchange(comm, out, bytes_sent);
  // The directory's part: (id, rank) for every copy, sorted, gives each id's holders.
  struct Copy {
    GlobalId id;
    int rank;
    bool operator<(const Copy& o) const { return id != o.id ? id < o.id : rank < o.rank; }
  };
  std::vector<Copy> copies;
  for (int r = 0; r < ranks; ++r)
    for (std::size_t k = 0; k < asked[r].size() / sizeof(GlobalId); ++k) {
      GlobalId g;
      std::memcpy(&g, asked[r].data() + k * sizeof(GlobalId), sizeof g);
      copies.push_back({g, r});
    }
  std::sort(copies.begin(), copies.end());
  auto holders = [&](GlobalId g, int& owner) {
    auto lo = std::lower_bound(copies.begin(), copies.end(), Copy{g, -1});
    owner = lo->rank;
    int count = 0;
    for (auto it = lo; it != copies.end() && it->id == g; ++it) ++count;
    return count;
  };
  std::vector<std::vector<char>> answers(ranks);
  for (int r = 0; r < ranks; ++r) {
    Packer p;
    Unpacker u(asked[r].data(), asked[r].size());
    while (!u.done()) {
      int owner = 0;
      const int count = holders(u.get<GlobalId>(), owner);
      p.put<std::int32_t>(owner);
      p.put<std::uint8_t>(count > 1 ? 1 : 0);
    }
    answers[r] = std::move(p.bytes());
  }
  const auto replies = exchange(comm, answers, bytes_sent);
  Sharing s;
  s.shared.assign(global_ids.size(), 0);
  s.owner.assign(global_ids.size(), 0);
  for (int r = 0; r < ranks; ++r) {
    Unpacker u(replies[r].data(), replies[r].size());
    for (std::size_t i : positions[r]) {
      s.owner[i] = u.get<std::int32_t>();
      s.shared[i] = u.get<std::uint8_t>();
    }
  }
  return s;
}

void apply_merges(MPI_Comm comm, const std::vector<std::pair<GlobalId, GlobalId>>& merges, std::vector<GlobalId>& ids,
                  std::uint64_t* bytes_sent) {
  const int ranks = size_of(comm);
  std::vector<std::vector<char>> out(ranks);
  {
    std::vector<Packer> packers(ranks);
    for (const auto& m : merges) {
      packers[home_of(m.first, ranks)].put(m.first);
      packers[home_of(m.first, ranks)].put(m.second);
    }
    for (int r = 0; r < ranks; ++r) out[r] = std::move(packers[r].bytes());
  }
  const auto received = exchange(comm, out, bytes_sent);
  std::vector<std::pair<GlobalId, GlobalId>> table;
  for (int r = 0; r < ranks; ++r) {
    Unpacker u(received[r].data(), received[r].size());
    while (!u.done()) {
      const GlobalId from = u.get<GlobalId>();
      table.emplace_back(from, u.get<GlobalId>());
    }
  }
  std::sort(table.begin(), table.end());
  const auto positions = by_home(ids, ranks);
  for (int r = 0; r < ranks; ++r) {
    Packer p;
    for (std::size_t i : positions[r]) p.put(ids[i]);
    out[r] = std::move(p.bytes());
  }
  const auto asked = exchange(comm, out, bytes_sent);
  for (int r = 0; r < ranks; ++r) {
    Packer p;
    Unpacker u(asked[r].data(), asked[r].size());
    while (!u.done()) {
      const GlobalId g = u.get<GlobalId>();
      auto it = std::lower_bound(table.begin(), table.end(), std::make_pair(g, GlobalId{0}));
      p.put(it != table.end() && it->first == g ? it->second : g);
    }
    out[r] = std::move(p.bytes());
  }
  const auto replies = exchange(comm, out, bytes_sent);
  for (int r = 0; r < ranks; ++r) {
    Unpacker u(replies[r].data(), replies[r].size());
    for (std::size_t i : positions[r]) ids[i] = u.get<GlobalId>();
  }
}

}  // namespace topotet::mpi::detail
