// A double-double stage for geogram's in-sphere predicate, between its double-precision filter
// and its exact expansion arithmetic (native/geogram/README.md, second change).
//
// Why. VoroCrust's seeds come in families that are cospherical before rounding (the seeds of
// the guide triangles around two balls lie on the circle where the balls' spheres meet). Their
// in-sphere determinants are then about 2^-53 of their size: too small for the double filter
// (error bound about 2^-50 of the size), far above what double-double resolves (2^-96 below).
// On the cube's seeds (eps = 0.0094977) the exact path took most of geogram's time, and this
// stage halves it (python benchmarks/bench_engines.py cells --eps 0.0094977 --cube: geogram
// with and without the stage, the same tetrahedra).
//
// What it returns. The sign of side4_3d(p0, ..., p4) (geogram's sign: positive when p4 is
// outside the sphere through p0..p3, for p0..p3 positively oriented), or 0 when this stage
// cannot be sure: the caller then evaluates exactly. It never returns a wrong sign; the
// argument, step by step:
//
// 1. Inputs. a_ij = p_i[j] - p0[j] as double-doubles (Two-Sum: exact). All are multiplied by
//    one power of two that puts the largest |hi| in [1, 2); the stage gives up (0) when a part
//    nonzero before the scaling is below 2^-900 after it (the scaling, a product with
//    2^shift or ldexp, both correctly rounded, may round a part to zero: tested before it), or when a hi or lo part is not finite (an overflow inside Two-Sum
//    would show in lo). Scaling by a power of two is then exact, and every |a_ij| < 2. The
//    signs of both determinants are unchanged (homogeneous polynomials times a positive
//    factor).
// 2. The determinants. Delta4 = det[a_1..a_3] (the orientation of p0..p3) and
//    r = sum_k (-1)^(k+1) Delta_k * q_k with q_i = |a_i|^2 (geogram's expansion of side4), as
//    trees of double-double operations. What the bound below needs is, per exact monomial, the
//    number D of rounded operations it passes through, where a product passes on the counts
//    of both its operands plus its own: products of a_ij (1), the 2x2 minors (2), the minor
//    times a_ij (3), the three-term sums Delta_k (5), q_i (3), the products Delta_k q_k
//    (5 + 3 + 1 = 9) and the four-term sum started from zero (13). So D = 5 for Delta4 and
//    D = 13 for r. The six minors are computed once and shared by the Delta_k: each use reads
//    the same computed value, so the bound below holds as for the tree the sharing unfolds to.
// 3. Each operation returns op(x, y)(1 + d) with |d| <= 7u^2 (u = 2^-53) for the computed
//    operands x, y: products by DWTimesDW1 (7u^2), sums by AccurateDWPlusDW (3u^2/(1-4u)), in
//    the absence of underflow (Joldes, Muller, Popescu, "Tight and rigorous error bounds for
//    basic building blocks of double-word arithmetic", ACM TOMS 44, 2017). By induction over
//    the tree (Higham, "Accuracy and Stability of Numerical Algorithms", 3.1), the computed
//    value is the sum of the exact monomials, each times a product of at most D such factors,
//    so |computed - exact| <= gamma_D * P with gamma_D = D*7u^2/(1 - D*7u^2) and P the same
//    tree evaluated on |a_ij| with every sign +. For D = 13: gamma_13 < 92u^2 < 2^-99.4.
// 4. P is evaluated in double on RN(|hi| (1 + 2^-52)) >= |hi| + ulp(hi) >= |a_ij| (Two-Sum's
//    |lo| is at most ulp(hi)/2), all terms positive: at most 13 roundings per monomial, so
//    P <= P_double (1 + 2^-47) where no product of sizes underflows; where some do, P_double
//    misses at most 2^-1040, which 2^-96 turns into nothing step 6 could not absorb.
// 5. Underflow. After step 1 every quantity in the trees is below 2^12 in size. A DWTimesDW1
//    whose floating-point products round in the subnormal range adds at most six half-units
//    2^-1075 beyond the relative bound (four in Dekker's product, whose additions stay exact,
//    two in the cross terms); an addition none (a subnormal sum is exact, and Two-Sum and
//    Fast-Two-Sum stay exact). At most 52 products, each error carried through at most two later
//    products by factors below 2^12: the sum stays below 52 * 3 * 2^-1074 * 2^24 < 2^-1040.
// 6. So |computed - exact| <= B = 2^-96 P_double + 2^-1000 (more than 11 times the bound of
//    3-5: 2^-96 / (92u^2) > 11.1), and the exact value has the sign of the computed hi part
//    when |hi| > 2 B (the lo part is below u |hi|). Delta4 is treated the same way with its own P.
//
// A test compares the stage with an exact rational evaluation on rounded cospherical and
// exactly cospherical points (tests/sampling/test_geogram_delaunay.py).

#include <cfloat>
#include <cmath>

// The error-free transformations need each operation rounded once to double, in round to
// nearest; the build also passes -ffp-contract=off (a fused multiply-add in Dekker's splitting
// would break it), which no macro reveals.
#if defined(__FAST_MATH__)
#error "insphere_dd.cpp needs IEEE arithmetic: build without -ffast-math"
#endif
#if FLT_EVAL_METHOD != 0
#error "insphere_dd.cpp needs double operations evaluated in double (FLT_EVAL_METHOD 0)"
#endif

namespace vb_insphere {

namespace {

struct DD {
    double hi;
    double lo;
};

inline DD two_sum(double a, double b) {
    const double s = a + b;
    const double bb = s - a;
    return {s, (a - (s - bb)) + (b - bb)};
}

inline DD fast_two_sum(double a, double b) {
    const double s = a + b;
    return {s, b - (s - a)};
}

// Dekker's product (no fused multiply-add: the build passes -ffp-contract=off).
inline DD two_prod(double a, double b) {
    const double splitter = 134217729.0;  // 2^27 + 1
    const double p = a * b;
    double t = splitter * a;
    const double ah = t - (t - a);
    const double al = a - ah;
    t = splitter * b;
    const double bh = t - (t - b);
    const double bl = b - bh;
    const double err = ((ah * bh - p) + ah * bl + al * bh) + al * bl;
    return {p, err};
}

// AccurateDWPlusDW (relative error below 3u^2 / (1 - 4u)).
inline DD add(DD x, DD y) {
    const DD s = two_sum(x.hi, y.hi);
    const DD t = two_sum(x.lo, y.lo);
    const DD v = fast_two_sum(s.hi, s.lo + t.hi);
    return fast_two_sum(v.hi, t.lo + v.lo);
}

inline DD neg(DD x) { return {-x.hi, -x.lo}; }

inline DD sub(DD x, DD y) { return add(x, neg(y)); }

// DWTimesDW1 (relative error below 7u^2).
inline DD mul(DD x, DD y) {
    const DD c = two_prod(x.hi, y.hi);
    const double cross = x.hi * y.lo + x.lo * y.hi;
    return fast_two_sum(c.hi, c.lo + cross);
}

constexpr double SMALLEST_PART = 0x1p-900;
constexpr double RELATIVE_BOUND = 0x1p-96;
constexpr double ABSOLUTE_BOUND = 0x1p-1000;
constexpr double UP = 1.0 + 0x1p-52;

// +1, -1, or 0 (not sure) for the sign of `value` whose error is at most `bound`.
inline int sure_sign(DD value, double bound) {
    if (!(std::fabs(value.hi) > 2.0 * bound)) {
        return 0;
    }
    return value.hi > 0 ? 1 : -1;
}

}  // namespace

bool enabled = true;

int side4_3d(const double* p0, const double* p1, const double* p2, const double* p3,
             const double* p4) {
    if (!enabled) {
        return 0;
    }
    const double* rows[4] = {p1, p2, p3, p4};
    DD a[4][3];
    double largest = 0.0;
    for (int i = 0; i < 4; ++i) {
        for (int j = 0; j < 3; ++j) {
            a[i][j] = two_sum(rows[i][j], -p0[j]);
            if (!std::isfinite(a[i][j].hi) || !std::isfinite(a[i][j].lo)) {
                return 0;
            }
            largest = std::fmax(largest, std::fabs(a[i][j].hi));
        }
    }
    if (!(largest > 0.0)) {
        return 0;
    }
    int exponent = 0;
    std::frexp(largest, &exponent);  // largest in [2^(exponent-1), 2^exponent)
    const int shift = 1 - exponent;  // puts the largest |hi| in [1, 2)
    // A product with 2^shift where that is a double (the same correctly rounded result as
    // ldexp, without a call per part), ldexp beyond.
    const bool by_product = shift >= -1022 && shift <= 1023;
    const double factor = by_product ? std::ldexp(1.0, shift) : 1.0;
    double size[4][3];
    for (int i = 0; i < 4; ++i) {
        for (int j = 0; j < 3; ++j) {
            // A nonzero part is tested before scaling: ldexp may round it to zero (a shift
            // below -1 and a part below 2^(-1074-shift)), and 0 would pass as exact.
            const bool hi_nonzero = a[i][j].hi != 0.0;
            const bool lo_nonzero = a[i][j].lo != 0.0;
            if (by_product) {
                a[i][j].hi *= factor;
                a[i][j].lo *= factor;
            } else {
                a[i][j].hi = std::ldexp(a[i][j].hi, shift);
                a[i][j].lo = std::ldexp(a[i][j].lo, shift);
            }
            const double hi = std::fabs(a[i][j].hi);
            const double lo = std::fabs(a[i][j].lo);
            if ((hi_nonzero && hi < SMALLEST_PART) || (lo_nonzero && lo < SMALLEST_PART)) {
                return 0;
            }
            size[i][j] = hi * UP;
        }
    }
    // The six 2x2 minors of columns 1, 2 (rows i < k), computed once as geogram does, then the
    // 3x3 determinants Delta_k without row k.
    DD minor[4][4];
    double minor_size[4][4];
    for (int i = 0; i < 4; ++i) {
        for (int k = i + 1; k < 4; ++k) {
            minor[i][k] = sub(mul(a[i][1], a[k][2]), mul(a[i][2], a[k][1]));
            minor_size[i][k] = size[i][1] * size[k][2] + size[i][2] * size[k][1];
        }
    }
    auto det3 = [&](int i, int k, int l) {  // i < k < l
        DD d = mul(a[i][0], minor[k][l]);
        d = sub(d, mul(a[k][0], minor[i][l]));
        return add(d, mul(a[l][0], minor[i][k]));
    };
    auto det3_size = [&](int i, int k, int l) {
        return size[i][0] * minor_size[k][l] + size[k][0] * minor_size[i][l] +
               size[l][0] * minor_size[i][k];
    };
    const DD delta4 = det3(0, 1, 2);
    const int orientation =
        sure_sign(delta4, RELATIVE_BOUND * det3_size(0, 1, 2) + ABSOLUTE_BOUND);
    if (orientation == 0) {
        return 0;
    }
    const DD deltas[4] = {det3(1, 2, 3), det3(0, 2, 3), det3(0, 1, 3), delta4};
    const double delta_sizes[4] = {det3_size(1, 2, 3), det3_size(0, 2, 3), det3_size(0, 1, 3),
                                   det3_size(0, 1, 2)};
    DD r = {0.0, 0.0};
    double r_size = 0.0;
    for (int k = 0; k < 4; ++k) {
        const DD q = add(add(mul(a[k][0], a[k][0]), mul(a[k][1], a[k][1])), mul(a[k][2], a[k][2]));
        const double q_size =
            size[k][0] * size[k][0] + size[k][1] * size[k][1] + size[k][2] * size[k][2];
        // geogram: side4 = Delta4 * (-D1 q1 + D2 q2 - D3 q3 + D4 q4) (its a_k4 = -q_k)
        const DD term = mul(deltas[k], q);
        r = (k % 2 == 0) ? sub(r, term) : add(r, term);
        r_size += delta_sizes[k] * q_size;
    }
    const int value = sure_sign(r, RELATIVE_BOUND * r_size + ABSOLUTE_BOUND);
    return orientation * value;
}

}  // namespace vb_insphere
