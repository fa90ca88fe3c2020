// cgal_segmentation: a multi-material tet mesh made the way medical users make one, with CGAL
// Mesh_3 on a labelled voxel image (Labeled_mesh_domain_3 on a labelling function that returns the
// label of the voxel containing the point). The image is synthetic and built here: a "skin"
// region (an ellipsoidal body) enclosing seven "organs" (overlapping and adjacent ellipsoids, a
// blobby heart with an enclosed cavity, a bent tube), so the surfaces are smooth organ-like shapes
// carrying the voxel-scale staircase creases of real segmentations. Or a raw 8-bit volume
// labelled by thresholds (--raw). Output: MEDIT .mesh, the subdomain index as the material of each
// tet, and the surface facets (Triangles) with one ref per pair of subdomains they separate.
//
// Deterministic: sequential CGAL, CGAL::get_default_random() seeded (--seed), no time limits on
// the optimisers. See bench/cgal/README.md.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Labeled_mesh_domain_3.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_facet_topology.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/Random.h>
#include <CGAL/make_mesh_3.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <numbers>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "medit_io.h"

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;
using Mesh_domain = CGAL::Labeled_mesh_domain_3<K>;
using Tr = CGAL::Mesh_triangulation_3<Mesh_domain, CGAL::Default, CGAL::Sequential_tag>::type;
using C3t3 = CGAL::Mesh_complex_3_in_triangulation_3<Tr>;
using Criteria = CGAL::Mesh_criteria_3<Tr>;

constexpr const char* kUsage = R"(usage: cgal_segmentation -o OUT.mesh [options]

CGAL Mesh_3 on a labelled voxel image (Labeled_mesh_domain_3): a synthetic segmentation (a skin
region enclosing 7 organs: ellipsoids, a blobby heart with an enclosed cavity, a bent tube) or a
raw 8-bit volume labelled by thresholds. Writes MEDIT: Vertices, Tetrahedra (ref = subdomain
label), Triangles (ref = one id per pair of labels they separate). Deterministic.

options:
  -o, --output FILE          output .mesh (required)
  --size N                   synthetic image: N^3 voxels of size 1 (default 128)
  --raw FILE NX NY NZ        label a raw uint8 volume instead (voxel size 1)
  --thresholds A,B,...       with --raw: label = number of thresholds <= value (default 128)
  --facet-angle DEG          (default 30)
  --facet-size S             (default 2 voxels)
  --facet-distance D         (default 0.75 voxel)
  --cell-radius-edge-ratio R (default 3)
  --cell-size S              (default 2 voxels; the defaults give 412k tets at --size 128)
  --no-perturb, --no-exude   skip CGAL's sliver perturber / exuder (both run by default)
  --no-manifold              no facet_topology = MANIFOLD criterion (on by default: without it
                             Mesh_3 may leave non-manifold edges on the boundary, which CGAL's
                             own remesher then refuses to load)
  --no-triangles             write no Triangles
  --seed N                   CGAL::get_default_random() seed (default 0)
  -h, --help                 this text
)";

struct Image {
  int nx = 0, ny = 0, nz = 0;
  std::vector<std::uint8_t> labels;  // x fastest
  int at(int i, int j, int k) const { return labels[(static_cast<std::size_t>(k) * ny + j) * nx + i]; }
};

struct Ellipsoid {
  std::array<double, 3> c, r;
  double rot_z = 0.0;  // radians, about z through c
  bool contains(double x, double y, double z) const {
    const double dx = x - c[0], dy = y - c[1], dz = z - c[2];
    const double cs = std::cos(rot_z), sn = std::sin(rot_z);
    const double u = cs * dx + sn * dy, v = -sn * dx + cs * dy;
    return (u * u) / (r[0] * r[0]) + (v * v) / (r[1] * r[1]) + (dz * dz) / (r[2] * r[2]) <= 1.0;
  }
};

// The synthetic segmentation, in coordinates normalised to [0,1]^3 (voxel centres). Priority:
// the first shape that contains a voxel gives its label.
int synthetic_label(double x, double y, double z) {
  static const Ellipsoid body{{0.5, 0.5, 0.5}, {0.47, 0.38, 0.48}};
  static const Ellipsoid ventricle{{0.60, 0.42, 0.77}, {0.06, 0.045, 0.05}};
  static const Ellipsoid liver_a{{0.36, 0.45, 0.55}, {0.25, 0.17, 0.15}, 0.44};
  static const Ellipsoid liver_b{{0.52, 0.40, 0.64}, {0.15, 0.12, 0.10}, -0.3};
  static const Ellipsoid stomach{{0.66, 0.38, 0.52}, {0.14, 0.10, 0.12}, 0.2};
  static const Ellipsoid kidney_l{{0.28, 0.65, 0.32}, {0.08, 0.06, 0.14}, 0.3};
  static const Ellipsoid kidney_r{{0.72, 0.65, 0.32}, {0.08, 0.06, 0.14}, -0.3};
  if (!body.contains(x, y, z)) return 0;
  if (ventricle.contains(x, y, z)) return 6;
  // Heart: a metaball of three Gaussians.
  {
    static const std::array<std::array<double, 3>, 3> centres{{{0.56, 0.43, 0.80}, {0.66, 0.44, 0.76}, {0.60, 0.37, 0.71}}};
    double f = 0.0;
    for (const auto& ce : centres) {
      const double d2 = (x - ce[0]) * (x - ce[0]) + (y - ce[1]) * (y - ce[1]) + (z - ce[2]) * (z - ce[2]);
      f += std::exp(-d2 / (0.075 * 0.075));
    }
    if (f > 0.6) return 5;
  }
  // Aorta: a bent tube along z.
  if (z > 0.12 && z < 0.86) {
    const double cx = 0.5 + 0.06 * std::sin(2.0 * std::numbers::pi * z), cy = 0.60;
    if ((x - cx) * (x - cx) + (y - cy) * (y - cy) < 0.035 * 0.035) return 7;
  }
  if (liver_a.contains(x, y, z) || liver_b.contains(x, y, z)) return 2;
  if (stomach.contains(x, y, z)) return 8;
  if (kidney_l.contains(x, y, z)) return 3;
  if (kidney_r.contains(x, y, z)) return 4;
  return 1;  // skin / body
}

Image synthetic_image(int n) {
  Image im{n, n, n, std::vector<std::uint8_t>(static_cast<std::size_t>(n) * n * n)};
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        im.labels[(static_cast<std::size_t>(k) * n + j) * n + i] = static_cast<std::uint8_t>(
            synthetic_label((i + 0.5) / n, (j + 0.5) / n, (k + 0.5) / n));
  return im;
}

Image raw_image(const std::string& path, int nx, int ny, int nz, const std::vector<int>& thresholds) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot open");
  const std::size_t n = static_cast<std::size_t>(nx) * ny * nz;
  std::vector<std::uint8_t> bytes(n);
  in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(n));
  if (static_cast<std::size_t>(in.gcount()) != n)
    throw std::runtime_error(path + ": shorter than " + std::to_string(nx) + "x" + std::to_string(ny) + "x" +
                             std::to_string(nz) + " bytes");
  Image im{nx, ny, nz, std::vector<std::uint8_t>(n)};
  for (std::size_t i = 0; i < n; ++i) {
    int label = 0;
    for (int t : thresholds) label += bytes[i] >= t ? 1 : 0;
    im.labels[i] = static_cast<std::uint8_t>(label);
  }
  return im;
}

struct Args {
  std::string output;
  int size = 128;
  std::string raw;
  int raw_n[3] = {0, 0, 0};
  std::vector<int> thresholds{128};
  double facet_angle = 30.0, facet_size = 2.0, facet_distance = 0.75, cell_radius_edge_ratio = 3.0, cell_size = 2.0;
  bool perturb = true, exude = true, triangles = true, manifold = true;
  int seed = 0;
};

double parse_double(const std::string& s, const std::string& what) {
  try {
    std::size_t used = 0;
    const double v = std::stod(s, &used);
    if (used != s.size() || !std::isfinite(v) || v <= 0.0) throw std::invalid_argument(s);
    return v;
  } catch (const std::exception&) {
    throw std::runtime_error(what + ": '" + s + "' is not a positive number");
  }
}

int parse_int(const std::string& s, const std::string& what, int min) {
  try {
    std::size_t used = 0;
    const long v = std::stol(s, &used);
    if (used != s.size() || v < min || v > 1 << 20) throw std::invalid_argument(s);
    return static_cast<int>(v);
  } catch (const std::exception&) {
    throw std::runtime_error(what + ": '" + s + "' is not an integer >= " + std::to_string(min));
  }
}

Args parse(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const auto value = [&](const char* name) -> std::string {
      if (i + 1 >= argc) throw std::runtime_error(std::string(name) + " needs a value");
      return argv[++i];
    };
    if (arg == "-h" || arg == "--help") {
      std::fputs(kUsage, stdout);
      std::exit(0);
    } else if (arg == "-o" || arg == "--output") {
      a.output = value("--output");
    } else if (arg == "--size") {
      a.size = parse_int(value("--size"), "--size", 8);
    } else if (arg == "--raw") {
      a.raw = value("--raw");
      for (int& n : a.raw_n) n = parse_int(value("--raw NX NY NZ"), "--raw NX NY NZ", 2);
    } else if (arg == "--thresholds") {
      a.thresholds.clear();
      std::string list = value("--thresholds"), item;
      for (std::size_t start = 0; start <= list.size();) {
        const std::size_t comma = std::min(list.find(',', start), list.size());
        a.thresholds.push_back(parse_int(list.substr(start, comma - start), "--thresholds", 1));
        start = comma + 1;
      }
      if (a.thresholds.size() > 254) throw std::runtime_error("--thresholds: at most 254 thresholds");
    } else if (arg == "--facet-angle") {
      a.facet_angle = parse_double(value("--facet-angle"), "--facet-angle");
    } else if (arg == "--facet-size") {
      a.facet_size = parse_double(value("--facet-size"), "--facet-size");
    } else if (arg == "--facet-distance") {
      a.facet_distance = parse_double(value("--facet-distance"), "--facet-distance");
    } else if (arg == "--cell-radius-edge-ratio") {
      a.cell_radius_edge_ratio = parse_double(value("--cell-radius-edge-ratio"), "--cell-radius-edge-ratio");
    } else if (arg == "--cell-size") {
      a.cell_size = parse_double(value("--cell-size"), "--cell-size");
    } else if (arg == "--no-perturb") {
      a.perturb = false;
    } else if (arg == "--no-exude") {
      a.exude = false;
    } else if (arg == "--no-manifold") {
      a.manifold = false;
    } else if (arg == "--no-triangles") {
      a.triangles = false;
    } else if (arg == "--seed") {
      a.seed = parse_int(value("--seed"), "--seed", 0);
    } else {
      throw std::runtime_error("unknown argument '" + arg + "' (see --help)");
    }
  }
  if (a.output.empty()) throw std::runtime_error("no output: -o OUT.mesh is required (see --help)");
  return a;
}

int run(const Args& args) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  const Image image = args.raw.empty() ? synthetic_image(args.size)
                                       : raw_image(args.raw, args.raw_n[0], args.raw_n[1], args.raw_n[2], args.thresholds);
  std::map<int, std::size_t> voxels;
  for (std::uint8_t l : image.labels) ++voxels[l];
  std::printf("image %dx%dx%d voxels;", image.nx, image.ny, image.nz);
  for (const auto& [label, count] : voxels) std::printf(" label %d: %zu", label, count);
  std::printf("\n");
  if (voxels.size() < 2) throw std::runtime_error("the image has a single label: nothing to mesh");

  CGAL::get_default_random() = CGAL::Random(static_cast<unsigned int>(args.seed));
  // The label of the voxel containing p (voxel size 1, voxel (i,j,k) = [i,i+1) x ...): the domain
  // is the labelled image itself, staircases included.
  const Image* im = &image;
  const auto label_of = [im](const Point& p) -> int {
    const double x = std::floor(p.x()), y = std::floor(p.y()), z = std::floor(p.z());
    if (x < 0 || y < 0 || z < 0 || x >= im->nx || y >= im->ny || z >= im->nz) return 0;
    return im->at(static_cast<int>(x), static_cast<int>(y), static_cast<int>(z));
  };
  const K::Iso_cuboid_3 box(-1.0, -1.0, -1.0, image.nx + 1.0, image.ny + 1.0, image.nz + 1.0);
  Mesh_domain domain(label_of, box, 1e-6);  // relative error bound of the surface intersections
  namespace P = CGAL::parameters;
  const Criteria criteria(P::facet_angle = args.facet_angle, P::facet_size = args.facet_size,
                          P::facet_distance = args.facet_distance,
                          P::cell_radius_edge_ratio = args.cell_radius_edge_ratio, P::cell_size = args.cell_size,
                          P::facet_topology = args.manifold ? CGAL::MANIFOLD : CGAL::FACET_VERTICES_ON_SURFACE);
  const auto t1 = Clock::now();
  // make_mesh_3 gives the perturber and the exuder the refinement's duration as a time limit by
  // default, which makes the output depend on the machine's speed: no time limit here (0).
  C3t3 c3t3;
  if (args.perturb && args.exude)
    c3t3 = CGAL::make_mesh_3<C3t3>(domain, criteria, P::perturb(P::time_limit = 0.0), P::exude(P::time_limit = 0.0));
  else if (args.perturb)
    c3t3 = CGAL::make_mesh_3<C3t3>(domain, criteria, P::perturb(P::time_limit = 0.0), P::no_exude());
  else if (args.exude)
    c3t3 = CGAL::make_mesh_3<C3t3>(domain, criteria, P::no_perturb(), P::exude(P::time_limit = 0.0));
  else
    c3t3 = CGAL::make_mesh_3<C3t3>(domain, criteria, P::no_perturb(), P::no_exude());
  const auto t2 = Clock::now();

  // To MEDIT: the vertices of the cells in the complex, in the triangulation's order.
  cgal_bench::MeditMesh out;
  std::unordered_map<Tr::Vertex_handle, std::uint32_t> index;
  const auto vertex_id = [&](Tr::Vertex_handle v) {
    const auto [it, inserted] = index.try_emplace(v, static_cast<std::uint32_t>(out.positions.size()));
    if (inserted) out.positions.push_back({v->point().x(), v->point().y(), v->point().z()});
    return it->second;
  };
  for (auto c = c3t3.cells_in_complex_begin(); c != c3t3.cells_in_complex_end(); ++c) {
    std::array<std::uint32_t, 4> t{};
    for (int i = 0; i < 4; ++i) t[i] = vertex_id(c->vertex(i));
    out.tets.push_back(t);
    out.tet_ref.push_back(static_cast<int>(c3t3.subdomain_index(c)));
  }
  std::map<std::pair<int, int>, int> patch_ref;  // (label, label) -> ref 1, 2, ... in label order
  if (args.triangles) {
    for (auto f = c3t3.facets_in_complex_begin(); f != c3t3.facets_in_complex_end(); ++f) {
      const auto c = f->first;
      const int a = c3t3.is_in_complex(c) ? static_cast<int>(c3t3.subdomain_index(c)) : 0;
      const auto n = c->neighbor(f->second);
      const int b = c3t3.is_in_complex(n) ? static_cast<int>(c3t3.subdomain_index(n)) : 0;
      patch_ref.try_emplace({std::min(a, b), std::max(a, b)}, 0);
    }
    int next = 1;
    for (auto& [pair, ref] : patch_ref) ref = next++;
    for (auto f = c3t3.facets_in_complex_begin(); f != c3t3.facets_in_complex_end(); ++f) {
      const auto c = f->first;
      const auto n = c->neighbor(f->second);
      const int a = c3t3.is_in_complex(c) ? static_cast<int>(c3t3.subdomain_index(c)) : 0;
      const int b = c3t3.is_in_complex(n) ? static_cast<int>(c3t3.subdomain_index(n)) : 0;
      std::array<std::uint32_t, 3> tri{};
      for (int i = 0, k = 0; i < 4; ++i)
        if (i != f->second) tri[k++] = index.at(c->vertex(i));
      out.triangles.push_back(tri);
      out.triangle_ref.push_back(patch_ref.at({std::min(a, b), std::max(a, b)}));
    }
  }
  cgal_bench::write_medit(args.output, out);
  const auto t3 = Clock::now();
  const auto sec = [](auto a, auto b) { return std::chrono::duration<double>(b - a).count(); };
  std::map<int, std::size_t> per_label;
  for (int r : out.tet_ref) ++per_label[r];
  std::printf("mesh %zu vertices, %zu tets, %zu surface triangles in %zu patches; image %.2f s, Mesh_3 %.2f s, write %.2f s\n",
              out.positions.size(), out.tets.size(), out.triangles.size(), patch_ref.size(), sec(t0, t1), sec(t1, t2),
              sec(t2, t3));
  for (const auto& [label, count] : per_label) std::printf("  subdomain %d: %zu tets\n", label, count);
  std::printf("wrote %s\n", args.output.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(parse(argc, argv));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cgal_segmentation: %s\n", e.what());
    return 2;
  }
}
