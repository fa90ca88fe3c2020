#include "seams.h"

#include <algorithm>
#include <cstdio>
#include <iterator>
#include <limits>
#include <optional>

namespace topotet::ooc {

namespace {

std::vector<GlobalId> sorted(std::vector<GlobalId> ids) {
  std::sort(ids.begin(), ids.end());
  return ids;
}

std::vector<GlobalId> common_ids(const std::vector<GlobalId>& a, const std::vector<GlobalId>& b) {
  std::vector<GlobalId> common;
  std::set_intersection(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(common));
  return common;
}

// The piece's vertices that other pieces hold too (sorted global ids).
std::vector<GlobalId> border_of(const Piece& piece, const std::vector<std::uint8_t>& holders) {
  std::vector<GlobalId> border;
  for (GlobalId g : piece.global_ids)
    if (holders[g] >= 2) border.push_back(g);
  std::sort(border.begin(), border.end());
  return border;
}

// A piece split into a band and the rest: the vertices both use (their new common border) and
// each part's share of the region, by its share of the interior vertices (the earlier levels left
// the interior about evenly simplified). The new border's vertices are frozen in both parts, kept
// as they are: their share goes to the band, which counts them among the vertices it keeps
// (between_kept), so that the seam's run removes what they would have.
struct Split {
  Piece band, rest;
  std::vector<GlobalId> between;
  std::uint64_t band_region = 0, rest_region = 0, between_kept = 0;
};

Split split(const Piece& piece, const std::vector<std::uint32_t>& band, const std::vector<std::uint8_t>& holders,
            std::uint64_t region) {
  std::vector<std::uint32_t> rest;
  rest.reserve(piece.mesh.tets.size() - band.size());
  for (std::uint32_t t = 0, b = 0; t < piece.mesh.tets.size(); ++t) {
    if (b < band.size() && band[b] == t) {
      ++b;
      continue;
    }
    rest.push_back(t);
  }
  Split s;
  s.band = sub_piece(piece, band);
  s.rest = sub_piece(piece, rest);
  s.between = common_ids(sorted(s.band.global_ids), sorted(s.rest.global_ids));
  // A vertex on the new border has its quadric in both parts, each from all of its tets: the next
  // run rebuilds it from its star (NaN: simplify.h), as a merge does for any border vertex.
  for (Piece* p : {&s.band, &s.rest}) {
    if (p->quadric_doubles == 0) continue;
    for (VertId v = 0; v < p->global_ids.size(); ++v)
      if (std::binary_search(s.between.begin(), s.between.end(), p->global_ids[v]))
        p->quadrics[std::size_t{v} * p->quadric_doubles] = std::numeric_limits<double>::quiet_NaN();
  }
  const std::uint64_t interior = interior_vertices(piece, holders);
  std::uint64_t between_interior = 0;
  for (GlobalId g : s.between) between_interior += holders[g] == 1;
  if (interior > 0) {
    s.band_region = region * interior_vertices(s.band, holders) / interior;
    s.rest_region = region * (interior_vertices(s.rest, holders) - between_interior) / interior;
  }
  s.between_kept = between_interior;
  return s;
}

// The smallest piece file number no piece uses (pieces never exceed kMaxPieces files at once:
// the signal handler removes piece-0 ... piece-(kMaxPieces - 1)).
std::optional<std::uint32_t> take_file(std::vector<bool>& used) {
  for (std::uint32_t f = 0; f < used.size(); ++f)
    if (!used[f]) {
      used[f] = true;
      return f;
    }
  return std::nullopt;
}

}  // namespace

Piece merge_slots(const ScratchFolder& scratch, std::vector<std::uint8_t>& holders, const PieceSlot& a,
                  const PieceSlot& b, PieceSlot& merged) {
  Piece pa = load_piece(scratch.piece_path(a.file));
  Piece pb = load_piece(scratch.piece_path(b.file));
  std::remove(scratch.piece_path(b.file).c_str());
  std::uint64_t made_interior = 0;
  for (GlobalId g : common_ids(sorted(pa.global_ids), sorted(pb.global_ids))) made_interior += --holders[g] == 1;
  merged.file = a.file;
  merged.region = a.region + b.region + made_interior;
  merged.kept_frozen = a.kept_frozen + b.kept_frozen;
  merged.field_bound = a.field_bound;  // until its run says (it may have nothing to remove)
  raise_to(merged.field_bound, b.field_bound);
  return merge_pieces(std::move(pa), std::move(pb));
}

Seams cut_seams(std::vector<PieceSlot> pieces, const ScratchFolder& scratch, std::vector<std::uint8_t>& holders,
                std::uint64_t piece_limit) {
  Seams result;
  std::vector<bool> used(kMaxPieces, false), alive(pieces.size(), true);
  for (const PieceSlot& s : pieces) used[s.file] = true;
  // Vertices that became a border by a cut between a band and its rest: already simplified by the
  // earlier levels, they call for no seam (or every cut would call for another).
  std::vector<bool> carved(holders.size(), false);
  // [piece] its border that calls for a seam: vertices others hold too, not carved (sorted).
  const auto seam_border = [&](const Piece& piece) {
    std::vector<GlobalId> border = border_of(piece, holders);
    border.erase(std::remove_if(border.begin(), border.end(), [&](GlobalId g) { return carved[g]; }), border.end());
    return border;
  };
  std::vector<std::vector<GlobalId>> borders;
  for (const PieceSlot& s : pieces) borders.push_back(seam_border(load_piece(scratch.piece_path(s.file))));
  const auto save_or_drop = [&](const Piece& piece, std::size_t index) {
    PieceSlot& slot = pieces[index];
    slot.tets = piece.mesh.tets.size();
    if (slot.tets == 0) {
      std::remove(scratch.piece_path(slot.file).c_str());
      used[slot.file] = false;
      alive[index] = false;
      borders[index].clear();
    } else {
      save_piece(scratch.piece_path(slot.file), piece);
    }
  };
  // The seam of pieces i and j around `seeds` (their common border), or false when the pair's
  // bands would not fit in one piece, or would freeze on their cuts (between band and rest) at
  // least as many vertices as the seam frees: pieces small against kSeamRings, whose cuts would
  // call for seams of their own, cut into slivers (nothing changed then).
  const auto seam = [&](std::size_t i, std::size_t j, const std::vector<GlobalId>& seeds) {
    // Side i first, kept in memory until side j is known to fit beside it.
    Split si, sj;
    {
      const Piece pi = load_piece(scratch.piece_path(pieces[i].file));
      const auto band = band_tets(pi, seeds, piece_limit / 2, kSeamRings);
      if (band.size() > piece_limit / 2) return false;
      si = split(pi, band, holders, pieces[i].region);
    }
    const std::uint64_t room = piece_limit - si.band.mesh.tets.size();
    {
      const Piece pj = load_piece(scratch.piece_path(pieces[j].file));
      const auto band = band_tets(pj, seeds, room, kSeamRings);
      if (band.size() > room) return false;
      sj = split(pj, band, holders, pieces[j].region);
    }
    // Worth it only if it frees more vertices than its cuts freeze.
    const auto freed = static_cast<std::uint64_t>(std::count_if(seeds.begin(), seeds.end(), [&](GlobalId g) { return holders[g] == 2; }));
    if (freed <= si.between_kept + sj.between_kept) return false;
    const std::optional<std::uint32_t> band_i_file = take_file(used), band_j_file = take_file(used);
    if (!band_i_file || !band_j_file) {  // every file number in use: leave the pair apart
      if (band_i_file) used[*band_i_file] = false;
      return false;
    }
    // Both fit: the rests replace the pieces, the bands become the seam.
    for (Split* s : {&si, &sj})
      for (GlobalId g : s->between) {
        if (holders[g] == 1) carved[g] = true;
        ++holders[g];
      }
    const PieceSlot band_i{*band_i_file, si.band.mesh.tets.size(), si.band_region, pieces[i].field_bound, si.between_kept};
    const PieceSlot band_j{*band_j_file, sj.band.mesh.tets.size(), sj.band_region, pieces[j].field_bound, sj.between_kept};
    save_piece(scratch.piece_path(band_i.file), si.band);
    save_piece(scratch.piece_path(band_j.file), sj.band);
    pieces[i].region = si.rest_region;
    pieces[j].region = sj.rest_region;
    save_or_drop(si.rest, i);
    save_or_drop(sj.rest, j);
    if (alive[i]) borders[i] = seam_border(si.rest);
    if (alive[j]) borders[j] = seam_border(sj.rest);
    si = Split{};
    sj = Split{};
    PieceSlot joined;
    const Piece merged = merge_slots(scratch, holders, band_i, band_j, joined);
    used[band_j.file] = false;
    joined.tets = merged.mesh.tets.size();
    save_piece(scratch.piece_path(joined.file), merged);
    pieces.push_back(joined);
    alive.push_back(true);
    borders.push_back(seam_border(merged));
    return true;
  };
  // Rounds over every pair, the seams made so far included (a seam holds part of its pieces'
  // other borders), until no pair calls for one. A pair declined is not tried again.
  // The count is bounded as a guard: a seam frees its seeds, but a cut may add a holder to a
  // vertex of another border.
  std::vector<std::pair<std::size_t, std::size_t>> failed;
  const std::size_t most = 8 * pieces.size() + 16;
  for (bool more = true; more && result.made < most;) {
    more = false;
    for (std::size_t i = 0; i < pieces.size(); ++i)
      for (std::size_t j = i + 1; j < pieces.size() && result.made < most; ++j) {
        if (!alive[i] || !alive[j]) continue;
        const std::vector<GlobalId> seeds = common_ids(borders[i], borders[j]);
        // A seam frees the vertices only these two hold; one around vertices a third piece holds
        // too (where three borders meet: a line) frees none of them.
        if (std::none_of(seeds.begin(), seeds.end(), [&](GlobalId g) { return holders[g] == 2; }) ||
            std::find(failed.begin(), failed.end(), std::make_pair(i, j)) != failed.end())
          continue;
        if (seam(i, j, seeds)) {
          ++result.made;
          more = true;
        } else {
          failed.push_back({i, j});
          ++result.declined;
        }
      }
  }
  for (std::size_t i = 0; i < pieces.size(); ++i)
    if (alive[i]) result.slots.push_back(pieces[i]);
  return result;
}

}  // namespace topotet::ooc
