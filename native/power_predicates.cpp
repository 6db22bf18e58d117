// A floating-point filter for the regular (weighted Delaunay) triangulation's conflict test,
// computed from the raw weights rather than from lifted heights rounded to doubles
// (native/geogram/README.md, third change).
//
// Why. geogram's weighted Delaunay3d stores the lifting h_i = |p_i|^2 - w_i as one double per
// vertex, and its predicate is exact for those rounded heights, not for the weights given: two
// triangulations can differ where the rounding of h_i flips a sign. vorobound's check needs the
// regular triangulation of the balls as given (centers and squared radii, doubles), so the
// predicate works on the differences of the raw weights instead.
//
// The quantity. geogram's side4h sign is sign(Delta4) * sign(r), with a_i = p_i - p0 (i = 1..4),
// Delta_k the 3x3 minors of the rows a_i (Delta4 = det[a_1, a_2, a_3], the orientation of
// p0..p3) and r = Delta1 e1 - Delta2 e2 + Delta3 e3 - Delta4 e4, the expansion of det[a_i, e_i]
// along its last column, where geogram's e_i is h0 - h_i. With exact heights
// h0 - h_i = (w_i - w0) - |a_i|^2 - 2 a_i.p0, and the last term is a combination of the first
// three columns, so it leaves the determinant unchanged: e_i = (w_i - w0) - |a_i|^2 gives the
// same sign, and every term of it is a polynomial in the input doubles, which geogram's
// expansions evaluate exactly (side4w_3d_exact_SOS in Delaunay_psm.cpp, a copy of
// side4h_3d_exact_SOS with these e_i; its symbolic perturbation reads only the Delta_k, as the
// original's does). With equal weights e_i = -|a_i|^2: geogram's unweighted side4 exactly.
//
// This file: the double-precision filter in front of the expansions. It returns the sign, or
// 0 when it cannot be sure (the caller then evaluates exactly); it never returns a wrong sign.
// The argument (u = 2^-53, round to nearest, no fused multiply-add: the build passes
// -ffp-contract=off):
//
// 1. Range. A = max |a_ij| and D = max |w_i - w0| as computed. The filter gives up unless
//    2^-60 <= A <= 2^10 and D <= 2^20 (NaN and infinities fail these comparisons too). In the
//    frame the Python side puts the points in (largest |coordinate| in [1/2, 1)), A < 2 always,
//    and A < 2^-60 or D > 2^20 only for tiny or wildly weighted tetrahedra (the expansions
//    decide those).
// 2. Rounding. Every value is computed by a tree of +, -, * from the exact differences
//    d_ij = p_i[j] - p0[j] and dw_i = w_i - w0, each rounded once. Without underflow each
//    operation returns op(x, y)(1 + d), |d| <= u, so by induction over the tree the computed
//    value is the sum of the exact monomials, each times at most K such factors (Higham,
//    "Accuracy and Stability of Numerical Algorithms", 3.1), and |computed - exact| <=
//    gamma_K P, gamma_K = K u / (1 - K u), P the same tree on the absolute values of the exact
//    inputs with every sign +. K counts the input rounding and adds up over a product's two
//    operands (a monomial of x y carries the factors of both) plus one, over a sum takes the
//    larger plus one: a 1, a * a 3, the 2x2 minors 4, a * minor 6, Delta_k (two sums) 8;
//    q_i = |a_i|^2 5, e_i = dw_i - q_i 6, Delta_k e_k 15, and r summed left to right 18. (The
//    minors are computed once and shared by the Delta_k: each use reads the same computed
//    value, so the bound holds as for the tree the sharing unfolds to.)
// 3. P. With A' = max |d_ij| <= A / (1 - u) and D' = max |dw_i| <= D / (1 - u):
//    P(Delta_k) <= 3 A' (2 A'^2) = 6 A'^3, P(e_k) <= D' + 3 A'^2, P(r) <= 24 A'^3 (D' + 3 A'^2).
//    So |r - exact| <= gamma_18 24 A^3 (D + 3 A^2) / (1 - u)^5 <= 432.1 u X with
//    X = A^3 (D + 3 A^2); X computed in double (six roundings) is within (1 - u)^6 of X, so
//    433 u X_computed bounds it: the filter uses B_r = 2^-43 X_computed (1024 u). For Delta4:
//    gamma_8 6 A'^3 <= 48.1 u A^3 <= 48.2 u (A*A)*A computed, bounded by B_4 = 2^-47 (A*A)*A
//    (64 u).
// 4. Underflow. A product whose result is subnormal may add an absolute error up to 2^-1075
//    (sums and differences stay exact there). The unfolded trees hold 52 products for r and 9
//    for Delta4, and an error made at one of them reaches the root multiplied by the other
//    factors on its path, whose product is below 2^34 under step 1 (a minor's product meets
//    an a and an e, a q_i's product a Delta, an a * minor an e; |a| <= 2^10, |e| <= 2^22,
//    |Delta| <= 6 2^30, with rounding margins): at most 52 * 2^-1075 * 2^34 < 2^-1035 in all.
//    Step 1 also gives X >= 3 A^5 >= 2^-300 and A^3 >= 2^-180, so the margins left in step 3
//    (590 u X and 15 u A^3, above 2^-344 and 2^-229) absorb it, and the second-order terms of
//    the relative model as well. No overflow: every value stays below 2^60.
// 5. So the exact r has the sign of the computed one when |r| > B_r, and Delta4 likewise when
//    |Delta4| > B_4; the result is their product's sign.
//
// A test compares the whole predicate (this filter, then the expansions) with exact rational
// arithmetic on random and nearly degenerate inputs (tests/sampling/test_geogram_regular.py).

#include <cfloat>
#include <cmath>
#include <initializer_list>

#if defined(__FAST_MATH__)
#error "power_predicates.cpp needs IEEE arithmetic: build without -ffast-math"
#endif
#if FLT_EVAL_METHOD != 0
#error "power_predicates.cpp needs double operations evaluated in double (FLT_EVAL_METHOD 0)"
#endif

namespace vb_power {

namespace {

constexpr double SMALLEST_SPREAD = 0x1p-60;
constexpr double LARGEST_SPREAD = 0x1p10;
constexpr double LARGEST_WEIGHT_SPREAD = 0x1p20;
constexpr double R_BOUND = 0x1p-43;
constexpr double DELTA_BOUND = 0x1p-47;

inline double larger(double a, double b) { return a > b ? a : b; }

}  // namespace

// Points geogram skipped in the weighted mode of Delaunay_psm.cpp (vorobound's change) because an
// inserted vertex sits at their position, whatever the weights: the glue (geogram_delaunay.cpp)
// resets it, triangulates, and triangulates again without copies when it is not zero.
thread_local long long skipped_copies = 0;

// Sign of geogram's side4h(p0, .., p4) for the heights |p_i|^2 - w_i taken exactly (positive
// when p4 is not in conflict with the tetrahedron p0..p3: its power distance to the
// orthosphere is positive), or 0 when the filter cannot be sure.
int side4w_3d_filter(const double* p0, const double* p1, const double* p2, const double* p3,
                     const double* p4, double w0, double w1, double w2, double w3, double w4) {
    const double a11 = p1[0] - p0[0], a12 = p1[1] - p0[1], a13 = p1[2] - p0[2];
    const double a21 = p2[0] - p0[0], a22 = p2[1] - p0[1], a23 = p2[2] - p0[2];
    const double a31 = p3[0] - p0[0], a32 = p3[1] - p0[1], a33 = p3[2] - p0[2];
    const double a41 = p4[0] - p0[0], a42 = p4[1] - p0[1], a43 = p4[2] - p0[2];
    const double d1 = w1 - w0, d2 = w2 - w0, d3 = w3 - w0, d4 = w4 - w0;

    double spread = std::fabs(a11);
    for (double a : {a12, a13, a21, a22, a23, a31, a32, a33, a41, a42, a43}) {
        spread = larger(spread, std::fabs(a));
    }
    const double weight_spread =
        larger(larger(std::fabs(d1), std::fabs(d2)), larger(std::fabs(d3), std::fabs(d4)));
    if (!(spread >= SMALLEST_SPREAD && spread <= LARGEST_SPREAD &&
          weight_spread <= LARGEST_WEIGHT_SPREAD)) {
        return 0;
    }

    // The 2x2 minors of columns 2 and 3, and the 3x3 minors, as in geogram's side4 filters.
    const double m12 = a12 * a23 - a13 * a22;
    const double m13 = a12 * a33 - a13 * a32;
    const double m14 = a12 * a43 - a13 * a42;
    const double m23 = a22 * a33 - a23 * a32;
    const double m24 = a22 * a43 - a23 * a42;
    const double m34 = a32 * a43 - a33 * a42;
    const double delta1 = (a21 * m34 - a31 * m24) + a41 * m23;
    const double delta2 = (a11 * m34 - a31 * m14) + a41 * m13;
    const double delta3 = (a11 * m24 - a21 * m14) + a41 * m12;
    const double delta4 = (a11 * m23 - a21 * m13) + a31 * m12;

    const double cube = spread * spread * spread;
    if (!(std::fabs(delta4) > DELTA_BOUND * cube)) {
        return 0;
    }

    const double e1 = d1 - ((a11 * a11 + a12 * a12) + a13 * a13);
    const double e2 = d2 - ((a21 * a21 + a22 * a22) + a23 * a23);
    const double e3 = d3 - ((a31 * a31 + a32 * a32) + a33 * a33);
    const double e4 = d4 - ((a41 * a41 + a42 * a42) + a43 * a43);
    const double r = ((delta1 * e1 - delta2 * e2) + delta3 * e3) - delta4 * e4;
    const double size = cube * (weight_spread + 3.0 * (spread * spread));
    if (!(std::fabs(r) > R_BOUND * size)) {
        return 0;
    }
    return (r > 0) == (delta4 > 0) ? 1 : -1;
}

}  // namespace vb_power
