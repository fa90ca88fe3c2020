#include "quadric.h"

#include <cmath>

namespace topotet {
namespace {

// Index of A(i, j), i <= j, in the packed upper triangle.
inline int tri_index(int n, int i, int j) { return i * n - i * (i - 1) / 2 + (j - i); }

}  // namespace

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

void quadric_add(double* q, const double* other, int n) {
  const int size = quadric_size(n);
  for (int i = 0; i < size; ++i) q[i] += other[i];
}

double quadric_eval(const double* q, int n, const double* x) {
  const double* b = q + n * (n + 1) / 2;
  double s = b[n];
  int k = 0;
  for (int i = 0; i < n; ++i) {
    s += 2.0 * b[i] * x[i] + q[k++] * x[i] * x[i];
    for (int j = i + 1; j < n; ++j) s += 2.0 * q[k++] * x[i] * x[j];
  }
  return s > 0.0 ? s : 0.0;  // rounding can make a PSD form slightly negative
}

namespace {

// Solves the m x m system in `m` (augmented: column m is the right-hand side) by Gaussian
// elimination with partial pivoting into y. False when a pivot is tiny relative to the largest
// diagonal entry (a nearly flat direction) or the result is not finite.
bool solve_dense(double (&m)[kMaxQuadricDim][kMaxQuadricDim + 1], int n, double* y) {
  double max_diag = 0.0;
  for (int i = 0; i < n; ++i) max_diag = std::fmax(max_diag, std::fabs(m[i][i]));
  if (!(max_diag > 0.0)) return false;
  for (int col = 0; col < n; ++col) {
    int piv = col;
    for (int r = col + 1; r < n; ++r)
      if (std::fabs(m[r][col]) > std::fabs(m[piv][col])) piv = r;
    // A pivot this small relative to the largest diagonal entry means a (nearly) flat direction.
    if (std::fabs(m[piv][col]) < 1e-9 * max_diag) return false;
    if (piv != col)
      for (int c = col; c <= n; ++c) std::swap(m[piv][c], m[col][c]);
    for (int r = col + 1; r < n; ++r) {
      const double f = m[r][col] / m[col][col];
      for (int c = col; c <= n; ++c) m[r][c] -= f * m[col][c];
    }
  }
  double r[kMaxQuadricDim];
  for (int i = n - 1; i >= 0; --i) {
    double s = m[i][n];
    for (int j = i + 1; j < n; ++j) s -= m[i][j] * r[j];
    r[i] = s / m[i][i];
    if (!std::isfinite(r[i])) return false;
  }
  for (int i = 0; i < n; ++i) y[i] = r[i];
  return true;
}

}  // namespace

bool quadric_minimize(const double* q, int n, double* x) {
  // Solve A x = -b on a dense copy.
  double m[kMaxQuadricDim][kMaxQuadricDim + 1];
  const double* b = q + n * (n + 1) / 2;
  for (int i = 0; i < n; ++i) {
    for (int j = i; j < n; ++j) m[i][j] = m[j][i] = q[tri_index(n, i, j)];
    m[i][n] = -b[i];
  }
  return solve_dense(m, n, x);
}

bool quadric_minimize_fields(const double* q, int n, double* x) {
  // With x = (p, f): dQ/df = 0  <=>  A_ff f = -(b_f + A_fp p).
  const int k = n - 3;
  if (k <= 0) return false;
  double m[kMaxQuadricDim][kMaxQuadricDim + 1];
  const double* b = q + n * (n + 1) / 2;
  for (int i = 0; i < k; ++i) {
    for (int j = i; j < k; ++j) m[i][j] = m[j][i] = q[tri_index(n, 3 + i, 3 + j)];
    double rhs = -b[3 + i];
    for (int d = 0; d < 3; ++d) rhs -= q[tri_index(n, d, 3 + i)] * x[d];
    m[i][k] = rhs;
  }
  return solve_dense(m, k, x + 3);
}

}  // namespace topotet
