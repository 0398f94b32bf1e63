/*
 * ORCA's linear programs for many robots in one call (van den Berg et al., ISRR 2011,
 * section 5.2-5.3): for each robot the incremental 2-D program over its half-planes inside
 * the speed disc, and the 3-D program (largest violation minimised) when it is infeasible.
 *
 * The pure-Python functions of swarmpath/control/orca/lp.py are the reference: this file
 * performs the same operations in the same order (tested to agree). It exists because 1,000
 * robots with a dozen lines each cost far more in Python call overhead than in arithmetic.
 *
 * Compiled as swarmpath.control.orca._orcalp; arrays arrive through the buffer protocol as
 * C-contiguous float64 / int64 arrays, so no numpy headers are needed.
 *
 * A line k of robot i is lines[i, k] = (px, py, dx, dy): a point on its boundary and a unit
 * direction; velocities v with det(d, p - v) <= 0 (on its left) are permitted.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PARALLEL_EPS 1e-12

typedef struct {
    Py_buffer buf;
    int held;
} Arg;

static int get(PyObject *obj, Arg *a, int writable, char kind, const char *name) {
    int flags = PyBUF_C_CONTIGUOUS | PyBUF_FORMAT | (writable ? PyBUF_WRITABLE : 0);
    if (PyObject_GetBuffer(obj, &a->buf, flags) < 0) return -1;
    a->held = 1;
    const char *f = a->buf.format;
    char c = (f == NULL) ? 0 : ((f[0] == '<' || f[0] == '=' || f[0] == '@') ? f[1] : f[0]);
    int ok = a->buf.itemsize == 8 &&
             (kind == 'd' ? c == 'd' : (c == 'q' || c == 'l'));
    if (!ok) {
        PyErr_Format(PyExc_TypeError, "%s must be a %s array", name, kind == 'd' ? "float64" : "int64");
        return -1;
    }
    return 0;
}

static inline double det(double ax, double ay, double bx, double by) { return ax * by - ay * bx; }

/* One line: point (L[0], L[1]), direction (L[2], L[3]). */
static int lp1(const double *L, Py_ssize_t line_no, double radius, double ox, double oy,
               int direction_opt, double *rx, double *ry) {
    const double *l = L + 4 * line_no;
    double px = l[0], py = l[1], dx = l[2], dy = l[3];
    double dot = px * dx + py * dy;
    double disc = dot * dot + radius * radius - (px * px + py * py);
    if (disc < 0.0) return 0;
    double root = sqrt(disc);
    double t_left = -dot - root, t_right = -dot + root;
    for (Py_ssize_t i = 0; i < line_no; i++) {
        const double *m = L + 4 * i;
        double denominator = det(dx, dy, m[2], m[3]);
        double numerator = det(m[2], m[3], px - m[0], py - m[1]);
        if (fabs(denominator) <= PARALLEL_EPS) {
            if (numerator < 0.0) return 0;
            continue;
        }
        double t = numerator / denominator;
        if (denominator >= 0.0) {
            if (t < t_right) t_right = t;
        } else {
            if (t > t_left) t_left = t;
        }
        if (t_left > t_right) return 0;
    }
    double t;
    if (direction_opt) {
        t = (ox * dx + oy * dy > 0.0) ? t_right : t_left;
    } else {
        t = dx * (ox - px) + dy * (oy - py);
        if (t < t_left) t = t_left;
        if (t > t_right) t = t_right;
    }
    *rx = px + t * dx;
    *ry = py + t * dy;
    return 1;
}

static Py_ssize_t lp2(const double *L, Py_ssize_t n, double radius, double ox, double oy,
                      int direction_opt, double *rx, double *ry) {
    if (direction_opt) {
        *rx = ox * radius;
        *ry = oy * radius;
    } else if (ox * ox + oy * oy > radius * radius) {
        double norm = sqrt(ox * ox + oy * oy);
        *rx = ox / norm * radius;
        *ry = oy / norm * radius;
    } else {
        *rx = ox;
        *ry = oy;
    }
    for (Py_ssize_t i = 0; i < n; i++) {
        const double *l = L + 4 * i;
        if (det(l[2], l[3], l[0] - *rx, l[1] - *ry) > 0.0) {
            double nx, ny;
            if (!lp1(L, i, radius, ox, oy, direction_opt, &nx, &ny)) return i;
            *rx = nx;
            *ry = ny;
        }
    }
    return n;
}

static void lp3(const double *L, Py_ssize_t n, Py_ssize_t n_hard, Py_ssize_t begin, double radius,
                double *rx, double *ry, double *proj) {
    double distance = 0.0;
    for (Py_ssize_t i = begin; i < n; i++) {
        const double *li = L + 4 * i;
        double dx = li[2], dy = li[3];
        if (det(dx, dy, li[0] - *rx, li[1] - *ry) <= distance) continue;
        memcpy(proj, L, sizeof(double) * 4 * n_hard);
        Py_ssize_t m = n_hard;
        for (Py_ssize_t j = n_hard; j < i; j++) {
            const double *lj = L + 4 * j;
            double ex = lj[2], ey = lj[3];
            double determinant = det(dx, dy, ex, ey);
            double qx, qy;
            if (fabs(determinant) <= PARALLEL_EPS) {
                if (dx * ex + dy * ey > 0.0) continue;
                qx = 0.5 * (li[0] + lj[0]);
                qy = 0.5 * (li[1] + lj[1]);
            } else {
                double s = det(ex, ey, li[0] - lj[0], li[1] - lj[1]) / determinant;
                qx = li[0] + s * dx;
                qy = li[1] + s * dy;
            }
            double bx = ex - dx, by = ey - dy;
            double norm = sqrt(bx * bx + by * by);
            double *p = proj + 4 * m;
            p[0] = qx;
            p[1] = qy;
            p[2] = bx / norm;
            p[3] = by / norm;
            m++;
        }
        double nx, ny;
        if (lp2(proj, m, radius, -dy, dx, 1, &nx, &ny) >= m) {
            *rx = nx;
            *ry = ny;
        }
        distance = det(dx, dy, li[0] - *rx, li[1] - *ry);
    }
}

/* solve(lines, n_lines, n_hard, n_firm, preferred, radius, out, status) -> None
 *
 * lines (n, k, 4) float64; n_lines, n_hard, n_firm (n,) int64; preferred (n, 2) and radius
 * (n,) float64; out (n, 2) float64 and status (n,) int64 are written (status as in
 * lp.solve_orca_lp: 0 feasible, 1 soft lines relaxed, 2 firm lines relaxed, 3 standing).
 */
static PyObject *solve(PyObject *self, PyObject *args) {
    PyObject *o[8];
    static const char *names[8] = {"lines", "n_lines", "n_hard", "n_firm", "preferred", "radius", "out", "status"};
    static const char kinds[8] = {'d', 'q', 'q', 'q', 'd', 'd', 'd', 'q'};
    Arg a[8] = {{0}};
    PyObject *result = NULL;
    double *proj = NULL;
    if (!PyArg_ParseTuple(args, "OOOOOOOO", &o[0], &o[1], &o[2], &o[3], &o[4], &o[5], &o[6], &o[7]))
        return NULL;
    for (int k = 0; k < 8; k++)
        if (get(o[k], &a[k], k >= 6, kinds[k], names[k]) < 0) goto done;
    Py_ssize_t n = a[5].buf.len / 8;
    if (a[1].buf.len / 8 != n || a[2].buf.len / 8 != n || a[3].buf.len / 8 != n || a[7].buf.len / 8 != n ||
        a[4].buf.len / 8 != 2 * n || a[6].buf.len / 8 != 2 * n || (n > 0 && (a[0].buf.len / 8) % (4 * n) != 0)) {
        PyErr_SetString(PyExc_ValueError, "shapes must be lines (n, k, 4), counts (n,), preferred/out (n, 2)");
        goto done;
    }
    Py_ssize_t k = n > 0 ? a[0].buf.len / 8 / (4 * n) : 0;
    const double *lines = (const double *)a[0].buf.buf;
    const long long *n_lines = (const long long *)a[1].buf.buf;
    const long long *n_hard = (const long long *)a[2].buf.buf;
    const long long *n_firm = (const long long *)a[3].buf.buf;
    const double *pref = (const double *)a[4].buf.buf;
    const double *radius = (const double *)a[5].buf.buf;
    double *out = (double *)a[6].buf.buf;
    long long *status = (long long *)a[7].buf.buf;
    for (Py_ssize_t i = 0; i < n; i++) {
        if (n_lines[i] < 0 || n_lines[i] > k || n_hard[i] < 0 || n_firm[i] < n_hard[i] || n_firm[i] > n_lines[i]) {
            PyErr_SetString(PyExc_ValueError, "need 0 <= n_hard <= n_firm <= n_lines <= k");
            goto done;
        }
    }
    proj = (double *)malloc(sizeof(double) * 4 * (k > 0 ? k : 1));
    if (proj == NULL) {
        PyErr_NoMemory();
        goto done;
    }
    Py_BEGIN_ALLOW_THREADS
    for (Py_ssize_t i = 0; i < n; i++) {
        const double *L = lines + 4 * k * i;
        Py_ssize_t m = (Py_ssize_t)n_lines[i];
        double rx, ry;
        Py_ssize_t fail = lp2(L, m, radius[i], pref[2 * i], pref[2 * i + 1], 0, &rx, &ry);
        long long st = 0;
        if (fail < m) {
            if (fail >= n_firm[i]) {
                lp3(L, m, (Py_ssize_t)n_firm[i], fail, radius[i], &rx, &ry, proj);
                st = 1;
            } else if (fail >= n_hard[i]) {
                /* obstacles corner the robot: balance the firm lines alone */
                lp3(L, (Py_ssize_t)n_firm[i], (Py_ssize_t)n_hard[i], fail, radius[i], &rx, &ry, proj);
                st = 2;
            } else {
                rx = 0.0;
                ry = 0.0;
                st = 3;
            }
        }
        out[2 * i] = rx;
        out[2 * i + 1] = ry;
        status[i] = st;
    }
    Py_END_ALLOW_THREADS
    result = Py_None;
    Py_INCREF(result);
done:
    free(proj);
    for (int q = 0; q < 8; q++)
        if (a[q].held) PyBuffer_Release(&a[q].buf);
    return result;
}

static PyMethodDef methods[] = {
    {"solve", solve, METH_VARARGS, "ORCA's 2-D and 3-D linear programs for every robot"},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_orcalp",
                                    "ORCA linear programs (see swarmpath/control/orca/lp.py)", -1, methods};

PyMODINIT_FUNC PyInit__orcalp(void) { return PyModule_Create(&module); }
