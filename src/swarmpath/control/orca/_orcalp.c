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
 * C-contiguous float64 / int64 / bool arrays, so no numpy headers are needed.
 *
 * Besides the programs (solve) it holds the other per-step loops of ORCASolver that cost
 * more in numpy call overhead than in arithmetic, each with a numpy reference it equals bit
 * for bit (tests/control/test_orca_kernels.py):
 * - knn: each robot's nearest robots within the neighbour distance (core.ORCASolver.neighbours,
 *   whose reference is scipy's cKDTree; robots with tied distances are flagged and left to it);
 * - robot_halfplanes: ORCA's robot-robot lines (halfplanes.orca_halfplanes_robots);
 * - count_lines / pack_lines: lines packed per robot by tier (kernels.pack_lines, numpy);
 * - robot_pairs: the pairwise move check of core.ORCASolver._robot_pairs (move_rules);
 * - tidy: core.tidy_moves.
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
    int ok = kind == 'b' ? (a->buf.itemsize == 1 && (c == '?' || c == 'B' || c == 'b'))
                         : (a->buf.itemsize == 8 && (kind == 'd' ? c == 'd' : (c == 'q' || c == 'l')));
    if (!ok) {
        PyErr_Format(PyExc_TypeError, "%s must be a %s array", name,
                     kind == 'd' ? "float64" : (kind == 'b' ? "bool" : "int64"));
        return -1;
    }
    return 0;
}

/* Release the buffers of the first n arguments that get() took. */
static void release(Arg *a, int n) {
    for (int q = 0; q < n; q++)
        if (a[q].held) PyBuffer_Release(&a[q].buf);
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
    release(a, 8);
    return result;
}

/* ------------------------------------------------------------------------------------------
 * A uniform grid over n points for neighbour searches: square cells of side at least
 * min_cell (a hair more, so that rounding of (x - x0) / cell never puts two points closer than
 * min_cell two cells apart), doubled until there are at most 4 n + 64 cells; points are
 * bucketed by a counting sort. Two points closer than min_cell lie in the same or in
 * adjacent cells, so a search of the 3 x 3 cells around a point finds a superset of its
 * neighbours; callers then apply their exact distance test.
 */
typedef struct {
    double x0, y0, cell;
    Py_ssize_t nx, ny;
    Py_ssize_t *start; /* (nx * ny + 1): the points of cell c are items[start[c] .. start[c + 1]) */
    Py_ssize_t *items; /* (n) point indices, cell by cell, each cell in increasing index */
    Py_ssize_t *cx;    /* (n) column of each point */
    Py_ssize_t *cy;    /* (n) row of each point */
} Grid;

static void grid_free(Grid *g) {
    free(g->start);
    free(g->items);
    free(g->cx);
    free(g->cy);
    g->start = g->items = g->cx = g->cy = NULL;
}

/* Returns 0, or -1 with a Python exception set (memory, or positions not finite). */
static int grid_build(Grid *g, const double *pos, Py_ssize_t n, double min_cell) {
    memset(g, 0, sizeof(*g));
    double xmin = 0.0, xmax = 0.0, ymin = 0.0, ymax = 0.0;
    for (Py_ssize_t i = 0; i < n; i++) {
        double x = pos[2 * i], y = pos[2 * i + 1];
        if (!isfinite(x) || !isfinite(y)) {
            PyErr_SetString(PyExc_ValueError, "positions must be finite");
            return -1;
        }
        if (i == 0 || x < xmin) xmin = x;
        if (i == 0 || x > xmax) xmax = x;
        if (i == 0 || y < ymin) ymin = y;
        if (i == 0 || y > ymax) ymax = y;
    }
    double wx = xmax - xmin, wy = ymax - ymin;
    /* any side works (the grid only narrows the candidates): min_cell <= 0 asks for nothing */
    double cell = min_cell > 0.0 ? min_cell * (1.0 + 1e-6) : 1.0;
    double cap = 4.0 * (double)n + 64.0;
    while ((floor(wx / cell) + 1.0) * (floor(wy / cell) + 1.0) > cap) cell *= 2.0;
    g->x0 = xmin;
    g->y0 = ymin;
    g->cell = cell;
    g->nx = (Py_ssize_t)(floor(wx / cell) + 1.0);
    g->ny = (Py_ssize_t)(floor(wy / cell) + 1.0);
    Py_ssize_t cells = g->nx * g->ny;
    g->start = (Py_ssize_t *)calloc((size_t)cells + 1, sizeof(Py_ssize_t));
    g->items = (Py_ssize_t *)malloc(sizeof(Py_ssize_t) * (size_t)(n > 0 ? n : 1));
    g->cx = (Py_ssize_t *)malloc(sizeof(Py_ssize_t) * (size_t)(n > 0 ? n : 1));
    g->cy = (Py_ssize_t *)malloc(sizeof(Py_ssize_t) * (size_t)(n > 0 ? n : 1));
    if (!g->start || !g->items || !g->cx || !g->cy) {
        grid_free(g);
        PyErr_NoMemory();
        return -1;
    }
    for (Py_ssize_t i = 0; i < n; i++) {
        Py_ssize_t cx = (Py_ssize_t)((pos[2 * i] - xmin) / cell);
        Py_ssize_t cy = (Py_ssize_t)((pos[2 * i + 1] - ymin) / cell);
        if (cx >= g->nx) cx = g->nx - 1; /* unreachable with finite input, kept as a guard */
        if (cy >= g->ny) cy = g->ny - 1;
        g->cx[i] = cx;
        g->cy[i] = cy;
        g->start[cy * g->nx + cx + 1]++;
    }
    for (Py_ssize_t c = 0; c < cells; c++) g->start[c + 1] += g->start[c];
    /* place the points, counting start[c] up; then shift back (start[c] = old start[c]) */
    for (Py_ssize_t i = 0; i < n; i++) g->items[g->start[g->cy[i] * g->nx + g->cx[i]]++] = i;
    for (Py_ssize_t c = cells; c > 0; c--) g->start[c] = g->start[c - 1];
    g->start[0] = 0;
    return 0;
}

/* Inserts candidate j at squared distance d2 into the list best_d/best_i of the *count
 * nearest so far (at most k1, sorted by d2, a new one after equal ones). */
static inline void keep_nearest(double *best_d, Py_ssize_t *best_i, Py_ssize_t *count, Py_ssize_t k1, double d2,
                                Py_ssize_t j) {
    if (*count == k1 && !(d2 < best_d[k1 - 1])) return;
    Py_ssize_t at = *count < k1 ? (*count)++ : k1 - 1;
    while (at > 0 && best_d[at - 1] > d2) {
        best_d[at] = best_d[at - 1];
        best_i[at] = best_i[at - 1];
        at--;
    }
    best_d[at] = d2;
    best_i[at] = j;
}

/* knn(pos, k, upper, idx, tied) -> None
 *
 * For each of n robots (pos (n, 2) float64) the k nearest robots (itself included, as in
 * cKDTree(pos).query(pos, k, distance_upper_bound=upper)) whose squared distance
 * dx * dx + dy * dy is below upper * upper, nearest first: idx (n, k) int64 is written, -1
 * where fewer are found. cKDTree orders robots at equal distances by its tree, which this
 * loop does not reproduce: tied (n,) bool marks the robots where two of the k nearest, or
 * the k-th and the next, are at exactly the same distance (their row of idx is then some
 * valid order; the caller asks cKDTree for them).
 *
 * The search visits rings of grid cells around the robot's cell (ring r: the cells r
 * columns or rows away) and stops once no point of the next ring can be nearer than the
 * (k + 1)-th found so far, or lie within upper.
 */
static PyObject *knn(PyObject *self, PyObject *args) {
    PyObject *o[3];
    Py_ssize_t k;
    double upper;
    Arg a[3] = {{0}};
    PyObject *result = NULL;
    Grid g = {0};
    double *best_d = NULL;
    Py_ssize_t *best_i = NULL;
    if (!PyArg_ParseTuple(args, "OndOO", &o[0], &k, &upper, &o[1], &o[2])) return NULL;
    if (get(o[0], &a[0], 0, 'd', "pos") < 0 || get(o[1], &a[1], 1, 'q', "idx") < 0 ||
        get(o[2], &a[2], 1, 'b', "tied") < 0)
        goto done;
    Py_ssize_t n = a[0].buf.len / 16;
    if (k < 1 || !(upper > 0.0) || a[0].buf.len != 16 * n || a[1].buf.len != 8 * n * k || a[2].buf.len != n) {
        PyErr_SetString(PyExc_ValueError,
                        "shapes must be pos (n, 2), idx (n, k), tied (n,) with k >= 1, and upper > 0");
        goto done;
    }
    const double *pos = (const double *)a[0].buf.buf;
    long long *idx = (long long *)a[1].buf.buf;
    char *tied = (char *)a[2].buf.buf;
    /* cells of about one robot each on average over the bounding box, between upper / 16
     * (a bounded number of rings within upper) and upper (3 x 3 cells cover it) */
    double cell = upper;
    if (n > 0) {
        double xmin = pos[0], xmax = pos[0], ymin = pos[1], ymax = pos[1];
        for (Py_ssize_t i = 1; i < n; i++) {
            double x = pos[2 * i], y = pos[2 * i + 1];
            xmin = x < xmin ? x : xmin;
            xmax = x > xmax ? x : xmax;
            ymin = y < ymin ? y : ymin;
            ymax = y > ymax ? y : ymax;
        }
        double spacing = sqrt((xmax - xmin) * (ymax - ymin) / (double)n);
        if (spacing < cell) cell = spacing;  /* a NaN spacing (infinite positions) keeps upper */
        if (cell < upper / 16.0) cell = upper / 16.0;
    }
    if (grid_build(&g, pos, n, cell) < 0) goto done;
    /* the k + 1 nearest so far, sorted by squared distance: the (k + 1)-th reveals a tie at the cut */
    Py_ssize_t k1 = k + 1;
    best_d = (double *)malloc(sizeof(double) * (size_t)k1);
    best_i = (Py_ssize_t *)malloc(sizeof(Py_ssize_t) * (size_t)k1);
    if (!best_d || !best_i) {
        PyErr_NoMemory();
        goto done;
    }
    double upper_sq = upper * upper;
    Py_ssize_t rings = g.nx > g.ny ? g.nx : g.ny;
    for (Py_ssize_t i = 0; i < n; i++) {
        double x = pos[2 * i], y = pos[2 * i + 1];
        Py_ssize_t count = 0, ci = g.cx[i], cj = g.cy[i];
        for (Py_ssize_t r = 0; r < rings; r++) {
            if (r >= 2) {
                /* every point of ring r is at least (r - 1) cells away along x or y (less a
                 * hair for the rounding of the cell of a point on a border) */
                double low = ((double)(r - 1) - 1e-6) * g.cell;
                double low_sq = low * low;
                if (low_sq >= upper_sq || (count == k1 && low_sq > best_d[k1 - 1])) break;
            }
            Py_ssize_t y0 = cj - r < 0 ? 0 : cj - r, y1 = cj + r >= g.ny ? g.ny - 1 : cj + r;
            Py_ssize_t x0 = ci - r < 0 ? 0 : ci - r, x1 = ci + r >= g.nx ? g.nx - 1 : ci + r;
            for (Py_ssize_t cy = y0; cy <= y1; cy++) {
                /* whole rows at the ring's top and bottom, else its two side cells */
                int edge_row = cy == cj - r || cy == cj + r;
                Py_ssize_t step = edge_row ? 1 : 2 * r;
                for (Py_ssize_t cx = edge_row ? x0 : ci - r; cx <= (edge_row ? x1 : ci + r); cx += step) {
                    if (cx < 0 || cx >= g.nx) continue;
                    Py_ssize_t c = cy * g.nx + cx;
                    for (Py_ssize_t s = g.start[c]; s < g.start[c + 1]; s++) {
                        Py_ssize_t j = g.items[s];
                        double dx = x - pos[2 * j], dy = y - pos[2 * j + 1];
                        double d2 = dx * dx + dy * dy;
                        if (d2 < upper_sq) keep_nearest(best_d, best_i, &count, k1, d2, j);
                    }
                }
            }
        }
        Py_ssize_t kept = count < k ? count : k;
        char tie = count > k && best_d[k - 1] == best_d[k];
        for (Py_ssize_t r = 0; r < k; r++) {
            idx[i * k + r] = r < kept ? (long long)best_i[r] : -1;
            if (r > 0 && r < kept && best_d[r] == best_d[r - 1]) tie = 1;
        }
        tied[i] = tie;
    }
    result = Py_None;
    Py_INCREF(result);
done:
    free(best_d);
    free(best_i);
    grid_free(&g);
    release(a, 3);
    return result;
}

/* robot_halfplanes(pos, vel, radii, resp, i, j, diag, margin, tau, dt, points, directions) -> None
 *
 * ORCA's line of robot i[e] for its neighbour j[e], e < E: the arithmetic of
 * halfplanes.orca_halfplanes_robots(pos[j] - pos[i], vel[i] - vel[j], vel[i], R, tau, dt,
 * resp[j]) in the same order, so the results are the same bits, with the combined radius
 * R = (radii[i] == radii[j] == 0 ? diag : radii[i] + radii[j]) + margin of
 * core.ORCASolver.combined_radius. pos, vel (n, 2), radii, resp (n,) float64; i, j (E,)
 * int64; points and directions (E, 2) float64 are written.
 */
static PyObject *robot_halfplanes(PyObject *self, PyObject *args) {
    PyObject *o[8];
    static const char *names[8] = {"pos", "vel", "radii", "resp", "i", "j", "points", "directions"};
    static const char kinds[8] = {'d', 'd', 'd', 'd', 'q', 'q', 'd', 'd'};
    double diag, margin, tau, dt;
    Arg a[8] = {{0}};
    PyObject *result = NULL;
    if (!PyArg_ParseTuple(args, "OOOOOOddddOO", &o[0], &o[1], &o[2], &o[3], &o[4], &o[5], &diag, &margin, &tau,
                          &dt, &o[6], &o[7]))
        return NULL;
    for (int q = 0; q < 8; q++)
        if (get(o[q], &a[q], q >= 6, kinds[q], names[q]) < 0) goto done;
    Py_ssize_t n = a[2].buf.len / 8, e = a[4].buf.len / 8;
    if (a[0].buf.len != 16 * n || a[1].buf.len != 16 * n || a[3].buf.len != 8 * n || a[5].buf.len != 8 * e ||
        a[6].buf.len != 16 * e || a[7].buf.len != 16 * e) {
        PyErr_SetString(PyExc_ValueError, "shapes must be pos, vel (n, 2), radii, resp (n,), i, j (e,), out (e, 2)");
        goto done;
    }
    const double *pos = (const double *)a[0].buf.buf, *vel = (const double *)a[1].buf.buf;
    const double *radii = (const double *)a[2].buf.buf, *resp = (const double *)a[3].buf.buf;
    const long long *ii = (const long long *)a[4].buf.buf, *jj = (const long long *)a[5].buf.buf;
    double *points = (double *)a[6].buf.buf, *dirs = (double *)a[7].buf.buf;
    for (Py_ssize_t q = 0; q < e; q++) {
        if (ii[q] < 0 || ii[q] >= n || jj[q] < 0 || jj[q] >= n) {
            PyErr_SetString(PyExc_IndexError, "robot index out of range");
            goto done;
        }
    }
    const double tiny = 1e-12; /* halfplanes._TINY */
    double inv_tau = 1.0 / tau, inv_dt = 1.0 / dt;
    for (Py_ssize_t q = 0; q < e; q++) {
        Py_ssize_t i = (Py_ssize_t)ii[q], j = (Py_ssize_t)jj[q];
        double R = ((radii[i] == 0.0 && radii[j] == 0.0) ? diag : radii[i] + radii[j]) + margin;
        double c = resp[j];
        double px = pos[2 * j] - pos[2 * i], py = pos[2 * j + 1] - pos[2 * i + 1];
        double vx = vel[2 * i] - vel[2 * j], vy = vel[2 * i + 1] - vel[2 * j + 1];
        double dist_sq = px * px + py * py;
        double r_sq = R * R;
        int apart = dist_sq > r_sq;
        /* vector from the cut-off centre to the relative velocity: tau apart, dt in contact */
        double inv = apart ? inv_tau : inv_dt;
        double wx = vx - inv * px, wy = vy - inv * py;
        double w_sq = wx * wx + wy * wy;
        double dot1 = wx * px + wy * py;
        int on_circle = !apart || (dot1 < 0.0 && dot1 * dot1 > r_sq * w_sq);
        double dx, dy, ux, uy;
        if (on_circle) {
            double w_len = sqrt(w_sq);
            double ox, oy;
            if (w_len > tiny) {
                ox = wx / w_len;
                oy = wy / w_len;
            } else {
                /* degenerate (w = 0 while in contact): push straight apart */
                double d_len = sqrt(dist_sq);
                if (d_len > tiny) {
                    ox = -px / d_len;
                    oy = -py / d_len;
                } else {
                    ox = -1.0;
                    oy = 0.0;
                }
            }
            dx = oy;
            dy = -ox;
            double s = R * inv - w_len;
            ux = s * ox;
            uy = s * oy;
        } else {
            /* legs of the cone; apart here, so dist_sq > r_sq >= 0 */
            double leg = sqrt(dist_sq - r_sq > 0.0 ? dist_sq - r_sq : 0.0);
            double safe_sq = dist_sq > tiny ? dist_sq : 1.0;
            if (px * wy - py * wx > 0.0) {
                dx = (px * leg - py * R) / safe_sq;
                dy = (px * R + py * leg) / safe_sq;
            } else {
                dx = -(px * leg + py * R) / safe_sq;
                dy = -(-px * R + py * leg) / safe_sq;
            }
            double dot2 = vx * dx + vy * dy;
            ux = dot2 * dx - vx;
            uy = dot2 * dy - vy;
        }
        points[2 * q] = vel[2 * i] + c * ux;
        points[2 * q + 1] = vel[2 * i + 1] + c * uy;
        dirs[2 * q] = dx;
        dirs[2 * q + 1] = dy;
    }
    result = Py_None;
    Py_INCREF(result);
done:
    release(a, 8);
    return result;
}

/* count_lines(owner, tier, n_lines, n_hard, n_firm) -> None
 *
 * Per robot the number of lines, of hard lines (tier 0) and of hard and firm lines (tiers 0
 * and 1): owner, tier (e,) int64 (tiers 0, 1, 2); the counts (n,) int64 are written.
 */
static PyObject *count_lines(PyObject *self, PyObject *args) {
    PyObject *o[5];
    static const char *names[5] = {"owner", "tier", "n_lines", "n_hard", "n_firm"};
    Arg a[5] = {{0}};
    PyObject *result = NULL;
    if (!PyArg_ParseTuple(args, "OOOOO", &o[0], &o[1], &o[2], &o[3], &o[4])) return NULL;
    for (int q = 0; q < 5; q++)
        if (get(o[q], &a[q], q >= 2, 'q', names[q]) < 0) goto done;
    Py_ssize_t e = a[0].buf.len / 8, n = a[2].buf.len / 8;
    if (a[1].buf.len != 8 * e || a[3].buf.len != 8 * n || a[4].buf.len != 8 * n) {
        PyErr_SetString(PyExc_ValueError, "shapes must be owner, tier (e,), counts (n,)");
        goto done;
    }
    const long long *owner = (const long long *)a[0].buf.buf, *tier = (const long long *)a[1].buf.buf;
    long long *n_lines = (long long *)a[2].buf.buf, *n_hard = (long long *)a[3].buf.buf;
    long long *n_firm = (long long *)a[4].buf.buf;
    for (Py_ssize_t q = 0; q < e; q++) {
        if (owner[q] < 0 || owner[q] >= n || tier[q] < 0 || tier[q] > 2) {
            PyErr_SetString(PyExc_ValueError, "need 0 <= owner < n and tier in 0, 1, 2");
            goto done;
        }
    }
    memset(n_lines, 0, 8 * (size_t)n);
    memset(n_hard, 0, 8 * (size_t)n);
    memset(n_firm, 0, 8 * (size_t)n);
    for (Py_ssize_t q = 0; q < e; q++) {
        n_lines[owner[q]]++;
        if (tier[q] == 0) n_hard[owner[q]]++;
        if (tier[q] <= 1) n_firm[owner[q]]++;
    }
    result = Py_None;
    Py_INCREF(result);
done:
    release(a, 5);
    return result;
}

/* pack_lines(owner, tier, points, directions, n_hard, n_firm, lines) -> None
 *
 * Copies line q (points[q], directions[q]) to lines[owner[q], slot]: each robot's hard lines
 * from slot 0, firm from n_hard, soft from n_firm, each tier in the given order (the order of
 * kernels.pack_lines' stable sort by robot and tier). owner, tier (e,) int64; points,
 * directions (e, 2) float64; n_hard, n_firm (n,) int64 from count_lines; lines (n, k, 4)
 * float64 is written where lines go (the caller zeroes it).
 */
static PyObject *pack_lines(PyObject *self, PyObject *args) {
    PyObject *o[7];
    static const char *names[7] = {"owner", "tier", "points", "directions", "n_hard", "n_firm", "lines"};
    static const char kinds[7] = {'q', 'q', 'd', 'd', 'q', 'q', 'd'};
    Arg a[7] = {{0}};
    PyObject *result = NULL;
    Py_ssize_t *cursor = NULL;
    if (!PyArg_ParseTuple(args, "OOOOOOO", &o[0], &o[1], &o[2], &o[3], &o[4], &o[5], &o[6])) return NULL;
    for (int q = 0; q < 7; q++)
        if (get(o[q], &a[q], q == 6, kinds[q], names[q]) < 0) goto done;
    Py_ssize_t e = a[0].buf.len / 8, n = a[4].buf.len / 8;
    if (a[1].buf.len != 8 * e || a[2].buf.len != 16 * e || a[3].buf.len != 16 * e || a[5].buf.len != 8 * n ||
        (n > 0 && (a[6].buf.len / 8) % (4 * n) != 0)) {
        PyErr_SetString(PyExc_ValueError, "shapes must be owner, tier (e,), points, directions (e, 2), "
                                          "counts (n,), lines (n, k, 4)");
        goto done;
    }
    Py_ssize_t k = n > 0 ? a[6].buf.len / 8 / (4 * n) : 0;
    const long long *owner = (const long long *)a[0].buf.buf, *tier = (const long long *)a[1].buf.buf;
    const double *points = (const double *)a[2].buf.buf, *dirs = (const double *)a[3].buf.buf;
    const long long *n_hard = (const long long *)a[4].buf.buf, *n_firm = (const long long *)a[5].buf.buf;
    double *lines = (double *)a[6].buf.buf;
    /* the next free slot of each robot's three tiers */
    cursor = (Py_ssize_t *)malloc(sizeof(Py_ssize_t) * 3 * (size_t)(n > 0 ? n : 1));
    if (cursor == NULL) {
        PyErr_NoMemory();
        goto done;
    }
    for (Py_ssize_t r = 0; r < n; r++) {
        cursor[3 * r] = 0;
        cursor[3 * r + 1] = (Py_ssize_t)n_hard[r];
        cursor[3 * r + 2] = (Py_ssize_t)n_firm[r];
    }
    for (Py_ssize_t q = 0; q < e; q++) {
        if (owner[q] < 0 || owner[q] >= n || tier[q] < 0 || tier[q] > 2) {
            PyErr_SetString(PyExc_ValueError, "need 0 <= owner < n and tier in 0, 1, 2");
            goto done;
        }
        Py_ssize_t slot = cursor[3 * owner[q] + tier[q]]++;
        if (slot >= k) {
            PyErr_SetString(PyExc_ValueError, "more lines than the counts and k allow");
            goto done;
        }
        double *l = lines + 4 * (k * owner[q] + slot);
        l[0] = points[2 * q];
        l[1] = points[2 * q + 1];
        l[2] = dirs[2 * q];
        l[3] = dirs[2 * q + 1];
    }
    result = Py_None;
    Py_INCREF(result);
done:
    free(cursor);
    release(a, 7);
    return result;
}

/* Whether the moves of robots a and b at their levels conflict under the simulator's move
 * rules (move_rules.move_conflicts != NO_CONFLICT), with the same arithmetic: end positions
 * p0 + scales[level] * d; need = r_a + r_b - EPS (EPS for two point robots); VERTEX when the
 * ends are closer than need or two point robots end in one grid cell, SWAP when two point
 * robots exchange cells, CROSSING when the swept gap (move_rules.swept_gap) is below need.
 * rr are the radii the check uses (core: radius + CHECK_SLACK for discs, 0 for points). */
static int moves_conflict(const double *p0, const double *d, const double *rr, const long long *level,
                          const double *scales, double resolution, Py_ssize_t a, Py_ssize_t b) {
    const double eps = 1e-9; /* swarmpath.world.geometry.EPS */
    double sa = scales[level[a]], sb = scales[level[b]];
    double a0x = p0[2 * a], a0y = p0[2 * a + 1], b0x = p0[2 * b], b0y = p0[2 * b + 1];
    double a1x = a0x + sa * d[2 * a], a1y = a0y + sa * d[2 * a + 1];
    double b1x = b0x + sb * d[2 * b], b1y = b0y + sb * d[2 * b + 1];
    double rsum = rr[a] + rr[b];
    double need = rsum > 0.0 ? rsum - eps : eps;
    /* end positions (VERTEX) */
    double ex = a1x - b1x, ey = a1y - b1y;
    if (sqrt(ex * ex + ey * ey) < need) return 1;
    /* the relative motion (p0_a - p0_b) -> (p1_a - p1_b): its distance to the origin
     * (geometry.origin_segment_distance; CROSSING) */
    double ax = a0x - b0x, ay = a0y - b0y;
    double dx = ex - ax, dy = ey - ay;
    double denom = dx * dx + dy * dy;
    double t = -(ax * dx + ay * dy) / (denom > 0.0 ? denom : 1.0);
    if (t < 0.0) t = 0.0;
    if (t > 1.0) t = 1.0;
    double cx = ax + t * dx, cy = ay + t * dy;
    if (sqrt(cx * cx + cy * cy) < need) return 1;
    if (rr[a] == 0.0 && rr[b] == 0.0) {
        /* point robots: cells floor(p / resolution + 1e-9) (move_rules.point_cells) */
        double ca0x = floor(a0x / resolution + 1e-9), ca0y = floor(a0y / resolution + 1e-9);
        double cb0x = floor(b0x / resolution + 1e-9), cb0y = floor(b0y / resolution + 1e-9);
        double ca1x = floor(a1x / resolution + 1e-9), ca1y = floor(a1y / resolution + 1e-9);
        double cb1x = floor(b1x / resolution + 1e-9), cb1y = floor(b1y / resolution + 1e-9);
        if (ca1x == cb1x && ca1y == cb1y) return 1;                      /* VERTEX: same end cell */
        if (ca1x == cb0x && ca1y == cb0y && cb1x == ca0x && cb1y == ca0y &&
            (ca0x != cb0x || ca0y != cb0y))
            return 1;                                                     /* SWAP */
    }
    return 0;
}

/* robot_pairs(p0, d, rr, threatened, level, scales, resolution, extra) -> None
 *
 * core.ORCASolver._robot_pairs: every pair of robots whose starts p0 (n, 2) lie within
 * reach = 2 max |d| + extra (beyond which two moves cannot conflict; the caller's extra covers
 * the radii) is checked by moves_conflict at the robots' levels (n,) int64, index into
 * scales (s,) float64, of the moves d (n, 2). In each
 * round every conflicting pair lowers (level + 1) its robot of lower priority (threatened
 * (n,) bool first, then the smaller index ranks higher), or the other when that one cannot
 * (it is at the last level or does not move); only pairs with a robot lowered are checked
 * again; at most (s - 1) n + 1 rounds. level is updated in place; rr (n,) as in
 * moves_conflict.
 */
static PyObject *robot_pairs(PyObject *self, PyObject *args) {
    PyObject *o[6];
    static const char *names[6] = {"p0", "d", "rr", "threatened", "level", "scales"};
    static const char kinds[6] = {'d', 'd', 'd', 'b', 'q', 'd'};
    double resolution, extra;
    Arg a[6] = {{0}};
    PyObject *result = NULL;
    Grid g = {0};
    Py_ssize_t *pi = NULL, *pj = NULL, *test = NULL;
    char *bad = NULL, *can = NULL, *lower = NULL, *moving = NULL;
    if (!PyArg_ParseTuple(args, "OOOOOOdd", &o[0], &o[1], &o[2], &o[3], &o[4], &o[5], &resolution, &extra))
        return NULL;
    for (int q = 0; q < 6; q++)
        if (get(o[q], &a[q], q == 4, kinds[q], names[q]) < 0) goto done;
    Py_ssize_t n = a[2].buf.len / 8, ns = a[5].buf.len / 8;
    if (a[0].buf.len != 16 * n || a[1].buf.len != 16 * n || a[3].buf.len != n || a[4].buf.len != 8 * n || ns < 1) {
        PyErr_SetString(PyExc_ValueError, "shapes must be p0, d (n, 2), rr, threatened, level (n,), scales (s,)");
        goto done;
    }
    const double *p0 = (const double *)a[0].buf.buf, *d = (const double *)a[1].buf.buf;
    const double *rr = (const double *)a[2].buf.buf, *scales = (const double *)a[5].buf.buf;
    const char *threatened = (const char *)a[3].buf.buf;
    long long *level = (long long *)a[4].buf.buf;
    long long last = (long long)ns - 1;
    for (Py_ssize_t r = 0; r < n; r++) {
        if (level[r] < 0 || level[r] > last) {
            PyErr_SetString(PyExc_ValueError, "levels must index scales");
            goto done;
        }
    }
    if (n < 2) goto ok;
    /* the pairs (i < j) within reach */
    double longest = 0.0;
    for (Py_ssize_t r = 0; r < n; r++) {
        double len = sqrt(d[2 * r] * d[2 * r] + d[2 * r + 1] * d[2 * r + 1]);
        if (len > longest) longest = len;
    }
    double reach = 2.0 * longest + extra;
    if (grid_build(&g, p0, n, reach) < 0) goto done;
    Py_ssize_t np_ = 0, cap = 4 * n;
    pi = (Py_ssize_t *)malloc(sizeof(Py_ssize_t) * (size_t)cap);
    pj = (Py_ssize_t *)malloc(sizeof(Py_ssize_t) * (size_t)cap);
    if (!pi || !pj) {
        PyErr_NoMemory();
        goto done;
    }
    double reach_sq = reach * reach;
    for (Py_ssize_t i = 0; i < n; i++) {
        double x = p0[2 * i], y = p0[2 * i + 1];
        for (Py_ssize_t cy = g.cy[i] - 1; cy <= g.cy[i] + 1; cy++) {
            if (cy < 0 || cy >= g.ny) continue;
            for (Py_ssize_t cx = g.cx[i] - 1; cx <= g.cx[i] + 1; cx++) {
                if (cx < 0 || cx >= g.nx) continue;
                Py_ssize_t c = cy * g.nx + cx;
                for (Py_ssize_t s = g.start[c]; s < g.start[c + 1]; s++) {
                    Py_ssize_t j = g.items[s];
                    if (j <= i) continue;
                    double dx = x - p0[2 * j], dy = y - p0[2 * j + 1];
                    if (dx * dx + dy * dy > reach_sq) continue;
                    if (np_ == cap) {
                        cap *= 2;
                        Py_ssize_t *ni = (Py_ssize_t *)realloc(pi, sizeof(Py_ssize_t) * (size_t)cap);
                        if (ni) pi = ni;
                        Py_ssize_t *nj = (Py_ssize_t *)realloc(pj, sizeof(Py_ssize_t) * (size_t)cap);
                        if (nj) pj = nj;
                        if (!ni || !nj) {
                            PyErr_NoMemory();
                            goto done;
                        }
                    }
                    pi[np_] = i;
                    pj[np_] = j;
                    np_++;
                }
            }
        }
    }
    if (np_ == 0) goto ok;
    bad = (char *)calloc((size_t)np_, 1);
    test = (Py_ssize_t *)malloc(sizeof(Py_ssize_t) * (size_t)np_);
    can = (char *)malloc((size_t)n);
    lower = (char *)malloc((size_t)n);
    moving = (char *)malloc((size_t)n);
    if (!bad || !test || !can || !lower || !moving) {
        PyErr_NoMemory();
        goto done;
    }
    for (Py_ssize_t r = 0; r < n; r++) moving[r] = d[2 * r] != 0.0 || d[2 * r + 1] != 0.0;
    Py_ssize_t n_test = np_;
    for (Py_ssize_t q = 0; q < np_; q++) test[q] = q;
    for (long long turn = 0; turn < last * (long long)n + 1; turn++) {
        for (Py_ssize_t t = 0; t < n_test; t++) {
            Py_ssize_t q = test[t];
            bad[q] = (char)moves_conflict(p0, d, rr, level, scales, resolution, pi[q], pj[q]);
        }
        int any_bad = 0;
        for (Py_ssize_t q = 0; q < np_ && !any_bad; q++) any_bad = bad[q];
        if (!any_bad) break;
        for (Py_ssize_t r = 0; r < n; r++) {
            can[r] = level[r] < last && moving[r];
            lower[r] = 0;
        }
        for (Py_ssize_t q = 0; q < np_; q++) {
            if (!bad[q]) continue;
            Py_ssize_t bi = pi[q], bj = pj[q];
            /* j has the lower priority unless i is the unthreatened one of a mixed pair */
            int j_first = threatened[bi] || !threatened[bj];
            Py_ssize_t lose = j_first ? bj : bi, keep = j_first ? bi : bj;
            lower[can[lose] ? lose : keep] = 1;
        }
        int any_lower = 0;
        for (Py_ssize_t r = 0; r < n; r++) {
            lower[r] = lower[r] && can[r];
            if (lower[r]) {
                level[r]++;
                any_lower = 1;
            }
        }
        if (!any_lower) break;
        n_test = 0;
        for (Py_ssize_t q = 0; q < np_; q++)
            if (lower[pi[q]] || lower[pj[q]]) test[n_test++] = q;
    }
ok:
    result = Py_None;
    Py_INCREF(result);
done:
    free(pi);
    free(pj);
    free(test);
    free(bad);
    free(can);
    free(lower);
    free(moving);
    grid_free(&g);
    release(a, 6);
    return result;
}

/* tidy(pos, p1, goals, step_len, snap, out) -> None
 *
 * core.tidy_moves with the same arithmetic: each end p1 (n, 2) within snap of its goal is
 * the goal, a move shorter than 1e-12 is none, and one longer than step_len (n,) is scaled
 * to that length (step measured after the goal snap). pos, goals (n, 2); out (n, 2) written.
 */
static PyObject *tidy(PyObject *self, PyObject *args) {
    PyObject *o[5];
    static const char *names[5] = {"pos", "p1", "goals", "step_len", "out"};
    double snap;
    Arg a[5] = {{0}};
    PyObject *result = NULL;
    if (!PyArg_ParseTuple(args, "OOOOdO", &o[0], &o[1], &o[2], &o[3], &snap, &o[4])) return NULL;
    for (int q = 0; q < 5; q++)
        if (get(o[q], &a[q], q == 4, 'd', names[q]) < 0) goto done;
    Py_ssize_t n = a[3].buf.len / 8;
    if (a[0].buf.len != 16 * n || a[1].buf.len != 16 * n || a[2].buf.len != 16 * n || a[4].buf.len != 16 * n) {
        PyErr_SetString(PyExc_ValueError, "shapes must be pos, p1, goals, out (n, 2), step_len (n,)");
        goto done;
    }
    const double *pos = (const double *)a[0].buf.buf, *p1 = (const double *)a[1].buf.buf;
    const double *goals = (const double *)a[2].buf.buf, *step_len = (const double *)a[3].buf.buf;
    double *out = (double *)a[4].buf.buf;
    for (Py_ssize_t i = 0; i < n; i++) {
        double x = p1[2 * i], y = p1[2 * i + 1];
        double gx = x - goals[2 * i], gy = y - goals[2 * i + 1];
        if (sqrt(gx * gx + gy * gy) <= snap) {
            x = goals[2 * i];
            y = goals[2 * i + 1];
        }
        double px = pos[2 * i], py = pos[2 * i + 1];
        double sx = x - px, sy = y - py;
        double step = sqrt(sx * sx + sy * sy);
        if (step < 1e-12) {
            x = px;
            y = py;
        }
        if (step > step_len[i]) {
            double f = step_len[i] / step;
            x = px + (x - px) * f;
            y = py + (y - py) * f;
        }
        out[2 * i] = x;
        out[2 * i + 1] = y;
    }
    result = Py_None;
    Py_INCREF(result);
done:
    release(a, 5);
    return result;
}

static PyMethodDef methods[] = {
    {"solve", solve, METH_VARARGS, "ORCA's 2-D and 3-D linear programs for every robot"},
    {"knn", knn, METH_VARARGS, "each robot's nearest robots within a distance, ties flagged"},
    {"robot_halfplanes", robot_halfplanes, METH_VARARGS, "ORCA's robot-robot lines"},
    {"count_lines", count_lines, METH_VARARGS, "lines per robot: all, hard, hard and firm"},
    {"pack_lines", pack_lines, METH_VARARGS, "lines packed per robot, by tier in the given order"},
    {"robot_pairs", robot_pairs, METH_VARARGS, "levels of the moves after the pairwise move check"},
    {"tidy", tidy, METH_VARARGS, "end positions snapped to goals, dust dropped, steps capped"},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_orcalp",
    "ORCA linear programs (see swarmpath/control/orca/lp.py) and per-step kernels", -1, methods};

PyMODINIT_FUNC PyInit__orcalp(void) { return PyModule_Create(&module); }
