/*
 * Lazy per-goal distance tables for swarmpath (compiled as swarmpath.search._lazydist).
 *
 * One table per goal cell answers "grid distance from this cell to the goal" by a resumable
 * backward A* from the goal (Reverse Resumable A*, Silver 2005): cells are closed in order of
 * f = g + h, where h is the octile (or Manhattan) distance to a *target* cell, the cell that
 * was last queried. A query of a closed cell is a lookup; a query of an open cell resumes the
 * search until that cell is closed. With a consistent heuristic every closed cell has its
 * exact g whatever target the open list was keyed to when it was popped, so the target may
 * change between queries: the open list is then re-keyed (rebuilt as a heap), but only when
 * the new target is more than REKEY_DISTANCE cells away from the current one, so a robot
 * walking along its path does not re-key at every step.
 *
 * Costs are kept exactly as integer pairs (a straight moves, b diagonal moves); the double
 * a + b * sqrt 2 is computed from the pair, so equal costs are equal doubles. Moves as in
 * _gridsearch.c: 4 orthogonal (cost 1) and, with diagonal=1, 4 diagonal moves (cost sqrt 2)
 * allowed only when both orthogonal neighbours are free (no corner cutting).
 *
 * Memory: a table stores what it expanded in 8x8 tiles (64 doubles and a closed bitmask),
 * allocated on first touch and indexed by a per-table directory of int32; a table that was
 * never queried holds no memory at all. remove() frees everything of a table.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define SQRT2 1.41421356237309504880
#define TILE_SHIFT 3
#define TILE_SIDE 8
#define TILE_CELLS 64
#define REKEY_DISTANCE 4

typedef struct {
    double g[TILE_CELLS];   /* tentative or final cost; INFINITY = not reached yet */
    uint64_t closed;        /* bit k: cell k of the tile is closed (g exact) */
} Tile;

typedef struct {
    double f;
    int32_t a, b;           /* straight and diagonal move counts of g */
    int32_t idx;
} Item;

typedef struct {
    int32_t goal;           /* flat cell index; -1 = unused slot */
    int32_t target;         /* heuristic target (flat index), -1 = none yet */
    int32_t *dir;           /* tile directory (lazily allocated): index into tiles or -1 */
    Tile *tiles;
    int32_t ntiles, captiles;
    Item *heap;
    Py_ssize_t hsize, hcap;
    int64_t expanded;
    int started, exhausted;
} Table;

typedef struct {
    PyObject_HEAD
    uint8_t *blocked;
    int w, h, diagonal, tw, th;
    Table *tables;
    Py_ssize_t ntables, cap;
    Py_ssize_t *free_slots;
    Py_ssize_t nfree;
    double *landmarks;      /* optional (cells, nlm) exact costs from landmark cells (ALT) */
    int nlm;
} LazyObject;

static const int DX[8] = {1, -1, 0, 0, 1, 1, -1, -1};
static const int DY[8] = {0, 0, 1, -1, 1, -1, 1, -1};
/* the 9 grid moves of swarmpath.world.move_rules.GRID_MOVES: stay, E, NE, N, NW, W, SW, S, SE */
static const int MX[9] = {0, 1, 1, 0, -1, -1, -1, 0, 1};
static const int MY[9] = {0, 0, 1, 1, 1, 0, -1, -1, -1};

static inline double pair_cost(int32_t a, int32_t b) { return (double)a + SQRT2 * (double)b; }

static inline int free_at(const LazyObject *L, int x, int y) {
    return x >= 0 && y >= 0 && x < L->w && y < L->h && !L->blocked[(Py_ssize_t)y * L->w + x];
}

static inline double octile_xy(const LazyObject *L, int x, int y, int tx, int ty) {
    int dx = abs(x - tx), dy = abs(y - ty);
    if (!L->diagonal) return (double)(dx + dy);
    int mn = dx < dy ? dx : dy, mx = dx < dy ? dy : dx;
    return (double)(mx - mn) + SQRT2 * (double)mn;
}

/* The heuristic toward target t: the octile (Manhattan) distance and, with landmarks, the
 * differential heuristic max_L |d(L, v) - d(L, t)| (Goldberg & Harrelson's ALT), both
 * consistent, so their maximum is. The landmark costs are sums of doubles (a few ulps off),
 * so a margin of 1e-9 relative keeps the bound below the true cost; distinct grid costs
 * a + b sqrt 2 of any realistic path differ by far more, so no cell is closed early. */
static inline double heuristic_xy(const LazyObject *L, int x, int y, int tx, int ty) {
    double h = octile_xy(L, x, y, tx, ty);
    if (L->nlm) {
        const double *a = L->landmarks + ((Py_ssize_t)y * L->w + x) * L->nlm;
        const double *b = L->landmarks + ((Py_ssize_t)ty * L->w + tx) * L->nlm;
        for (int k = 0; k < L->nlm; k++) {
            double d = a[k] - b[k];
            if (d < 0) d = -d;
            if (d > h && d < INFINITY) {
                double lb = d - 1e-9 * (1.0 + d);
                if (lb > h) h = lb;
            }
        }
    }
    return h;
}

static inline double heuristic(const LazyObject *L, int32_t v, int32_t t) {
    if (t < 0) return 0.0;
    return heuristic_xy(L, v % L->w, v / L->w, t % L->w, t / L->w);
}

/* ------------------------------------------------------------------ heap (4-ary, min f, then max g) */
static inline int item_less(const Item *x, const Item *y) {
    if (x->f != y->f) return x->f < y->f;
    return pair_cost(x->a, x->b) > pair_cost(y->a, y->b);
}

static void sift_down(Item *hp, Py_ssize_t n, Py_ssize_t i) {
    Item it = hp[i];
    while (1) {
        Py_ssize_t c = 4 * i + 1;
        if (c >= n) break;
        Py_ssize_t best = c, end = c + 4 < n ? c + 4 : n;
        for (Py_ssize_t k = c + 1; k < end; k++)
            if (item_less(&hp[k], &hp[best])) best = k;
        if (!item_less(&hp[best], &it)) break;
        hp[i] = hp[best];
        i = best;
    }
    hp[i] = it;
}

static int heap_push(Table *T, Item it) {
    if (T->hsize == T->hcap) {
        Py_ssize_t nc = T->hcap ? T->hcap + T->hcap / 2 + 16 : 64;
        Item *n = (Item *)realloc(T->heap, (size_t)nc * sizeof(Item));
        if (!n) return -1;
        T->heap = n;
        T->hcap = nc;
    }
    Py_ssize_t i = T->hsize++;
    while (i > 0) {
        Py_ssize_t p = (i - 1) >> 2;
        if (!item_less(&it, &T->heap[p])) break;
        T->heap[i] = T->heap[p];
        i = p;
    }
    T->heap[i] = it;
    return 0;
}

static Item heap_pop(Table *T) {
    Item top = T->heap[0];
    T->hsize--;
    if (T->hsize > 0) {
        T->heap[0] = T->heap[T->hsize];
        sift_down(T->heap, T->hsize, 0);
    }
    return top;
}

/* ------------------------------------------------------------------ tiles */
static inline Tile *tile_get(const LazyObject *L, const Table *T, int32_t v) {
    if (!T->dir) return NULL;
    int x = v % L->w, y = v / L->w;
    int32_t k = T->dir[(y >> TILE_SHIFT) * L->tw + (x >> TILE_SHIFT)];
    return k < 0 ? NULL : &T->tiles[k];
}

static inline int in_tile(const LazyObject *L, int32_t v) {
    int x = v % L->w, y = v / L->w;
    return ((y & (TILE_SIDE - 1)) << TILE_SHIFT) | (x & (TILE_SIDE - 1));
}

static Tile *tile_touch(const LazyObject *L, Table *T, int32_t v) {
    Py_ssize_t nt = (Py_ssize_t)L->tw * L->th;
    if (!T->dir) {
        T->dir = (int32_t *)malloc((size_t)nt * sizeof(int32_t));
        if (!T->dir) return NULL;
        for (Py_ssize_t i = 0; i < nt; i++) T->dir[i] = -1;
    }
    int x = v % L->w, y = v / L->w;
    int32_t *slot = &T->dir[(y >> TILE_SHIFT) * L->tw + (x >> TILE_SHIFT)];
    if (*slot < 0) {
        if (T->ntiles == T->captiles) {
            int32_t nc = T->captiles ? T->captiles + T->captiles / 2 + 4 : 8;
            Tile *n = (Tile *)realloc(T->tiles, (size_t)nc * sizeof(Tile));
            if (!n) return NULL;
            T->tiles = n;
            T->captiles = nc;
        }
        Tile *t = &T->tiles[T->ntiles];
        for (int i = 0; i < TILE_CELLS; i++) t->g[i] = INFINITY;
        t->closed = 0;
        *slot = T->ntiles++;
    }
    return &T->tiles[*slot];
}

static void table_release(Table *T) {
    free(T->dir); free(T->tiles); free(T->heap);
    memset(T, 0, sizeof(Table));
    T->goal = -1;
    T->target = -1;
}

/* ------------------------------------------------------------------ the search */
static void rekey(const LazyObject *L, Table *T, int32_t target) {
    T->target = target;
    for (Py_ssize_t i = 0; i < T->hsize; i++)
        T->heap[i].f = pair_cost(T->heap[i].a, T->heap[i].b) + heuristic(L, T->heap[i].idx, target);
    for (Py_ssize_t i = (T->hsize - 2) / 4; i >= 0; i--) sift_down(T->heap, T->hsize, i);
}

static inline Tile *tile_xy(const LazyObject *L, const Table *T, int x, int y) {
    int32_t k = T->dir[(y >> TILE_SHIFT) * L->tw + (x >> TILE_SHIFT)];
    return k < 0 ? NULL : &T->tiles[k];
}

static inline int in_tile_xy(int x, int y) {
    return ((y & (TILE_SIDE - 1)) << TILE_SHIFT) | (x & (TILE_SIDE - 1));
}

/* The exact cost from cell v to the table's goal (INFINITY when unreachable), or -1 on
 * memory exhaustion. v must be a valid cell index. */
static double table_query(LazyObject *L, Table *T, int32_t v) {
    if (L->blocked[v]) return INFINITY;
    Tile *t = tile_get(L, T, v);
    int k = in_tile(L, v);
    if (t && (t->closed >> k & 1)) return t->g[k];
    if (T->exhausted) return INFINITY;
    if (!T->started) {
        T->started = 1;
        T->target = v;
        Tile *tg = tile_touch(L, T, T->goal);
        if (!tg) return -1;
        tg->g[in_tile(L, T->goal)] = 0.0;
        Item it = {heuristic(L, T->goal, v), 0, 0, T->goal};
        if (heap_push(T, it) < 0) return -1;
    } else if (octile_xy(L, T->target % L->w, T->target / L->w, v % L->w, v / L->w) > REKEY_DISTANCE) {
        rekey(L, T, v);
    }
    const int W = L->w, H = L->h, nmoves = L->diagonal ? 8 : 4;
    const int tx = T->target % W, ty = T->target / W;
    const uint8_t *B = L->blocked;
    while (T->hsize > 0) {
        Item it = heap_pop(T);
        int32_t u = it.idx;
        int ux = u % W, uy = u / W;
        Tile *tu = tile_xy(L, T, ux, uy);
        int ku = in_tile_xy(ux, uy);
        if (tu->closed >> ku & 1) continue;
        double gu = pair_cost(it.a, it.b);
        if (gu > tu->g[ku]) continue; /* stale: a cheaper entry was pushed later */
        tu->closed |= (uint64_t)1 << ku;
        tu->g[ku] = gu;
        T->expanded++;
        /* free orthogonal neighbours first: the diagonals need both of theirs */
        int fe = ux + 1 < W && !B[u + 1], fw = ux > 0 && !B[u - 1];
        int fn = uy + 1 < H && !B[u + W], fs = uy > 0 && !B[u - W];
        for (int m = 0; m < nmoves; m++) {
            int dx = DX[m], dy = DY[m];
            int ok;
            switch (m) {
                case 0: ok = fe; break;
                case 1: ok = fw; break;
                case 2: ok = fn; break;
                case 3: ok = fs; break;
                default: {
                    int ox = dx > 0 ? fe : fw, oy = dy > 0 ? fn : fs;
                    ok = ox && oy && !B[u + dy * W + dx];
                }
            }
            if (!ok) continue;
            int vx = ux + dx, vy = uy + dy;
            int32_t w = u + dy * W + dx;
            Tile *tw = tile_xy(L, T, vx, vy);
            if (!tw) {
                tw = tile_touch(L, T, w);
                if (!tw) return -1;
            }
            int kw = in_tile_xy(vx, vy);
            if (tw->closed >> kw & 1) continue;
            int32_t na = it.a + (m < 4), nb = it.b + (m >= 4);
            double nd = pair_cost(na, nb);
            if (nd < tw->g[kw]) {
                tw->g[kw] = nd;
                Item ni = {nd + heuristic_xy(L, vx, vy, tx, ty), na, nb, w};
                if (heap_push(T, ni) < 0) return -1;
            }
        }
        if (u == v) return gu;
    }
    T->exhausted = 1;
    free(T->heap);
    T->heap = NULL;
    T->hsize = T->hcap = 0;
    return INFINITY;
}

/* ------------------------------------------------------------------ Python type */
static Table *get_table(LazyObject *L, Py_ssize_t slot) {
    if (slot < 0 || slot >= L->ntables || L->tables[slot].goal < 0) {
        PyErr_Format(PyExc_KeyError, "no distance table %zd", slot);
        return NULL;
    }
    return &L->tables[slot];
}

static void Lazy_dealloc(LazyObject *L) {
    for (Py_ssize_t i = 0; i < L->ntables; i++) table_release(&L->tables[i]);
    free(L->tables);
    free(L->free_slots);
    free(L->blocked);
    free(L->landmarks);
    Py_TYPE(L)->tp_free((PyObject *)L);
}

static int Lazy_init(LazyObject *L, PyObject *args, PyObject *kwds) {
    PyObject *grid, *lm = Py_None;
    int w, h, diagonal;
    if (!PyArg_ParseTuple(args, "Oiip|O", &grid, &w, &h, &diagonal, &lm)) return -1;
    if (w <= 0 || h <= 0 || (Py_ssize_t)w * h > 0x7fffffffLL) {
        PyErr_SetString(PyExc_ValueError, "grid size must be positive and below 2**31 cells");
        return -1;
    }
    Py_buffer view;
    if (PyObject_GetBuffer(grid, &view, PyBUF_C_CONTIGUOUS) < 0) return -1;
    if (view.len != (Py_ssize_t)w * h) {
        PyErr_SetString(PyExc_ValueError, "blocked must be a C-contiguous 1-byte array of height*width");
        PyBuffer_Release(&view);
        return -1;
    }
    free(L->blocked);
    L->blocked = (uint8_t *)malloc((size_t)view.len);
    if (!L->blocked) { PyBuffer_Release(&view); PyErr_NoMemory(); return -1; }
    for (Py_ssize_t i = 0; i < view.len; i++) L->blocked[i] = ((uint8_t *)view.buf)[i] != 0;
    PyBuffer_Release(&view);
    L->w = w; L->h = h; L->diagonal = diagonal;
    free(L->landmarks);
    L->landmarks = NULL;
    L->nlm = 0;
    if (lm != Py_None) {
        Py_buffer lb;
        if (PyObject_GetBuffer(lm, &lb, PyBUF_C_CONTIGUOUS) < 0) return -1;
        Py_ssize_t per = (Py_ssize_t)w * h * (Py_ssize_t)sizeof(double);
        if (lb.len % per != 0 || lb.len / per > 64) {
            PyErr_SetString(PyExc_ValueError, "landmarks must be float64 of shape (height*width, k), k <= 64");
            PyBuffer_Release(&lb);
            return -1;
        }
        L->nlm = (int)(lb.len / per);
        L->landmarks = (double *)malloc((size_t)lb.len ? (size_t)lb.len : 1);
        if (!L->landmarks) { PyBuffer_Release(&lb); PyErr_NoMemory(); return -1; }
        memcpy(L->landmarks, lb.buf, (size_t)lb.len);
        PyBuffer_Release(&lb);
    }
    L->tw = (w + TILE_SIDE - 1) / TILE_SIDE;
    L->th = (h + TILE_SIDE - 1) / TILE_SIDE;
    return 0;
}

static PyObject *Lazy_add(LazyObject *L, PyObject *args) {
    int x, y;
    if (!PyArg_ParseTuple(args, "ii", &x, &y)) return NULL;
    if (!free_at(L, x, y)) {
        PyErr_Format(PyExc_ValueError, "goal (%d, %d) is outside the grid or blocked", x, y);
        return NULL;
    }
    Py_ssize_t slot;
    if (L->nfree > 0) {
        slot = L->free_slots[--L->nfree];
    } else {
        if (L->ntables == L->cap) {
            Py_ssize_t nc = L->cap ? L->cap * 2 : 64;
            Table *n = (Table *)realloc(L->tables, (size_t)nc * sizeof(Table));
            if (!n) return PyErr_NoMemory();
            L->tables = n;
            Py_ssize_t *f = (Py_ssize_t *)realloc(L->free_slots, (size_t)nc * sizeof(Py_ssize_t));
            if (!f) return PyErr_NoMemory();
            L->free_slots = f;
            L->cap = nc;
        }
        slot = L->ntables++;
    }
    Table *T = &L->tables[slot];
    memset(T, 0, sizeof(Table));
    T->goal = y * L->w + x;
    T->target = -1;
    return PyLong_FromSsize_t(slot);
}

static PyObject *Lazy_remove(LazyObject *L, PyObject *args) {
    Py_ssize_t slot;
    if (!PyArg_ParseTuple(args, "n", &slot)) return NULL;
    Table *T = get_table(L, slot);
    if (!T) return NULL;
    table_release(T);
    L->free_slots[L->nfree++] = slot;
    Py_RETURN_NONE;
}

static PyObject *Lazy_get(LazyObject *L, PyObject *args) {
    Py_ssize_t slot;
    int x, y;
    if (!PyArg_ParseTuple(args, "nii", &slot, &x, &y)) return NULL;
    Table *T = get_table(L, slot);
    if (!T) return NULL;
    if (x < 0 || y < 0 || x >= L->w || y >= L->h) return PyFloat_FromDouble(INFINITY);
    double d = table_query(L, T, y * L->w + x);
    if (d < 0) return PyErr_NoMemory();
    return PyFloat_FromDouble(d);
}

static int get_buf(PyObject *obj, Py_buffer *view, Py_ssize_t itemsize, int writable, const char *what) {
    int flags = PyBUF_C_CONTIGUOUS | (writable ? PyBUF_WRITABLE : 0);
    if (PyObject_GetBuffer(obj, view, flags) < 0) return -1;
    if (view->len % itemsize != 0) {
        PyErr_Format(PyExc_ValueError, "%s has the wrong item size", what);
        PyBuffer_Release(view);
        return -1;
    }
    return 0;
}

/* get_many(slots int64 (k,), cells int64 (k,) flat indices (-1: outside), out float64 (k,)) */
static PyObject *Lazy_get_many(LazyObject *L, PyObject *args) {
    PyObject *so, *co, *oo;
    if (!PyArg_ParseTuple(args, "OOO", &so, &co, &oo)) return NULL;
    Py_buffer sb, cb, ob;
    if (get_buf(so, &sb, 8, 0, "slots") < 0) return NULL;
    if (get_buf(co, &cb, 8, 0, "cells") < 0) { PyBuffer_Release(&sb); return NULL; }
    if (get_buf(oo, &ob, 8, 1, "out") < 0) { PyBuffer_Release(&sb); PyBuffer_Release(&cb); return NULL; }
    Py_ssize_t k = sb.len / 8;
    PyObject *ret = Py_None;
    if (cb.len / 8 != k || ob.len / 8 != k) {
        PyErr_SetString(PyExc_ValueError, "slots, cells and out must have the same length");
        ret = NULL;
    }
    const int64_t *slots = (const int64_t *)sb.buf, *cells = (const int64_t *)cb.buf;
    double *out = (double *)ob.buf;
    Py_ssize_t ncell = (Py_ssize_t)L->w * L->h;
    for (Py_ssize_t i = 0; ret && i < k; i++) {
        Table *T = get_table(L, slots[i]);
        if (!T) { ret = NULL; break; }
        if (cells[i] < 0 || cells[i] >= ncell) { out[i] = INFINITY; continue; }
        double d = table_query(L, T, (int32_t)cells[i]);
        if (d < 0) { PyErr_NoMemory(); ret = NULL; break; }
        out[i] = d;
    }
    PyBuffer_Release(&sb); PyBuffer_Release(&cb); PyBuffer_Release(&ob);
    if (ret) Py_INCREF(ret);
    return ret;
}

/* neighbour_costs(slots int64 (k,), cells int64 (k,) flat, out float64 (k, 9)): the cost to
 * goal of the cell each of the 9 grid moves reaches from cells[i]; NaN where the move itself
 * is impossible (outside, blocked, corner cutting, or a diagonal in 4-connected mode). */
static PyObject *Lazy_neighbour_costs(LazyObject *L, PyObject *args) {
    PyObject *so, *co, *oo;
    if (!PyArg_ParseTuple(args, "OOO", &so, &co, &oo)) return NULL;
    Py_buffer sb, cb, ob;
    if (get_buf(so, &sb, 8, 0, "slots") < 0) return NULL;
    if (get_buf(co, &cb, 8, 0, "cells") < 0) { PyBuffer_Release(&sb); return NULL; }
    if (get_buf(oo, &ob, 8, 1, "out") < 0) { PyBuffer_Release(&sb); PyBuffer_Release(&cb); return NULL; }
    Py_ssize_t k = sb.len / 8;
    PyObject *ret = Py_None;
    if (cb.len / 8 != k || ob.len / 8 != 9 * k) {
        PyErr_SetString(PyExc_ValueError, "slots and cells must have length k and out 9k");
        ret = NULL;
    }
    const int64_t *slots = (const int64_t *)sb.buf, *cells = (const int64_t *)cb.buf;
    double *out = (double *)ob.buf;
    Py_ssize_t ncell = (Py_ssize_t)L->w * L->h;
    for (Py_ssize_t i = 0; ret && i < k; i++) {
        Table *T = get_table(L, slots[i]);
        if (!T) { ret = NULL; break; }
        double *row = out + 9 * i;
        if (cells[i] < 0 || cells[i] >= ncell) {
            for (int m = 0; m < 9; m++) row[m] = NAN;
            continue;
        }
        int x = (int)(cells[i] % L->w), y = (int)(cells[i] / L->w);
        for (int m = 0; m < 9; m++) {
            int nx = x + MX[m], ny = y + MY[m];
            int diag = MX[m] != 0 && MY[m] != 0;
            if ((diag && !L->diagonal) || !free_at(L, nx, ny) ||
                (diag && (!free_at(L, nx, y) || !free_at(L, x, ny)))) {
                row[m] = (m == 0) ? INFINITY : NAN; /* a blocked own cell: stay is still a move */
                continue;
            }
            double d = table_query(L, T, ny * L->w + nx);
            if (d < 0) { PyErr_NoMemory(); ret = NULL; break; }
            row[m] = d;
        }
    }
    PyBuffer_Release(&sb); PyBuffer_Release(&cb); PyBuffer_Release(&ob);
    if (ret) Py_INCREF(ret);
    return ret;
}

static PyObject *Lazy_expanded(LazyObject *L, PyObject *args) {
    Py_ssize_t slot;
    if (!PyArg_ParseTuple(args, "n", &slot)) return NULL;
    Table *T = get_table(L, slot);
    if (!T) return NULL;
    return PyLong_FromLongLong((long long)T->expanded);
}

static PyObject *Lazy_is_closed(LazyObject *L, PyObject *args) {
    Py_ssize_t slot;
    int x, y;
    if (!PyArg_ParseTuple(args, "nii", &slot, &x, &y)) return NULL;
    Table *T = get_table(L, slot);
    if (!T) return NULL;
    if (x < 0 || y < 0 || x >= L->w || y >= L->h) Py_RETURN_FALSE;
    int32_t v = y * L->w + x;
    Tile *t = tile_get(L, T, v);
    if (t && (t->closed >> in_tile(L, v) & 1)) Py_RETURN_TRUE;
    Py_RETURN_FALSE;
}

/* memory_bytes() -> bytes held by all tables (directories, tiles, open lists) */
static PyObject *Lazy_memory_bytes(LazyObject *L, PyObject *noargs) {
    long long total = (long long)L->cap * (long long)(sizeof(Table) + sizeof(Py_ssize_t));
    for (Py_ssize_t i = 0; i < L->ntables; i++) {
        Table *T = &L->tables[i];
        if (T->goal < 0) continue;
        if (T->dir) total += (long long)L->tw * L->th * (long long)sizeof(int32_t);
        total += (long long)T->captiles * (long long)sizeof(Tile);
        total += (long long)T->hcap * (long long)sizeof(Item);
    }
    return PyLong_FromLongLong(total);
}

static PyObject *Lazy_live(LazyObject *L, PyObject *noargs) {
    return PyLong_FromSsize_t(L->ntables - L->nfree);
}

static PyMethodDef Lazy_methods[] = {
    {"add", (PyCFunction)Lazy_add, METH_VARARGS, "add(x, y) -> slot: a new empty table for goal (x, y)."},
    {"remove", (PyCFunction)Lazy_remove, METH_VARARGS, "remove(slot): free a table."},
    {"get", (PyCFunction)Lazy_get, METH_VARARGS, "get(slot, x, y) -> cost to the goal (inf: unreachable)."},
    {"get_many", (PyCFunction)Lazy_get_many, METH_VARARGS, "get_many(slots, flat_cells, out)."},
    {"neighbour_costs", (PyCFunction)Lazy_neighbour_costs, METH_VARARGS,
     "neighbour_costs(slots, flat_cells, out (k, 9)): costs of the 9 grid moves' cells."},
    {"expanded", (PyCFunction)Lazy_expanded, METH_VARARGS, "expanded(slot) -> cells closed so far."},
    {"is_closed", (PyCFunction)Lazy_is_closed, METH_VARARGS, "is_closed(slot, x, y) -> bool."},
    {"memory_bytes", (PyCFunction)Lazy_memory_bytes, METH_NOARGS, "bytes held by all tables."},
    {"live", (PyCFunction)Lazy_live, METH_NOARGS, "number of tables not removed."},
    {NULL, NULL, 0, NULL},
};

static PyTypeObject LazyType = {
    PyVarObject_HEAD_INIT(NULL, 0)
    .tp_name = "swarmpath.search._lazydist.LazyTables",
    .tp_basicsize = sizeof(LazyObject),
    .tp_dealloc = (destructor)Lazy_dealloc,
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "LazyTables(blocked_uint8, width, height, diagonal): resumable backward A* tables.",
    .tp_methods = Lazy_methods,
    .tp_init = (initproc)Lazy_init,
    .tp_new = PyType_GenericNew,
};

/* C API for other extensions (swarmpath.control.pibt._pibt reads distances of arbitrary cells
 * while it emulates swaps): the capsule "swarmpath.search._lazydist._C_API" points to this. */
typedef struct {
    double (*query)(PyObject *tables, Py_ssize_t slot, int32_t cell); /* -1: no memory, -2: bad slot */
    PyTypeObject *type;
} LazyDistCAPI;

static double capi_query(PyObject *obj, Py_ssize_t slot, int32_t cell) {
    LazyObject *L = (LazyObject *)obj;
    if (slot < 0 || slot >= L->ntables || L->tables[slot].goal < 0) return -2;
    if (cell < 0 || cell >= (Py_ssize_t)L->w * L->h) return INFINITY;
    return table_query(L, &L->tables[slot], cell);
}

static LazyDistCAPI CAPI = {capi_query, NULL};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_lazydist",
                                    "Lazy per-goal grid distance tables (Reverse Resumable A*).", -1, NULL};

PyMODINIT_FUNC PyInit__lazydist(void) {
    if (PyType_Ready(&LazyType) < 0) return NULL;
    PyObject *m = PyModule_Create(&module);
    if (!m) return NULL;
    CAPI.type = &LazyType;
    PyObject *cap = PyCapsule_New(&CAPI, "swarmpath.search._lazydist._C_API", NULL);
    if (!cap || PyModule_AddObject(m, "_C_API", cap) < 0) {
        Py_XDECREF(cap);
        Py_DECREF(m);
        return NULL;
    }
    Py_INCREF(&LazyType);
    if (PyModule_AddObject(m, "LazyTables", (PyObject *)&LazyType) < 0) {
        Py_DECREF(&LazyType);
        Py_DECREF(m);
        return NULL;
    }
    return m;
}
