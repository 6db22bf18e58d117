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
#include <new>

#include "Delaunay_psm.h"

namespace vb_insphere {
extern bool enabled;
int side4_3d(const double* p0, const double* p1, const double* p2, const double* p3,
             const double* p4);
}  // namespace vb_insphere

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

}  // namespace

extern "C" {

// Triangulates the n points (x, y, z rows of `points`). On success returns 0 and sets *cells to
// a new array of 4 * *count vertex indices (the finite tetrahedra, each row ascending; with
// `ordered` nonzero the rows in lexicographic order), to be freed with vb_free_cells. Returns 1
// when geogram failed (an assertion or an allocation), 2 for n out of range.
int vb_delaunay_cells(const double* points, int64_t n, int ordered, int64_t** cells,
                      int64_t* count) {
    *cells = nullptr;
    *count = 0;
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
        const GEO::index_t total = triangulation->nb_cells();
        int64_t finite = 0;
        for (GEO::index_t c = 0; c < total; ++c) {
            finite += triangulation->cell_is_infinite(c) ? 0 : 1;
        }
        int64_t* out = new int64_t[size_t(finite) * 4 + 1];
        const GEO::index_t* corners = triangulation->cell_to_v();
        int64_t k = 0;
        for (GEO::index_t c = 0; c < total; ++c) {
            if (triangulation->cell_is_infinite(c)) {
                continue;
            }
            int64_t* row = out + 4 * k;
            for (int j = 0; j < 4; ++j) {
                row[j] = int64_t(corners[4 * c + j]);
            }
            std::sort(row, row + 4);
            ++k;
        }
        if (ordered) {
            using Row = std::array<int64_t, 4>;  // 32 bytes, no padding: the rows in place
            static_assert(sizeof(Row) == 4 * sizeof(int64_t), "a row is four indices");
            Row* rows = reinterpret_cast<Row*>(out);
            std::sort(rows, rows + finite);
        }
        *cells = out;
        *count = finite;
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
