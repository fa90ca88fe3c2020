// Closest-point throughput of the tolerance check's Embree reference (engine/guarantees/surface_tolerance.h)
// on a 1M-triangle scene: a latitude-longitude sphere of radius 1 (1000 x 500 quads, 1,000,000
// triangles, one label). Two kinds of queries from random points within 0.01 of the sphere:
//   within    "is the surface within h = 0.001?" (the kernel's query; stops at the first hit)
//   distance  the exact closest distance, unbounded radius (the metric's query)
// Each thread runs its own queries; prints one JSON line per (kind, threads) with queries per
// second per thread.
//   bench_closest_point [queries_per_thread=1000000] [max_threads=2]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <random>
#include <thread>
#include <vector>

#include "guarantees/surface_tolerance.h"

namespace {

topotet::SurfaceSoup lat_long_sphere(int nu, int nv) {
  topotet::SurfaceSoup soup;
  soup.face_labels = 1;
  for (int j = 0; j <= nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const double theta = std::numbers::pi * j / nv, phi = 2 * std::numbers::pi * i / nu;
      soup.positions.push_back({std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)});
    }
  auto id = [&](int i, int j) { return static_cast<topotet::VertId>(j * nu + (i % nu)); };
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      soup.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      soup.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  soup.triangle_label.assign(soup.triangles.size(), 0);
  return soup;
}

}  // namespace

int main(int argc, char** argv) {
  const long queries = argc > 1 ? std::atol(argv[1]) : 1'000'000;
  const int max_threads = argc > 2 ? std::atoi(argv[2]) : 2;
  const auto build_start = std::chrono::steady_clock::now();
  topotet::SurfaceSoup soup = lat_long_sphere(1000, 500);
  const std::size_t triangles = soup.triangles.size();
  const topotet::SurfaceReference reference(std::move(soup));
  const double build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - build_start).count();
  std::printf("{\"scene_triangles\": %zu, \"build_seconds\": %.3f}\n", triangles, build_seconds);

  for (const char* kind : {"within", "distance"}) {
    const bool within = kind[0] == 'w';
    for (int threads = 1; threads <= max_threads; ++threads) {
      std::vector<std::thread> pool;
      std::vector<long> hits(static_cast<std::size_t>(threads), 0);
      const auto start = std::chrono::steady_clock::now();
      for (int t = 0; t < threads; ++t)
        pool.emplace_back([&, t] {
          std::mt19937_64 rng(static_cast<std::uint64_t>(t) + 1);
          std::normal_distribution<double> gauss;
          std::uniform_real_distribution<double> radius(0.99, 1.01);
          long n = 0;
          for (long q = 0; q < queries; ++q) {
            glm::dvec3 p{gauss(rng), gauss(rng), gauss(rng)};
            p *= radius(rng) / std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z);
            n += within ? (reference.within(p, 0, 0.001) ? 1 : 0) : (reference.distance(p, 0, 10.0) < 0.001 ? 1 : 0);
          }
          hits[static_cast<std::size_t>(t)] = n;
        });
      for (auto& th : pool) th.join();
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      long total_hits = 0;
      for (long h : hits) total_hits += h;
      std::printf("{\"kind\": \"%s\", \"threads\": %d, \"queries\": %ld, \"seconds\": %.3f, "
                  "\"queries_per_second_per_thread\": %.0f, \"hit_fraction\": %.3f}\n",
                  kind, threads, queries * threads, seconds, static_cast<double>(queries) / seconds,
                  static_cast<double>(total_hits) / static_cast<double>(queries * threads));
    }
  }
  return 0;
}
