#include "quadric.h"

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

void quadric_add_tet_one_field(double* q, const double* points, double weight) {
  constexpr int n = 4;
  const double* p0 = points;
  double e[3][3], df[3];
  for (int i = 0; i < 3; ++i) {
    for (int d = 0; d < 3; ++d) e[i][d] = points[(i + 1) * n + d] - p0[d];
    df[i] = points[(i + 1) * n + 3] - p0[3];
  }
  auto cross = [](const double* a, const double* b, double* out) {
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
  };
  double c23[3], c31[3], c12[3];
  cross(e[1], e[2], c23);
  cross(e[2], e[0], c31);
  cross(e[0], e[1], c12);
  const double det = e[0][0] * c23[0] + e[0][1] * c23[1] + e[0][2] * c23[2];
  if (det == 0.0) return;
  // Gradient of the linear interpolant (Cramer's rule: g . e_i = df_i).
  double normal[4];
  for (int d = 0; d < 3; ++d) normal[d] = (df[0] * c23[d] + df[1] * c31[d] + df[2] * c12[d]) / det;
  normal[3] = -1.0;
  const double norm2 = normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2] + 1.0;
  const double s = weight / norm2;
  const double offset = normal[0] * p0[0] + normal[1] * p0[1] + normal[2] * p0[2] + normal[3] * p0[3];
  if (!std::isfinite(s * offset * offset)) return;
  // A = s n n^T, b = -A p0 = -s (n . p0) n, c = s (n . p0)^2.
  int k = 0;
  for (int i = 0; i < n; ++i)
    for (int j = i; j < n; ++j) q[k++] += s * normal[i] * normal[j];
  for (int i = 0; i < n; ++i) q[k++] -= s * offset * normal[i];
  q[k] += s * offset * offset;
}

void quadric_add(double* q, const double* other, int n) { quadric_detail::add<0>(q, other, n); }

double quadric_eval(const double* q, int n, const double* x) { return quadric_detail::eval<0>(q, n, x); }

bool quadric_minimize(const double* q, int n, double* x) { return quadric_detail::minimize<0>(q, n, x); }

bool quadric_minimize_fields(const double* q, int n, double* x) { return quadric_detail::minimize_fields<0>(q, n, x); }

}  // namespace topotet
