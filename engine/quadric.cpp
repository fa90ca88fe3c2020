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

bool quadric_minimize(const double* q, int n, double* x) {
  // Solve A x = -b by Gaussian elimination with partial pivoting on a dense copy.
  double m[kMaxQuadricDim][kMaxQuadricDim + 1];
  const double* b = q + n * (n + 1) / 2;
  double max_diag = 0.0;
  for (int i = 0; i < n; ++i) {
    for (int j = i; j < n; ++j) m[i][j] = m[j][i] = q[tri_index(n, i, j)];
    m[i][n] = -b[i];
    max_diag = std::fmax(max_diag, std::fabs(m[i][i]));
  }
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
  for (int i = n - 1; i >= 0; --i) {
    double s = m[i][n];
    for (int j = i + 1; j < n; ++j) s -= m[i][j] * x[j];
    x[i] = s / m[i][i];
    if (!std::isfinite(x[i])) return false;
  }
  return true;
}

}  // namespace topotet
