#include "cost/quadric.h"

#include <cmath>

namespace topotet {

using quadric_detail::tri_index;

void quadric_add_simplex(double* q, int n, const double* points, int count, double weight) {
  // Orthonormal basis of the directions p_i - p_0 by modified Gram-Schmidt.
  double basis[3][kMaxQuadricDim];
  int dims = 0;
  for (int i = 1; i < count; ++i) {
    double* e = basis[dims];
    double norm0 = 0.0;
    for (int r = 0; r < n; ++r) {
      e[r] = points[i * n + r] - points[r];
      norm0 += e[r] * e[r];
    }
    for (int d = 0; d < dims; ++d) {
      double dot = 0.0;
      for (int r = 0; r < n; ++r) dot += e[r] * basis[d][r];
      for (int r = 0; r < n; ++r) e[r] -= dot * basis[d][r];
    }
    double norm = 0.0;
    for (int r = 0; r < n; ++r) norm += e[r] * e[r];
    if (!(norm > 1e-24 * norm0) || norm == 0.0) continue;  // dependent direction: drop it
    norm = 1.0 / std::sqrt(norm);
    for (int r = 0; r < n; ++r) e[r] *= norm;
    ++dims;
  }
  // A = w (I - sum e e^T); b = -A p0; c = p0^T A p0.
  double* b = q + n * (n + 1) / 2;
  double ap0[kMaxQuadricDim];
  for (int i = 0; i < n; ++i) ap0[i] = 0.0;
  for (int i = 0; i < n; ++i)
    for (int j = i; j < n; ++j) {
      double a = i == j ? 1.0 : 0.0;
      for (int d = 0; d < dims; ++d) a -= basis[d][i] * basis[d][j];
      a *= weight;
      q[tri_index(n, i, j)] += a;
      ap0[i] += a * points[j];
      if (i != j) ap0[j] += a * points[i];
    }
  double c = 0.0;
  for (int i = 0; i < n; ++i) {
    b[i] -= ap0[i];
    c += points[i] * ap0[i];
  }
  b[n] += c;  // c is stored right after b
}

void quadric_add_simplex_positions(double* q, int n, const double* points, int count, double weight) {
  double positions[3 * 3];
  for (int i = 0; i < count; ++i)
    for (int d = 0; d < 3; ++d) positions[i * 3 + d] = points[i * n + d];
  double q3[quadric_size(3)] = {};
  quadric_add_simplex(q3, 3, positions, count, weight);
  // Embed: the position block of A, the position part of b, and c.
  for (int i = 0; i < 3; ++i)
    for (int j = i; j < 3; ++j) q[tri_index(n, i, j)] += q3[tri_index(3, i, j)];
  double* b = q + n * (n + 1) / 2;
  const double* b3 = q3 + 3 * 4 / 2;
  for (int i = 0; i < 3; ++i) b[i] += b3[i];
  b[n] += b3[3];
}

namespace {

template <int kN, int kCount>
double add_field_simplex(double* q, int n_runtime, const double* points, const double* weights) {
  constexpr int count = kCount;
  const int n = quadric_detail::dim<kN>(n_runtime);
  const int k = n - 3;
  const double* p0 = points;
  // Gradients g_c of the interpolants: g_c . e_i = df_i for the edge vectors e_i = p_i - p_0.
  double e[3][3];
  for (int i = 0; i + 1 < count; ++i)
    for (int d = 0; d < 3; ++d) e[i][d] = points[(i + 1) * n + d] - p0[d];
  constexpr int kK = kN > 0 ? kN - 3 : kMaxQuadricDim - 3;
  double grad[kK > 0 ? kK : 1][3];
  double measure = 0.0;
  if constexpr (count == 4) {
    // Cramer's rule: g = (df0 (e1 x e2) + df1 (e2 x e0) + df2 (e0 x e1)) / det, det = 6 volume.
    const auto cross = [](const double* a, const double* b, double* out) {
      out[0] = a[1] * b[2] - a[2] * b[1];
      out[1] = a[2] * b[0] - a[0] * b[2];
      out[2] = a[0] * b[1] - a[1] * b[0];
    };
    double c12[3], c20[3], c01[3];
    cross(e[1], e[2], c12);
    cross(e[2], e[0], c20);
    cross(e[0], e[1], c01);
    const double det = e[0][0] * c12[0] + e[0][1] * c12[1] + e[0][2] * c12[2];
    if (det == 0.0) return 0.0;
    measure = std::fabs(det) / 6.0;
    const double inv = 1.0 / det;
    for (int c = 0; c < k; ++c) {
      const double d0 = points[n + 3 + c] - p0[3 + c], d1 = points[2 * n + 3 + c] - p0[3 + c],
                   d2 = points[3 * n + 3 + c] - p0[3 + c];
      for (int d = 0; d < 3; ++d) grad[c][d] = (d0 * c12[d] + d1 * c20[d] + d2 * c01[d]) * inv;
    }
  } else {
    static_assert(count == 3);
    // In the plane: g = a e0 + b e1 with the Gram system [e0.e0 e0.e1; e0.e1 e1.e1] (a, b) = df;
    // its determinant is |e0 x e1|^2 = (2 area)^2.
    const double g00 = e[0][0] * e[0][0] + e[0][1] * e[0][1] + e[0][2] * e[0][2];
    const double g01 = e[0][0] * e[1][0] + e[0][1] * e[1][1] + e[0][2] * e[1][2];
    const double g11 = e[1][0] * e[1][0] + e[1][1] * e[1][1] + e[1][2] * e[1][2];
    const double det = g00 * g11 - g01 * g01;
    if (!(det > 1e-24 * g00 * g11)) return 0.0;  // collinear corners: no plane
    measure = 0.5 * std::sqrt(det);
    const double inv = 1.0 / det;
    for (int c = 0; c < k; ++c) {
      const double d0 = points[n + 3 + c] - p0[3 + c], d1 = points[2 * n + 3 + c] - p0[3 + c];
      const double a = (g11 * d0 - g01 * d1) * inv, b = (g00 * d1 - g01 * d0) * inv;
      for (int d = 0; d < 3; ++d) grad[c][d] = a * e[0][d] + b * e[1][d];
    }
  }
  if (k <= 0) return measure;
  // Component c contributes w (g.x - f - o)^2 with o = g.p0 - f0: the rank-1 form of the normal
  // (g, -e_c) with A = w nu nu^T, b = -w o nu, c = w o^2 (w = measure x weight). Summed:
  double w[kK > 0 ? kK : 1], offset[kK > 0 ? kK : 1];
  double aa[6] = {}, bp[3] = {}, cc = 0.0;
  for (int c = 0; c < k; ++c) {
    const double* g = grad[c];
    w[c] = measure * weights[c];
    offset[c] = g[0] * p0[0] + g[1] * p0[1] + g[2] * p0[2] - p0[3 + c];
    if (!std::isfinite(w[c] * offset[c] * offset[c] * (1.0 + g[0] * g[0] + g[1] * g[1] + g[2] * g[2]))) return 0.0;
    const double wg[3] = {w[c] * g[0], w[c] * g[1], w[c] * g[2]};
    aa[0] += wg[0] * g[0];
    aa[1] += wg[0] * g[1];
    aa[2] += wg[0] * g[2];
    aa[3] += wg[1] * g[1];
    aa[4] += wg[1] * g[2];
    aa[5] += wg[2] * g[2];
    for (int i = 0; i < 3; ++i) bp[i] -= offset[c] * wg[i];
    cc += w[c] * offset[c] * offset[c];
  }
  q[tri_index(n, 0, 0)] += aa[0];
  q[tri_index(n, 0, 1)] += aa[1];
  q[tri_index(n, 0, 2)] += aa[2];
  q[tri_index(n, 1, 1)] += aa[3];
  q[tri_index(n, 1, 2)] += aa[4];
  q[tri_index(n, 2, 2)] += aa[5];
  for (int i = 0; i < 3; ++i)
    for (int c = 0; c < k; ++c) q[tri_index(n, i, 3 + c)] -= w[c] * grad[c][i];
  for (int c = 0; c < k; ++c) q[tri_index(n, 3 + c, 3 + c)] += w[c];
  double* b = q + n * (n + 1) / 2;
  for (int i = 0; i < 3; ++i) b[i] += bp[i];
  for (int c = 0; c < k; ++c) b[3 + c] += w[c] * offset[c];
  b[n] += cc;
  return measure;
}

}  // namespace

double quadric_add_field_simplex(double* q, int n, const double* points, int count, const double* weights) {
  // Instantiated for the common dimensions (one to four field components), where the loops unroll.
  if (count == 4) {
    switch (n) {
      case 4: return add_field_simplex<4, 4>(q, n, points, weights);
      case 5: return add_field_simplex<5, 4>(q, n, points, weights);
      case 6: return add_field_simplex<6, 4>(q, n, points, weights);
      case 7: return add_field_simplex<7, 4>(q, n, points, weights);
      default: return add_field_simplex<0, 4>(q, n, points, weights);
    }
  }
  if (count == 3) return add_field_simplex<0, 3>(q, n, points, weights);
  return 0.0;
}

void quadric_add(double* q, const double* other, int n) { quadric_detail::add<0>(q, other, n); }

double quadric_eval(const double* q, int n, const double* x) { return quadric_detail::eval<0>(q, n, x); }

bool quadric_minimize(const double* q, int n, double* x) { return quadric_detail::minimize<0>(q, n, x); }

bool quadric_minimize_fields(const double* q, int n, double* x) { return quadric_detail::minimize_fields<0>(q, n, x); }

}  // namespace topotet
