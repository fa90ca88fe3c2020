// Garland–Zhou quadrics in n = 3 + k dimensions (position plus k scaled field values).
//
// A quadric is Q(x) = x^T A x + 2 b^T x + c with A symmetric; it is stored packed in
// quadric_size(n) doubles: the upper triangle of A row by row, then b, then c. The quadric of a
// simplex (segment, triangle, tet) in R^n is its weight times the squared distance from x to the
// simplex's affine hull: A = w (I - E E^T) for an orthonormal basis E of the hull's directions,
// b = -A p0, c = p0^T A p0.
//
// The operations the cost model runs for every candidate edge (add, eval, minimise) are written
// once, as templates on the dimension: kN > 0 fixes n at compile time (the cost model instantiates
// the common n = 3..7, where the loops unroll), kN = 0 reads n at run time (everything else). The
// plain functions below are the run-time forms.
#pragma once

#include <cmath>

namespace topotet {

inline constexpr int kMaxQuadricDim = 3 + 16;  // positions + at most 16 field components

constexpr int quadric_size(int n) { return n * (n + 1) / 2 + n + 1; }

// q += weight * squared distance to the affine hull of `count` points of R^n (rows of `points`,
// each n doubles, contiguous). Degenerate directions are dropped (a flat triangle acts as a line).
void quadric_add_simplex(double* q, int n, const double* points, int count, double weight);

// The same, measured in position space only: the distance from x's position x[0..3) to the affine
// hull of the points' positions; field coordinates are free. For boundary, surface and polyline
// constraints, which are about geometry: in R^n they would also pin the field along the feature
// (weighted by the feature penalty), starving the interior of vertices.
void quadric_add_simplex_positions(double* q, int n, const double* points, int count, double weight);

// q += sum over the field components c = 0 .. n-4 of m * weights[c] * (x[3 + c] - L_c(x[0..3)))^2,
// where L_c is the linear interpolant of component c over `count` points (rows of `points`, n
// doubles each) and m their measure: a tet (count 4, m its volume), or a triangle (count 3, m its
// area; L_c then varies only in the triangle's plane and is constant along its normal). Returns m
// (0 for a flat simplex, which adds nothing). This is the "vertical" distance to the graph of the
// interpolant: the error of the field value at a position, which is what a field error measures.
// The orthogonal distance of quadric_add_simplex is that error divided by sqrt(1 + |grad f|^2),
// which all but ignores the steep regions of a field (cost.h says what that did). One rank-1 term
// per component, sharing the gradient computation.
double quadric_add_field_simplex(double* q, int n, const double* points, int count, const double* weights);

void quadric_add(double* q, const double* other, int n);

double quadric_eval(const double* q, int n, const double* x);

// Minimiser of Q. Returns false when A is too ill-conditioned to trust (e.g. a quadric of flat
// surfaces only, whose minimum is a whole line or plane): then the caller uses a fallback.
bool quadric_minimize(const double* q, int n, double* x);

// Minimiser of Q over the field coordinates x[3..n) with the position x[0..3) held fixed: the best
// field values for a vertex placed at that position. Leaves x unchanged and returns false when the
// field block of A is too ill-conditioned (e.g. n == 3, or no field information in Q).
bool quadric_minimize_fields(const double* q, int n, double* x);

namespace quadric_detail {

template <int kN>
constexpr int dim(int n) {
  return kN > 0 ? kN : n;
}

// Index of A(i, j), i <= j, in the packed upper triangle.
constexpr int tri_index(int n, int i, int j) { return i * n - i * (i - 1) / 2 + (j - i); }

template <int kN>
void add(double* q, const double* other, int n) {
  const int size = quadric_size(dim<kN>(n));
  for (int i = 0; i < size; ++i) q[i] += other[i];
}

template <int kN>
double eval(const double* q, int n_runtime, const double* x) {
  const int n = dim<kN>(n_runtime);
  const double* b = q + n * (n + 1) / 2;
  double s = b[n];
  int k = 0;
  for (int i = 0; i < n; ++i) {
    s += 2.0 * b[i] * x[i] + q[k++] * x[i] * x[i];
    for (int j = i + 1; j < n; ++j) s += 2.0 * q[k++] * x[i] * x[j];
  }
  return s > 0.0 ? s : 0.0;  // rounding can make a PSD form slightly negative
}

// Solves the symmetric positive semi-definite m x m system in `m` (augmented: column m is the
// right-hand side; only the lower triangle and the last column are read) by an LDL^T
// factorisation into y. Every matrix solved here is a sum of quadrics (or a diagonal block of
// one), hence PSD, so no pivoting is needed. False when a pivot falls below 1e-9 of the largest
// diagonal entry (a nearly flat direction: the minimum is a line or a plane, not a point) or the
// result is not finite. kM > 0 fixes m at compile time.
template <int kM, class Matrix>
bool solve(Matrix& m, int size, double* y) {
  const int n = dim<kM>(size);
  double max_diag = 0.0;
  for (int i = 0; i < n; ++i) max_diag = m[i][i] > max_diag ? m[i][i] : max_diag;
  if (!(max_diag > 0.0)) return false;  // also false for NaN
  const double tiny = 1e-9 * max_diag;
  // In place: m[i][j] (j < i) becomes L(i, j), m[j][j] becomes D(j).
  for (int j = 0; j < n; ++j) {
    double d = m[j][j];
    for (int k = 0; k < j; ++k) d -= m[j][k] * m[j][k] * m[k][k];
    if (!(d >= tiny)) return false;
    m[j][j] = d;
    for (int i = j + 1; i < n; ++i) {
      double l = m[i][j];
      for (int k = 0; k < j; ++k) l -= m[i][k] * m[j][k] * m[k][k];
      m[i][j] = l / d;
    }
  }
  double r[kM > 0 ? kM : kMaxQuadricDim];
  for (int i = 0; i < n; ++i) {  // L z = rhs
    double z = m[i][n];
    for (int k = 0; k < i; ++k) z -= m[i][k] * r[k];
    r[i] = z;
  }
  for (int i = n - 1; i >= 0; --i) {  // D L^T y = z
    double v = r[i] / m[i][i];
    for (int k = i + 1; k < n; ++k) v -= m[k][i] * r[k];
    r[i] = v;
    if (!std::isfinite(v)) return false;
  }
  for (int i = 0; i < n; ++i) y[i] = r[i];
  return true;
}

template <int kN>
bool minimize(const double* q, int n_runtime, double* x) {
  // Solve A x = -b on a dense copy.
  const int n = dim<kN>(n_runtime);
  constexpr int kD = kN > 0 ? kN : kMaxQuadricDim;
  double m[kD][kD + 1];
  const double* b = q + n * (n + 1) / 2;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j <= i; ++j) m[i][j] = q[tri_index(n, j, i)];
    m[i][n] = -b[i];
  }
  return solve<kN>(m, n, x);
}

template <int kN>
bool minimize_fields(const double* q, int n_runtime, double* x) {
  // With x = (p, f): dQ/df = 0  <=>  A_ff f = -(b_f + A_fp p).
  const int n = dim<kN>(n_runtime);
  const int k = n - 3;
  if (k <= 0) return false;
  constexpr int kK = kN > 3 ? kN - 3 : 0;
  constexpr int kD = kK > 0 ? kK : kMaxQuadricDim;
  double m[kD][kD + 1];
  const double* b = q + n * (n + 1) / 2;
  for (int i = 0; i < k; ++i) {
    for (int j = 0; j <= i; ++j) m[i][j] = q[tri_index(n, 3 + j, 3 + i)];
    double rhs = -b[3 + i];
    for (int d = 0; d < 3; ++d) rhs -= q[tri_index(n, d, 3 + i)] * x[d];
    m[i][k] = rhs;
  }
  return solve<kK>(m, k, x + 3);
}

}  // namespace quadric_detail
}  // namespace topotet
