// The Delaunay tetrahedra of a point set from geogram's triangulation (native/geogram, its
// Delaunay module), handed to Python as one int32 array; vorobound/sampling/geogram_delaunay.py
// calls it through ctypes. A Python module only in name: setuptools builds it as an extension
// module, and nothing is called through the Python C API.
//
// What the caller relies on (the Python side documents and tests it):
// - exact predicates with the lexicographic symbolic perturbation (PCK::SOS_LEXICO): the outcome
//   of every test depends on the coordinates of the points it reads, not on their indices, so a
//   subset's triangulation agrees with the whole set's wherever a tetrahedron's ball is empty;
// - the same input gives the same rows in the same order (the random engine is restarted);
// - geogram's assertions throw (ASSERT_THROW) instead of aborting the process: a failure is a
//   nonzero return code, and the caller falls back to CGAL.

#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <signal.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <exception>
#include <mutex>
#include <memory>
#include <new>
#include <utility>
#include <vector>

#include "Delaunay_psm.h"

namespace vb_insphere {
extern bool enabled;
int side4_3d(const double* p0, const double* p1, const double* p2, const double* p3,
             const double* p4);
}  // namespace vb_insphere

namespace vb_power {
extern thread_local long long skipped_copies;
int side4w_3d_filter(const double* p0, const double* p1, const double* p2, const double* p3,
                     const double* p4, double w0, double w1, double w2, double w3, double w4);
}  // namespace vb_power

namespace GEO {
namespace PCK {
// Delaunay_psm.cpp (vorobound's change): orient_3dlifted_SOS exact for the raw weights.
Sign orient_3dweighted_SOS(const double* p0, const double* p1, const double* p2,
                           const double* p3, const double* p4, double w0, double w1, double w2,
                           double w3, double w4);
}  // namespace PCK
}  // namespace GEO

namespace {

std::once_flag started;

void start_geogram() {
    // GEO::initialize resets SIGINT to its default action (Process::enable_cancel(false), run
    // whatever the flags), which would turn Python's KeyboardInterrupt into a kill: the
    // process's handler is put back.
    struct sigaction interrupt;
    const bool saved = sigaction(SIGINT, nullptr, &interrupt) == 0;
    GEO::initialize(GEO::GEOGRAM_INSTALL_NONE);
    if (saved) {
        sigaction(SIGINT, &interrupt, nullptr);
    }
    GEO::CmdLine::import_arg_group("standard");
    GEO::CmdLine::import_arg_group("algo");
    GEO::Logger::instance()->set_quiet(true);
    GEO::set_assert_mode(GEO::ASSERT_THROW);
    GEO::PCK::set_SOS_mode(GEO::PCK::SOS_LEXICO);
}

// The finite tetrahedra of `triangulation` as a new array of 4 * *count indices (each row
// ascending, through `original` when it is not null; with `ordered` the rows in lexicographic
// order). With `neighbours` not null (only with `ordered` 0), also a new array of the same
// shape: per row, the row across the face opposite each of its corners (geogram's facet lf is
// opposite its vertex lf, so each row's facets are permuted with its corners), -1 on the hull.
void finite_cells(const GEO::Delaunay& triangulation, const int64_t* original, int ordered,
                  int64_t** cells, int64_t* count, int64_t** neighbours = nullptr) {
    const GEO::index_t total = triangulation.nb_cells();
    std::vector<int64_t> row_of(total, -1);  // finite cell -> output row
    int64_t finite = 0;
    for (GEO::index_t c = 0; c < total; ++c) {
        if (!triangulation.cell_is_infinite(c)) {
            row_of[c] = finite++;
        }
    }
    std::unique_ptr<int64_t[]> kept(new int64_t[size_t(finite) * 4 + 1]);
    std::unique_ptr<int64_t[]> beside(neighbours == nullptr ? nullptr
                                                            : new int64_t[size_t(finite) * 4 + 1]);
    int64_t* out = kept.get();
    int64_t* across = beside.get();
    const GEO::index_t* corners = triangulation.cell_to_v();
    for (GEO::index_t c = 0; c < total; ++c) {
        const int64_t k = row_of[c];
        if (k < 0) {
            continue;
        }
        std::array<std::pair<int64_t, int64_t>, 4> row;  // (vertex, row across its facet)
        for (GEO::index_t j = 0; j < 4; ++j) {
            const int64_t v = int64_t(corners[4 * c + j]);
            const GEO::index_t other = triangulation.cell_adjacent(c, j);
            row[j] = {original == nullptr ? v : original[v],
                      other < total ? row_of[other] : int64_t(-1)};
        }
        std::sort(row.begin(), row.end());
        for (int j = 0; j < 4; ++j) {
            out[4 * k + j] = row[j].first;
            if (across != nullptr) {
                across[4 * k + j] = row[j].second;
            }
        }
    }
    if (ordered) {
        using Row = std::array<int64_t, 4>;  // 32 bytes, no padding: the rows in place
        static_assert(sizeof(Row) == 4 * sizeof(int64_t), "a row is four indices");
        Row* rows = reinterpret_cast<Row*>(out);
        std::sort(rows, rows + finite);
    }
    *cells = kept.release();
    *count = finite;
    if (neighbours != nullptr) {
        *neighbours = beside.release();
    }
}

// The weighted points (x, y, z, w) geogram is given, one per distinct position: of the points
// at one position the one of largest weight, the first of those (geogram would keep whichever
// it inserts first, its weight aside, and a heavier copy hides a lighter one). `original` maps
// them back to the input's indices.
void distinct_positions(const double* points, const double* weights, int64_t n,
                        std::vector<double>& lifted, std::vector<int64_t>& original) {
    std::vector<int64_t> order(static_cast<size_t>(n));
    for (int64_t i = 0; i < n; ++i) {
        order[size_t(i)] = i;
    }
    const auto before = [points, weights](int64_t a, int64_t b) {
        const double* p = points + 3 * a;
        const double* q = points + 3 * b;
        if (p[0] != q[0]) return p[0] < q[0];
        if (p[1] != q[1]) return p[1] < q[1];
        if (p[2] != q[2]) return p[2] < q[2];
        if (weights[a] != weights[b]) return weights[a] > weights[b];
        return a < b;
    };
    std::sort(order.begin(), order.end(), before);
    std::vector<char> kept(static_cast<size_t>(n), 0);
    for (int64_t k = 0; k < n; ++k) {
        const double* p = points + 3 * order[size_t(k)];
        const double* q = k ? points + 3 * order[size_t(k - 1)] : nullptr;
        kept[size_t(order[size_t(k)])] =
            q == nullptr || p[0] != q[0] || p[1] != q[1] || p[2] != q[2];
    }
    // In the input's order: geogram's spatial sort then sees the same sequence as without
    // copies.
    lifted.clear();
    original.clear();
    for (int64_t i = 0; i < n; ++i) {
        if (kept[size_t(i)]) {
            lifted.insert(lifted.end(), {points[3 * i], points[3 * i + 1], points[3 * i + 2],
                                         weights[i]});
            original.push_back(i);
        }
    }
}

// The triangles of `triangulation` (each once: from the cell of smaller index, or from the
// only finite cell on the hull) whose three vertices, mapped through `original`, are below
// `limit`, as a new array of 3 * *count indices, each row ascending; with `ordered` the rows
// in lexicographic order.
void finite_facets(const GEO::Delaunay& triangulation, const int64_t* original, int64_t limit,
                   int ordered, int64_t** facets, int64_t* count) {
    // Without the infinite cells (set_keeps_infinite(false)) every cell is finite, and a hull
    // facet has no neighbour (NO_INDEX).
    const GEO::index_t total = triangulation.nb_cells();
    const GEO::index_t* corners = triangulation.cell_to_v();
    const GEO::index_t* neighbours = triangulation.cell_to_cell();
    std::vector<std::array<int64_t, 3>> found;
    found.reserve(size_t(total) * 2);
    for (GEO::index_t c = 0; c < total; ++c) {
        int64_t v[4];
        for (int j = 0; j < 4; ++j) {
            const GEO::index_t corner = corners[4 * c + j];
            v[j] = corner == GEO::NO_INDEX ? limit : original == nullptr ? corner : original[corner];
        }
        for (int f = 0; f < 4; ++f) {  // facet f is opposite vertex f
            const GEO::index_t other = neighbours[4 * c + f];
            if (other != GEO::NO_INDEX && other < c) {
                continue;  // listed from the other cell
            }
            std::array<int64_t, 3> row;
            int k = 0;
            for (int j = 0; j < 4; ++j) {
                if (j != f) {
                    row[k++] = v[j];
                }
            }
            if (row[0] < limit && row[1] < limit && row[2] < limit) {
                std::sort(row.begin(), row.end());
                found.push_back(row);
            }
        }
    }
    if (ordered && limit <= (int64_t(1) << 21)) {
        // Three indices below 2^21 packed in one key: the same order, a cheaper sort.
        std::vector<uint64_t> keys(found.size());
        for (size_t i = 0; i < found.size(); ++i) {
            keys[i] = uint64_t(found[i][0]) << 42 | uint64_t(found[i][1]) << 21 | uint64_t(found[i][2]);
        }
        std::sort(keys.begin(), keys.end());
        const uint64_t mask = (uint64_t(1) << 21) - 1;
        for (size_t i = 0; i < keys.size(); ++i) {
            found[i] = {int64_t(keys[i] >> 42), int64_t(keys[i] >> 21 & mask), int64_t(keys[i] & mask)};
        }
    } else if (ordered) {
        std::sort(found.begin(), found.end());
    }
    int64_t* out = new int64_t[found.size() * 3 + 1];
    for (size_t i = 0; i < found.size(); ++i) {
        std::copy(found[i].begin(), found[i].end(), out + 3 * i);
    }
    *facets = out;
    *count = int64_t(found.size());
}

// The regular triangulation of vb_regular_cells. First on every point, `original` left empty
// (the identity); where geogram skipped a copy of an inserted vertex (it would keep whichever
// it inserts first, whatever the weights), again on the distinct positions. Without a skipped
// copy the result is that of the distinct positions: a copy of a point hidden at its
// insertion is inserted if heavier, hidden if not.
GEO::Delaunay_var regular_triangulation(const double* points, const double* weights, int64_t n,
                                        std::vector<double>& lifted,
                                        std::vector<int64_t>& original) {
    std::call_once(started, start_geogram);
    lifted.resize(size_t(n) * 4);
    for (int64_t i = 0; i < n; ++i) {
        std::copy(points + 3 * i, points + 3 * i + 3, lifted.data() + 4 * i);
        lifted[size_t(4 * i + 3)] = weights[i];
    }
    original.clear();
    for (int pass = 0; pass < 2; ++pass) {
        if (pass == 1) {
            distinct_positions(points, weights, n, lifted, original);
        }
        GEO::Numeric::random_reset(-1);  // as in vb_delaunay_cells
        GEO::Delaunay_var triangulation = GEO::Delaunay::create(4, "VBPOW");
        if (triangulation.is_null()) {
            return triangulation;
        }
        triangulation->set_keeps_infinite(false);
        vb_power::skipped_copies = 0;
        triangulation->set_vertices(GEO::index_t(lifted.size() / 4), lifted.data());
        if (vb_power::skipped_copies == 0 || pass == 1) {
            return triangulation;
        }
    }
    return GEO::Delaunay_var();  // not reached
}

}  // namespace

extern "C" {

// Triangulates the n points (x, y, z rows of `points`). On success returns 0 and sets *cells to
// a new array of 4 * *count vertex indices (the finite tetrahedra, each row ascending; with
// `ordered` nonzero the rows in lexicographic order), to be freed with vb_free_cells. Returns 1
// when geogram failed (an assertion or an allocation), 2 for n out of range.
// With `neighbours` not null (and `ordered` 0), also *neighbours: a second new array of
// 4 * *count indices, per row the row across the face opposite each corner, -1 on the hull (the
// layout of scipy's Delaunay.neighbors), to be freed with vb_free_cells. Returns 2 also for
// neighbours asked with `ordered`.
int vb_delaunay_cells(const double* points, int64_t n, int ordered, int64_t** cells,
                      int64_t** neighbours, int64_t* count) {
    *cells = nullptr;
    *count = 0;
    if (neighbours != nullptr) {
        *neighbours = nullptr;
        if (ordered) {
            return 2;
        }
    }
    if (n < 0 || n >= INT32_MAX) {
        return 2;
    }
    try {
        std::call_once(started, start_geogram);
        // The insertion order (a randomized spatial sort) draws from geogram's global random
        // engine; restarting it makes the row order a function of the input alone.
        GEO::Numeric::random_reset(-1);
        GEO::Delaunay_var triangulation = GEO::Delaunay::create(3, "BDEL");
        triangulation->set_keeps_infinite(false);
        triangulation->set_vertices(GEO::index_t(n), points);
        finite_cells(*triangulation, nullptr, ordered, cells, count, neighbours);
        return 0;
    } catch (...) {
        return 1;
    }
}

// The regular (weighted Delaunay) triangulation of the n points (x, y, z rows of `points`)
// with weights `weights` (power distance |x - p|^2 - w), exact for the doubles given
// (Delaunay_psm.cpp, vorobound's third change). Returns as vb_delaunay_cells; a point whose
// cell in the power diagram is empty (hidden) is in no tetrahedron, and of several points at
// one position only the heaviest (the first of those) can be.
int vb_regular_cells(const double* points, const double* weights, int64_t n, int ordered,
                     int64_t** cells, int64_t* count) {
    *cells = nullptr;
    *count = 0;
    if (n < 0 || n >= INT32_MAX) {
        return 2;
    }
    try {
        std::vector<double> lifted;
        std::vector<int64_t> original;
        GEO::Delaunay_var triangulation =
            regular_triangulation(points, weights, n, lifted, original);
        if (triangulation.is_null()) {
            return 1;
        }
        finite_cells(*triangulation, original.empty() ? nullptr : original.data(), ordered, cells,
                     count);
        return 0;
    } catch (...) {
        return 1;
    }
}

// The triangles of that regular triangulation whose three vertices are below `limit` (the
// check's balls come first, its filler points after them), each once, as 3 * *count indices
// (rows ascending; with `ordered` in lexicographic order), to be freed with vb_free_cells.
// Returns as vb_regular_cells, and 3 when the points span no volume (geogram makes no cell;
// a flat set has triangles all the same, which the caller then asks CGAL for).
int vb_regular_facets(const double* points, const double* weights, int64_t n, int64_t limit,
                      int ordered, int64_t** facets, int64_t* count) {
    *facets = nullptr;
    *count = 0;
    if (n < 0 || n >= INT32_MAX) {
        return 2;
    }
    try {
        std::vector<double> lifted;
        std::vector<int64_t> original;
        GEO::Delaunay_var triangulation =
            regular_triangulation(points, weights, n, lifted, original);
        if (triangulation.is_null()) {
            return 1;
        }
        if (triangulation->nb_cells() == 0) {
            return 3;
        }
        finite_facets(*triangulation, original.empty() ? nullptr : original.data(), limit,
                      ordered, facets, count);
        return 0;
    } catch (...) {
        return 1;
    }
}

void vb_free_cells(int64_t* cells) { delete[] cells; }

// Tests: the in-sphere predicate on five points (15 doubles, the first four positively
// oriented): *staged is the double-double stage's side4 sign (0: not sure), *full geogram's
// whole side4_3d (filter, that stage, exact with symbolic perturbation), 0 when geogram failed
// (an assertion, as on non-finite input).
void vb_side4_stages(const double* p, int* staged, int* full) {
    *staged = vb_insphere::side4_3d(p, p + 3, p + 6, p + 9, p + 12);
    *full = 0;
    try {
        std::call_once(started, start_geogram);
        *full = -int(GEO::PCK::in_sphere_3d_SOS(p, p + 3, p + 6, p + 9, p + 12));
    } catch (...) {
    }
}

// Tests: the weighted conflict test on five points (15 doubles, the first four not coplanar)
// and their weights (5 doubles), as side4 signs (+1: p4 is not in conflict with the
// tetrahedron, its power distance to the orthosphere is positive): *filtered the double
// filter's (0: not sure), *full the whole exact predicate's (with symbolic perturbation),
// *lifted geogram's original predicate on the heights |p_i|^2 - w_i rounded to doubles; the
// last two 0 when geogram failed.
void vb_side4w_stages(const double* p, const double* w, int* filtered, int* full, int* lifted) {
    *filtered = vb_power::side4w_3d_filter(p, p + 3, p + 6, p + 9, p + 12, w[0], w[1], w[2],
                                           w[3], w[4]);
    *full = 0;
    *lifted = 0;
    try {
        std::call_once(started, start_geogram);
        *full = -int(GEO::PCK::orient_3dweighted_SOS(p, p + 3, p + 6, p + 9, p + 12, w[0], w[1],
                                                      w[2], w[3], w[4]));
        double h[5];
        for (int i = 0; i < 5; ++i) {
            const double* q = p + 3 * i;
            h[i] = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] - w[i];
        }
        *lifted = -int(GEO::PCK::orient_3dlifted_SOS(p, p + 3, p + 6, p + 9, p + 12, h[0], h[1],
                                                      h[2], h[3], h[4]));
    } catch (...) {
    }
}

// Benchmarks and tests: 0 turns the double-double stage off (every test the double filter
// leaves goes to the exact stage), 1 back on.
void vb_set_double_double(int on) { vb_insphere::enabled = on != 0; }

}  // extern "C"

static struct PyModuleDef geogram_module = {
    PyModuleDef_HEAD_INIT, "_geogram",
    "geogram's Delaunay triangulation, called through ctypes (vorobound.sampling.geogram_delaunay)",
    -1, nullptr, nullptr, nullptr, nullptr, nullptr,
};

PyMODINIT_FUNC PyInit__geogram(void) { return PyModule_Create(&geogram_module); }
