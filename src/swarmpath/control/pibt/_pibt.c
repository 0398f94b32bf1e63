/*
 * One step of Priority Inheritance with Backtracking (PIBT; Okumura, Machida, Defago and
 * Tamura, "Priority inheritance with backtracking for iterative multi-agent path finding",
 * Artificial Intelligence 310, 2022, Algorithm 1), compiled as swarmpath.control.pibt._pibt.
 *
 * The Python side (core.py) gives, per robot, its cell, the cost-to-goal of each of the 9
 * grid moves (move_rules.GRID_MOVES order: stay, E, NE, N, NW, W, SW, S, SE), which moves are
 * allowed (static map, reach, moving-obstacle danger), random tie-break keys, and the order
 * in which robots decide (decreasing priority). The robot-robot rule is the checker's: the
 * table of move_rules.grid_conflict_table, table[k][a][b] (25 x 9 x 9) = robot j starting at
 * NEAR_OFFSETS[k] from robot i conflicts when i makes move a and j move b.
 *
 * Reservation rule (PIBT's vertex and swap checks, generalised to the table):
 *  - a move of robot i must not conflict with the move of any robot already decided, and
 *  - must not conflict with an undecided robot staying where it is, except the robot that
 *    occupies i's target cell: that one must move first (priority inheritance, line 10 of
 *    Algorithm 1); if it cannot, i backtracks to its next candidate.
 * For point robots this is exactly PIBT (a staying robot only conflicts with a robot that
 * ends in its cell). For discs it also keeps robots out of moves that would brush a robot
 * that may still stay. A robot whose candidates all fail stays (line 15); by induction over
 * the recursion everything a failed call touched stays too, so the stay is conflict-free
 * unless a LaCAM constraint (a forced move, decided first) makes it impossible.
 *
 * Constraints (LaCAM's low-level nodes): forced[i] >= 0 fixes robot i's move; forced robots
 * are placed first, in the order given, and checked only against each other.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define NMOVES 9
#define NNEAR 25
#define PUSHED 1
#define STUCK 2

static const int MX[9] = {0, 1, 1, 0, -1, -1, -1, 0, 1};
static const int MY[9] = {0, 0, 1, 1, 1, 0, -1, -1, -1};

typedef struct {
    int w, h, n;
    const int32_t *pos;
    const double *dist;
    const uint8_t *allowed;
    const double *tie;
    const uint8_t *table;
    int32_t *occ;         /* w*h: robot standing on each cell now, -1 none */
    uint8_t *decided;
    int8_t *move;
    uint8_t *flags;
    long long calls;
    /* swap emulation (LaCAM3, Okumura 2024): the graph, goals and distance tables */
    int swap, diagonal, yield;
    const uint8_t *blocked;
    const int32_t *goal;
    const int64_t *slot;
    PyObject *tables;
    double (*query)(PyObject *, Py_ssize_t, int32_t);
    int error;
    long long swaps;
} Ctx;

typedef struct {
    double (*query)(PyObject *tables, Py_ssize_t slot, int32_t cell);
    PyTypeObject *type;
} LazyDistCAPI;
static LazyDistCAPI *CAPI = NULL;

static int32_t *OCC = NULL;
static Py_ssize_t OCC_CAP = 0;

static inline int near_index(int dx, int dy) { return (dy + 2) * 5 + (dx + 2); }

static inline const uint8_t *tab(const Ctx *c, int k, int a) { return c->table + ((Py_ssize_t)k * NMOVES + a) * NMOVES; }

/* robots within Chebyshev distance 2 of robot i (excluding i): indices and offset indices */
static int neighbours(const Ctx *c, int i, int32_t *who, int8_t *kk) {
    int x = c->pos[i] % c->w, y = c->pos[i] / c->w, m = 0;
    for (int dy = -2; dy <= 2; dy++) {
        int yy = y + dy;
        if (yy < 0 || yy >= c->h) continue;
        for (int dx = -2; dx <= 2; dx++) {
            int xx = x + dx;
            if (xx < 0 || xx >= c->w || (dx == 0 && dy == 0)) continue;
            int32_t j = c->occ[yy * c->w + xx];
            if (j >= 0 && j != i) { who[m] = j; kk[m] = (int8_t)near_index(dx, dy); m++; }
        }
    }
    return m;
}

/* does move a of robot i conflict with a decided neighbour, or (unless undecided_too is 0)
 * with an undecided neighbour other than `skip` staying put? */
static int clashes(const Ctx *c, int a, const int32_t *who, const int8_t *kk, int m, int skip, int undecided_too) {
    for (int r = 0; r < m; r++) {
        int j = who[r];
        const uint8_t *row = tab(c, kk[r], a);
        if (c->decided[j]) {
            if (row[c->move[j]]) return 1;
        } else if (undecided_too && j != skip) {
            if (row[0]) return 1;
        }
    }
    return 0;
}

/* ---------------------------------------------------------------- swap emulation
 * PIBT alone livelocks when two robots must pass each other in a corridor (each one's goal
 * lies behind the other). LaCAM3's PIBT (Okumura, "Engineering LaCAM*", AAMAS 2024) detects
 * it: robot i whose best cell is held by j (or whose neighbour k would have to back through
 * i's cell) reverses its candidate order (moves away) and pulls that robot into its cell,
 * when the corridor ahead has a branch where they can pass (is_swap_possible). */
static int graph_neighbours(const Ctx *c, int32_t v, int32_t *out) {
    int x = v % c->w, y = v / c->w, m = 0;
    for (int a = 1; a < NMOVES; a++) {
        int diag = MX[a] && MY[a];
        if (diag && !c->diagonal) continue;
        int nx = x + MX[a], ny = y + MY[a];
        if (nx < 0 || ny < 0 || nx >= c->w || ny >= c->h || c->blocked[ny * c->w + nx]) continue;
        if (diag && (c->blocked[y * c->w + nx] || c->blocked[ny * c->w + x])) continue;
        out[m++] = ny * c->w + nx;
    }
    return m;
}

static double D(Ctx *c, int i, int32_t v) {
    if (c->slot[i] >= 0 && c->query) {
        double d = c->query(c->tables, (Py_ssize_t)c->slot[i], v);
        if (d >= 0) return d;
        c->error = 1;
        return INFINITY;
    }
    /* no table (the robot is in its goal cell): the octile/Manhattan distance, exact for the
     * goal's neighbours and a lower bound beyond */
    int dx = abs(v % c->w - c->goal[i] % c->w), dy = abs(v / c->w - c->goal[i] / c->w);
    if (!c->diagonal) return (double)(dx + dy);
    int mn = dx < dy ? dx : dy, mx = dx < dy ? dy : dx;
    return (double)(mx - mn) + 1.41421356237309504880 * (double)mn;
}

/* neighbours of v that a pulled robot could step to: not the pusher's cell and not a dead
 * end where a robot sits on its goal; returns their count and one of them in *other */
static int pass_options(const Ctx *c, int32_t v, int32_t v_pusher, int32_t *other) {
    int32_t nb[8], nb2[8];
    int m = graph_neighbours(c, v, nb), n = m;
    for (int r = 0; r < m; r++) {
        int32_t u = nb[r];
        int32_t k = c->occ[u];
        if (u == v_pusher || (graph_neighbours(c, u, nb2) == 1 && k >= 0 && c->goal[k] == u)) n--;
        else *other = u;
    }
    return n;
}

static int swap_required(Ctx *c, int pusher, int puller, int32_t v_pusher, int32_t v_puller) {
    int32_t tmp = -1;
    long long budget = (long long)c->w * c->h;
    while (budget-- > 0 && D(c, pusher, v_puller) < D(c, pusher, v_pusher)) {
        int n = pass_options(c, v_puller, v_pusher, &tmp);
        if (n >= 2) return 0;   /* they can pass at v_puller */
        if (n <= 0) break;
        v_pusher = v_puller;
        v_puller = tmp;
    }
    return D(c, puller, v_pusher) < D(c, puller, v_puller) &&
           (D(c, pusher, v_pusher) == 0 || D(c, pusher, v_puller) < D(c, pusher, v_pusher));
}

static int swap_possible(Ctx *c, int32_t v_pusher_origin, int32_t v_puller_origin) {
    int32_t v_pusher = v_pusher_origin, v_puller = v_puller_origin, tmp = -1;
    long long budget = (long long)c->w * c->h;
    while (budget-- > 0 && v_puller != v_pusher_origin) {
        int n = pass_options(c, v_puller, v_pusher, &tmp);
        if (n >= 2) return 1;
        if (n <= 0) return 0;
        v_pusher = v_puller;
        v_puller = tmp;
    }
    return 0;
}

static int swap_agent(Ctx *c, int i, int32_t best) {
    int32_t here = c->pos[i];
    int32_t j = c->occ[best];
    if (best != here && j >= 0 && j != i && !c->decided[j] && swap_required(c, i, j, here, c->pos[j]) &&
        swap_possible(c, c->pos[j], here))
        return j;
    if (best != here) {
        int32_t nb[8];
        int m = graph_neighbours(c, here, nb);
        for (int r = 0; r < m; r++) {
            int32_t k = c->occ[nb[r]];
            if (k >= 0 && best != c->pos[k] && swap_required(c, k, i, here, best) && swap_possible(c, best, here))
                return k;
        }
    }
    return -1;
}

static int move_between(const Ctx *c, int32_t from, int32_t to) {
    int dx = to % c->w - from % c->w, dy = to / c->w - from / c->w;
    for (int a = 0; a < NMOVES; a++)
        if (MX[a] == dx && MY[a] == dy) return a;
    return -1;
}

static int pibt(Ctx *c, int i, int parent);

/* LaCAM3's pull: robot k steps into the cell robot i just left, if that is conflict-free */
static void pull(Ctx *c, int k, int i) {
    if (k < 0 || c->decided[k]) return;
    int a = move_between(c, c->pos[k], c->pos[i]);
    if (a <= 0 || !c->allowed[(Py_ssize_t)k * NMOVES + a]) return;
    int32_t who[24];
    int8_t kk[24];
    int m = neighbours(c, k, who, kk);
    if (clashes(c, a, who, kk, m, -1, 1)) return;
    c->decided[k] = 1;
    c->move[k] = (int8_t)a;
    c->flags[k] |= PUSHED;
    c->swaps++;
}

static int pibt(Ctx *c, int i, int parent) {
    int32_t who[24];
    int8_t kk[24];
    int m = neighbours(c, i, who, kk);
    c->calls++;
    if (parent >= 0) c->flags[i] |= PUSHED;
    /* candidates sorted by (cost to goal, occupied now, random key): insertion sort of <= 9 */
    int cand[NMOVES], nc = 0;
    int x = c->pos[i] % c->w, y = c->pos[i] / c->w;
    int occupied[NMOVES], ahead[NMOVES];
    /* a robot pushed off its goal has no way of its own: it leaves the pusher's way first */
    int yielding = c->yield && parent >= 0 && c->pos[i] == c->goal[i];
    double d_here = yielding ? D(c, parent, c->pos[i]) : 0.0;
    for (int a = 0; a < NMOVES; a++) {
        if (!c->allowed[(Py_ssize_t)i * NMOVES + a]) continue;
        int32_t u = (y + MY[a]) * c->w + (x + MX[a]);
        occupied[a] = a != 0 && c->occ[u] >= 0;
        ahead[a] = yielding && a != 0 && D(c, parent, u) < d_here;
        int p = nc++;
        const double *d = c->dist + (Py_ssize_t)i * NMOVES, *t = c->tie + (Py_ssize_t)i * NMOVES;
        while (p > 0) {
            int b = cand[p - 1];
            int before = ahead[a] < ahead[b] || (ahead[a] == ahead[b] && (d[a] < d[b] ||
                         (d[a] == d[b] && (occupied[a] < occupied[b] || (occupied[a] == occupied[b] && t[a] < t[b])))));
            if (!before) break;
            cand[p] = b;
            p--;
        }
        cand[p] = a;
    }
    int sw = -1;
    /* no swap manoeuvre for a robot that must leave its cell (a moving obstacle may reach it):
       the reversed order would try its least safe cells first */
    if (c->swap && nc > 0 && c->allowed[(Py_ssize_t)i * NMOVES]) {
        sw = swap_agent(c, i, (y + MY[cand[0]]) * c->w + (x + MX[cand[0]]));
        if (sw >= 0)
            for (int l = 0, r = nc - 1; l < r; l++, r--) { int t = cand[l]; cand[l] = cand[r]; cand[r] = t; }
    }
    for (int q = 0; q < nc; q++) {
        int a = cand[q];
        if (a == 0) {
            if (!clashes(c, 0, who, kk, m, -1, 0)) {
                c->decided[i] = 1; c->move[i] = 0;
                return 1;
            }
            continue;
        }
        int32_t u = (y + MY[a]) * c->w + (x + MX[a]);
        int32_t k = c->occ[u];
        int skip = (k >= 0 && !c->decided[k]) ? k : -1;
        if (clashes(c, a, who, kk, m, skip, 1)) continue;
        c->decided[i] = 1; c->move[i] = (int8_t)a;
        if (skip < 0 || pibt(c, skip, i)) {  /* free cell, or priority inheritance succeeded */
            if (q == 0 && sw >= 0) pull(c, sw, i);
            return 1;
        }
        c->decided[i] = 0;                /* backtracking: the occupant stays, try the next */
    }
    c->decided[i] = 1; c->move[i] = 0;
    c->flags[i] |= STUCK;
    return 0;
}

static int get(PyObject *o, Py_buffer *b, Py_ssize_t len, int writable, const char *what) {
    if (PyObject_GetBuffer(o, b, PyBUF_C_CONTIGUOUS | (writable ? PyBUF_WRITABLE : 0)) < 0) return -1;
    if (b->len != len) {
        PyErr_Format(PyExc_ValueError, "%s has %zd bytes, expected %zd", what, b->len, len);
        PyBuffer_Release(b);
        return -1;
    }
    return 0;
}

/* step(w, h, diagonal, blocked u8 (h*w), pos int32 (n), dist f64 (n,9), allowed u8 (n,9),
 *      tie f64 (n,9), order int32 (n), table u8 (25,9,9), forced int8 (n) [-1 = free],
 *      forced_order int32 (f), goals int32 (n), slots int64 (n) [-1 = no table],
 *      tables (LazyTables or None), swap (bool), yield (bool), out_move int8 (n), out_flags u8 (n))
 *   -> (ok, conflicting_pairs, calls, swaps)
 * ok = 0 when a forced move is impossible or clashes with an earlier forced move, or (with
 * forced moves) a robot has no conflict-free option; conflicting_pairs counts robot pairs whose
 * final moves conflict (0 without forced moves unless the start itself is in conflict). */
static PyObject *py_step(PyObject *self, PyObject *args) {
    int w, h, diagonal, swap, yield;
    PyObject *bo, *po, *dop, *ao, *to, *oo, *tbo, *fo, *foo, *go, *so, *tables, *mo, *flo;
    if (!PyArg_ParseTuple(args, "iipOOOOOOOOOOOOppOO", &w, &h, &diagonal, &bo, &po, &dop, &ao, &to, &oo, &tbo,
                          &fo, &foo, &go, &so, &tables, &swap, &yield, &mo, &flo))
        return NULL;
    Py_buffer bb, pb, db, ab, tb, ob, tbb, fb, fob, gb, sb, mb, flb;
    Py_buffer *all[13] = {&bb, &pb, &db, &ab, &tb, &ob, &tbb, &fb, &fob, &gb, &sb, &mb, &flb};
    int got = 0;
    PyObject *ret = NULL;
    Py_ssize_t cells = (Py_ssize_t)w * h;
    if (get(bo, &bb, cells, 0, "blocked") < 0) return NULL;
    got = 1;
    if (PyObject_GetBuffer(po, &pb, PyBUF_C_CONTIGUOUS) < 0) goto done; got++;
    Py_ssize_t n = pb.len / 4;
    if (get(dop, &db, n * 72, 0, "dist") < 0) goto done; got++;
    if (get(ao, &ab, n * 9, 0, "allowed") < 0) goto done; got++;
    if (get(to, &tb, n * 72, 0, "tie") < 0) goto done; got++;
    if (get(oo, &ob, n * 4, 0, "order") < 0) goto done; got++;
    if (get(tbo, &tbb, NNEAR * NMOVES * NMOVES, 0, "table") < 0) goto done; got++;
    if (get(fo, &fb, n, 0, "forced") < 0) goto done; got++;
    if (PyObject_GetBuffer(foo, &fob, PyBUF_C_CONTIGUOUS) < 0) goto done; got++;
    if (get(go, &gb, n * 4, 0, "goals") < 0) goto done; got++;
    if (get(so, &sb, n * 8, 0, "slots") < 0) goto done; got++;
    if (get(mo, &mb, n, 1, "out_move") < 0) goto done; got++;
    if (get(flo, &flb, n, 1, "out_flags") < 0) goto done; got++;
    double (*query)(PyObject *, Py_ssize_t, int32_t) = NULL;
    if (tables != Py_None) {
        if (!CAPI) {
            CAPI = (LazyDistCAPI *)PyCapsule_Import("swarmpath.search._lazydist._C_API", 0);
            if (!CAPI) goto done;
        }
        if (!PyObject_TypeCheck(tables, CAPI->type)) {
            PyErr_SetString(PyExc_TypeError, "tables must be a _lazydist.LazyTables or None");
            goto done;
        }
        query = CAPI->query;
    }
    if (cells > OCC_CAP) {
        free(OCC);
        OCC = (int32_t *)malloc((size_t)cells * sizeof(int32_t));
        if (!OCC) { OCC_CAP = 0; PyErr_NoMemory(); goto done; }
        for (Py_ssize_t v = 0; v < cells; v++) OCC[v] = -1;
        OCC_CAP = cells;
    }
    uint8_t *decided = (uint8_t *)calloc((size_t)(n ? n : 1), 1);
    if (!decided) { PyErr_NoMemory(); goto done; }
    Ctx c;
    memset(&c, 0, sizeof(c));
    c.w = w; c.h = h; c.n = (int)n;
    c.pos = (const int32_t *)pb.buf;
    c.dist = (const double *)db.buf;
    c.allowed = (const uint8_t *)ab.buf;
    c.tie = (const double *)tb.buf;
    c.table = (const uint8_t *)tbb.buf;
    c.occ = OCC;
    c.decided = decided;
    c.move = (int8_t *)mb.buf;
    c.flags = (uint8_t *)flb.buf;
    c.swap = swap; c.diagonal = diagonal; c.yield = yield;
    c.blocked = (const uint8_t *)bb.buf;
    c.goal = (const int32_t *)gb.buf;
    c.slot = (const int64_t *)sb.buf;
    c.tables = tables;
    c.query = query;
    const int32_t *order = (const int32_t *)ob.buf;
    const int8_t *forced = (const int8_t *)fb.buf;
    const int32_t *forder = (const int32_t *)fob.buf;
    Py_ssize_t nf = fob.len / 4;
    int ok = 1;
    for (Py_ssize_t i = 0; i < n; i++) {
        if (c.pos[i] < 0 || c.pos[i] >= cells || c.goal[i] < 0 || c.goal[i] >= cells) {
            PyErr_SetString(PyExc_ValueError, "a robot's cell or goal is outside the grid");
            free(decided);
            for (Py_ssize_t r = 0; r < i; r++) OCC[c.pos[r]] = -1;
            goto done;
        }
        OCC[c.pos[i]] = (int32_t)i;
        c.move[i] = 0;
        c.flags[i] = 0;
    }
    int32_t who[24];
    int8_t kk[24];
    /* LaCAM constraints first */
    for (Py_ssize_t q = 0; ok && q < nf; q++) {
        int i = forder[q];
        if (i < 0 || i >= n) { ok = 0; break; }
        int a = forced[i];
        if (a < 0 || a >= NMOVES || c.decided[i] || !c.allowed[(Py_ssize_t)i * NMOVES + a]) { ok = 0; break; }
        int m = neighbours(&c, i, who, kk);
        if (clashes(&c, a, who, kk, m, -1, 0)) { ok = 0; break; }
        c.decided[i] = 1;
        c.move[i] = (int8_t)a;
    }
    /* PIBT in priority order */
    for (Py_ssize_t q = 0; ok && q < n; q++) {
        int i = order[q];
        if (i < 0 || i >= n) { ok = 0; break; }
        if (c.decided[i]) continue;
        if (!pibt(&c, i, -1) && nf > 0) {
            int m = neighbours(&c, i, who, kk);
            if (clashes(&c, 0, who, kk, m, -1, 0)) ok = 0;
        }
    }
    /* final check of every pair against the table (a safety net; 0 for plain PIBT) */
    long long bad = 0;
    if (ok) {
        for (Py_ssize_t i = 0; i < n; i++) {
            int m = neighbours(&c, (int)i, who, kk);
            for (int r = 0; r < m; r++)
                if (who[r] > i && tab(&c, kk[r], c.move[i])[c.move[who[r]]]) bad++;
        }
    }
    for (Py_ssize_t i = 0; i < n; i++) OCC[c.pos[i]] = -1;
    free(decided);
    if (c.error) {
        PyErr_NoMemory();
        goto done;
    }
    ret = Py_BuildValue("iLLL", ok, bad, c.calls, c.swaps);
done:
    for (int b = 0; b < got; b++) PyBuffer_Release(all[b]);
    return ret;
}

static PyMethodDef methods[] = {
    {"step", py_step, METH_VARARGS, "One PIBT step: (ok, conflicting pairs, PIBT calls)."},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_pibt",
                                    "One step of PIBT on a grid with the checker's conflict table.", -1, methods};

PyMODINIT_FUNC PyInit__pibt(void) { return PyModule_Create(&module); }
