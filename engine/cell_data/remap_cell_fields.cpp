// remap_cell_fields (topotet/cell_fields.h): a conservative remap by exact overlap volume.
//
//   grid over the original tets (tet_grid.h)
//   for each new tet j, in parallel, in fixed blocks of new tets:
//     candidates = original tets listed in the grid cells j's box meets, sorted, unique
//     overlaps(j) = [(i, vol(i ∩ j)) for i in candidates if same material, boxes meet, vol > 0]
//     intensive:   sum(ov * v_i) / sum(ov);  categorical: value with the largest sum(ov)
//     (no overlap: remember j for the nearest-centroid fallback)
//     keep overlaps(j) in the block when some array is extensive
//   extensive: covered_i = sum over j of vol(i ∩ j), in the order of the blocks;
//              new_j = sum(v_i * ov / covered_i); an original tet with covered_i = 0 gives its
//              whole amount to the new tet of its material whose centroid is nearest.
// Every sum runs over the original tets in increasing id, and blocks are fixed ranges of new tets
// whose results are combined in block order: the output does not depend on the thread count.
#include <algorithm>
#include <chrono>
#include <memory>
#include <optional>

#include "cell_data/tet_grid.h"
#include "cell_data/tet_overlap.h"
#include "mesh/glm_convert.h"
#include "parallel/for_range.h"
#include "parallel/scratch.h"
#include "topotet/cell_fields.h"
#include "topotet/error.h"

namespace topotet {
namespace {

using cell_data::Box;
using cell_data::TetGrid;

constexpr std::size_t kBlock = 1024;  // new tets per block (the unit of work and of the stored overlaps)

struct Overlap {
  TetId original;
  double volume;
};

// An overlap as kept for the extensive arrays: 8 bytes, not 16 (the kept overlaps are the remap's
// largest memory, about 5.5 per input tet at a tenth of the tets). The float volume is the weight
// both of the share and of the covered volume it is divided by, so each original tet still hands
// out exactly its amount (to double rounding); only the split between new tets moves, by 1e-7.
struct KeptOverlap {
  TetId original;
  float volume;
};

// The overlaps of one block of new tets: those of new tet j are entries[offsets[j - first] ..
// offsets[j - first + 1]).
struct BlockOverlaps {
  std::vector<std::uint32_t> offsets;
  std::vector<KeptOverlap> entries;
};

struct Scratch {
  std::vector<TetId> candidates;
  std::vector<Overlap> overlaps;
  std::vector<std::pair<double, double>> votes;  // (value, volume) of a categorical array
};

std::int32_t material_of(const MeshData& m, std::size_t t) { return m.tet_material.empty() ? 0 : m.tet_material[t]; }

// The materials of `m`, sorted: a nearest search for a material that is nowhere would scan the
// whole grid, so such a search goes straight to the nearest tet of any material.
std::vector<std::int32_t> materials_of(const MeshData& m) {
  std::vector<std::int32_t> list = m.tet_material.empty() ? std::vector<std::int32_t>{0} : m.tet_material;
  std::sort(list.begin(), list.end());
  list.erase(std::unique(list.begin(), list.end()), list.end());
  return list;
}

TetId nearest_tet(const TetGrid& grid, const std::vector<std::int32_t>& materials, const glm::dvec3& point,
                  std::int32_t material) {
  const bool present = std::binary_search(materials.begin(), materials.end(), material);
  return grid.nearest(point, material, /*any_material=*/!present);
}

void load_tet(const MeshData& m, std::size_t t, cell_data::Tet& out) {
  for (int k = 0; k < 4; ++k) out[k] = to_glm(m.positions[m.tets[t][static_cast<std::size_t>(k)]]);
}

// The overlaps of new tet j with the original tets of its material, by increasing original id.
void find_overlaps(const MeshData& original, const TetGrid& grid, const MeshData& simplified, std::size_t j,
                   Scratch& s) {
  s.candidates.clear();
  s.overlaps.clear();
  grid.gather(cell_data::tet_box(simplified, j), material_of(simplified, j), s.candidates);
  cell_data::Tet b, a;
  load_tet(simplified, j, b);
  const cell_data::TetClipper clipper(b);
  for (TetId i : s.candidates) {
    load_tet(original, i, a);
    const double v = clipper.overlap_volume(a);
    if (v > 0) s.overlaps.push_back({i, v});
  }
  // The sums run in the order of the original ids, whatever order the grid gave.
  std::sort(s.overlaps.begin(), s.overlaps.end(), [](const Overlap& x, const Overlap& y) { return x.original < y.original; });
}

// Intensive and categorical values of new tet j from its overlaps.
void average_and_vote(const std::vector<CellField>& in, std::vector<CellField>& out, std::size_t j, Scratch& s) {
  double total = 0;
  for (const Overlap& o : s.overlaps) total += o.volume;
  for (std::size_t f = 0; f < in.size(); ++f) {
    const std::size_t c = static_cast<std::size_t>(in[f].components);
    if (out[f].kind == CellFieldKind::kIntensive) {
      for (std::size_t k = 0; k < c; ++k) {
        double sum = 0;
        for (const Overlap& o : s.overlaps) sum += o.volume * in[f].values[o.original * c + k];
        out[f].values[j * c + k] = sum / total;
      }
    } else if (out[f].kind == CellFieldKind::kCategorical) {
      for (std::size_t k = 0; k < c; ++k) {
        s.votes.clear();
        for (const Overlap& o : s.overlaps) s.votes.emplace_back(in[f].values[o.original * c + k], o.volume);
        std::sort(s.votes.begin(), s.votes.end());
        double best_value = s.votes[0].first, best_volume = -1;
        for (std::size_t a = 0; a < s.votes.size();) {
          std::size_t b = a;
          double volume = 0;
          for (; b < s.votes.size() && s.votes[b].first == s.votes[a].first; ++b) volume += s.votes[b].second;
          if (volume > best_volume) {  // ascending values: a tie keeps the smaller one
            best_volume = volume;
            best_value = s.votes[a].first;
          }
          a = b;
        }
        out[f].values[j * c + k] = best_value;
      }
    }
  }
}

void check_fields(const MeshData& original) {
  for (const CellField& f : original.cell_fields) {
    if (f.components < 1 || f.values.size() != original.tets.size() * static_cast<std::size_t>(f.components))
      throw InputError("cell array '" + f.name + "': " + std::to_string(f.values.size()) + " values for " +
                       std::to_string(original.tets.size()) + " tets of " + std::to_string(f.components) +
                       " component(s)");
  }
}

}  // namespace

const char* cell_kind_name(CellFieldKind kind) {
  switch (kind) {
    case CellFieldKind::kCategorical: return "categorical";
    case CellFieldKind::kExtensive: return "extensive";
    default: return "intensive";
  }
}

void apply_cell_kinds(std::vector<CellField>& fields, const CellRemapOptions& options) {
  const auto set = [&](const std::vector<std::string>& names, CellFieldKind kind, const char* option) {
    for (const std::string& name : names) {
      const auto it = std::find_if(fields.begin(), fields.end(), [&](const CellField& f) { return f.name == name; });
      if (it == fields.end()) {
        std::string present;
        for (const CellField& f : fields) present += (present.empty() ? "'" : ", '") + f.name + "'";
        throw InputError(std::string(option) + " " + name + ": the input has no cell array of that name (its cell arrays: " +
                         (present.empty() ? "none" : present) + ")");
      }
      it->kind = kind;
    }
  };
  set(options.categorical, CellFieldKind::kCategorical, "--categorical");
  set(options.extensive, CellFieldKind::kExtensive, "--extensive");
}

CellRemapReport remap_cell_fields(const MeshData& original, MeshData& simplified, const CellRemapOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  CellRemapReport report;
  simplified.cell_fields.clear();
  if (original.cell_fields.empty()) return report;
  check_fields(original);
  // `out` is made first, with the kinds the options give; the values are read from `original`.
  const std::vector<CellField>& in = original.cell_fields;
  const std::size_t nj = simplified.tets.size();
  std::vector<CellField>& out = simplified.cell_fields;
  for (const CellField& f : in) out.push_back({f.name, f.components, f.kind, std::vector<double>(nj * static_cast<std::size_t>(f.components), 0.0)});
  apply_cell_kinds(out, options);
  const bool has_extensive = std::any_of(out.begin(), out.end(), [](const CellField& f) { return f.kind == CellFieldKind::kExtensive; });

  const TetGrid grid(original);
  const std::size_t blocks = (nj + kBlock - 1) / kBlock;
  std::vector<BlockOverlaps> kept(has_extensive ? blocks : 0);
  std::vector<std::vector<TetId>> uncovered(blocks);  // new tets without overlap, per block
  std::vector<std::uint64_t> pairs(blocks, 0);
  std::vector<double> block_volume(blocks, 0.0);
  parallel::PerThread<Scratch> scratch;
  parallel::for_range<std::size_t>(0, blocks, 1, "remap_cell_fields", [&](std::size_t b0, std::size_t b1) {
    Scratch& s = scratch.local();
    for (std::size_t b = b0; b < b1; ++b) {
      const std::size_t first = b * kBlock, last = std::min(nj, first + kBlock);
      if (has_extensive) kept[b].offsets.assign(1, 0);
      for (std::size_t j = first; j < last; ++j) {
        find_overlaps(original, grid, simplified, j, s);
        pairs[b] += s.overlaps.size();
        for (const Overlap& o : s.overlaps) block_volume[b] += o.volume;
        if (s.overlaps.empty()) {
          uncovered[b].push_back(static_cast<TetId>(j));
        } else {
          average_and_vote(in, out, j, s);
        }
        if (has_extensive) {
          for (const Overlap& o : s.overlaps) kept[b].entries.push_back({o.original, static_cast<float>(o.volume)});
          kept[b].offsets.push_back(static_cast<std::uint32_t>(kept[b].entries.size()));
        }
      }
    }
  });
  double covered_total = 0;
  for (std::size_t b = 0; b < blocks; ++b) {
    report.overlap_pairs += pairs[b];
    covered_total += block_volume[b];
  }

  // New tets that overlap no original tet of their material: the nearest one's values.
  std::vector<TetId> lonely;
  for (const auto& list : uncovered) lonely.insert(lonely.end(), list.begin(), list.end());
  report.nearest_new_tets = lonely.size();
  const std::vector<std::int32_t> original_materials = lonely.empty() ? std::vector<std::int32_t>{} : materials_of(original);
  parallel::for_range<std::size_t>(0, lonely.size(), 16, "remap_cell_fields_nearest", [&](std::size_t a, std::size_t b) {
    for (std::size_t k = a; k < b; ++k) {
      const TetId j = lonely[k];
      const TetId i = nearest_tet(grid, original_materials, cell_data::tet_centroid(simplified, j), material_of(simplified, j));
      if (i == kInvalid) continue;
      for (std::size_t f = 0; f < in.size(); ++f) {
        if (out[f].kind == CellFieldKind::kExtensive) continue;
        const std::size_t c = static_cast<std::size_t>(in[f].components);
        for (std::size_t x = 0; x < c; ++x) out[f].values[j * c + x] = in[f].values[i * c + x];
      }
    }
  });

  // Covered volume of every original tet, summed in block order (deterministic).
  std::vector<double> covered(has_extensive ? original.tets.size() : 0, 0.0);
  double original_total = 0;
  if (has_extensive) {
    for (const BlockOverlaps& block : kept)
      for (const KeptOverlap& o : block.entries) covered[o.original] += o.volume;
  }
  for (std::size_t i = 0; i < original.tets.size(); ++i) {
    cell_data::Tet a;
    load_tet(original, i, a);
    original_total += cell_data::tet_volume(a[0], a[1], a[2], a[3]);
  }
  if (has_extensive) {
    parallel::for_range<std::size_t>(0, blocks, 1, "remap_cell_fields_extensive", [&](std::size_t b0, std::size_t b1) {
      for (std::size_t b = b0; b < b1; ++b) {
        const std::size_t first = b * kBlock, last = std::min(nj, first + kBlock);
        for (std::size_t j = first; j < last; ++j) {
          const KeptOverlap* o0 = kept[b].entries.data() + kept[b].offsets[j - first];
          const KeptOverlap* o1 = kept[b].entries.data() + kept[b].offsets[j - first + 1];
          for (std::size_t f = 0; f < in.size(); ++f) {
            if (out[f].kind != CellFieldKind::kExtensive) continue;
            const std::size_t c = static_cast<std::size_t>(in[f].components);
            for (std::size_t k = 0; k < c; ++k) {
              double sum = 0;
              for (const KeptOverlap* o = o0; o != o1; ++o)
                if (o->volume > 0)  // a volume below float's range counts for nothing, in covered too
                  sum += in[f].values[o->original * c + k] * (static_cast<double>(o->volume) / covered[o->original]);
              out[f].values[j * c + k] = sum;
            }
          }
        }
      }
    });
    kept = {};
    // Original tets that no new tet of their material covers: their amount to the nearest one.
    std::optional<TetGrid> new_grid;
    std::vector<std::int32_t> new_materials;
    for (std::size_t i = 0; i < original.tets.size(); ++i) {
      if (covered[i] > 0) continue;
      if (!new_grid) {
        new_grid.emplace(simplified);
        new_materials = materials_of(simplified);
      }
      ++report.nearest_original_tets;
      const TetId j = nearest_tet(*new_grid, new_materials, cell_data::tet_centroid(original, i), material_of(original, i));
      if (j == kInvalid) continue;
      for (std::size_t f = 0; f < in.size(); ++f) {
        if (out[f].kind != CellFieldKind::kExtensive) continue;
        const std::size_t c = static_cast<std::size_t>(in[f].components);
        for (std::size_t k = 0; k < c; ++k) out[f].values[j * c + k] += in[f].values[i * c + k];
      }
    }
  }
  report.covered_volume_fraction = original_total > 0 ? covered_total / original_total : 0;
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

}  // namespace topotet
