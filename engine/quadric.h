// Garland–Zhou quadrics in n = 3 + k dimensions (position plus k scaled field values).
//
// A quadric is Q(x) = x^T A x + 2 b^T x + c with A symmetric; it is stored packed in
// quadric_size(n) doubles: the upper triangle of A row by row, then b, then c. The quadric of a
// simplex (segment, triangle, tet) in R^n is its weight times the squared distance from x to the
// simplex's affine hull: A = w (I - E E^T) for an orthonormal basis E of the hull's directions,
// b = -A p0, c = p0^T A p0.
#pragma once

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

void quadric_add(double* q, const double* other, int n);

double quadric_eval(const double* q, int n, const double* x);

// Minimiser of Q. Returns false when A is too ill-conditioned to trust (e.g. a quadric of flat
// surfaces only, whose minimum is a whole line or plane): then the caller uses a fallback.
bool quadric_minimize(const double* q, int n, double* x);

// Minimiser of Q over the field coordinates x[3..n) with the position x[0..3) held fixed: the best
// field values for a vertex placed at that position. Leaves x unchanged and returns false when the
// field block of A is too ill-conditioned (e.g. n == 3, or no field information in Q).
bool quadric_minimize_fields(const double* q, int n, double* x);

}  // namespace topotet
