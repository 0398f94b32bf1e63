/*
 * Grid shortest paths for swarmpath: A* and Dijkstra distance fields on an occupancy raster.
 *
 * Cells are indexed y * width + x. Moves: 4 orthogonal (cost 1) and, with diagonal=1, 4
 * diagonal (cost sqrt 2) allowed only when both orthogonal neighbours are free (no corner
 * cutting), exactly as the MovingAI benchmarks define octile paths. Costs are in cells.
 *
 * This file is compiled as the extension module swarmpath.search._gridsearch; the Python
 * wrappers in swarmpath/search/astar.py and distance_field.py give it a typed interface.
 * Inputs arrive through the buffer protocol (numpy arrays), so no numpy headers are needed.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define SQRT2 1.41421356237309504880

typedef struct {
    double f;
    float g;     /* only breaks ties between equal f; optimality never depends on it */
    int32_t idx;
} HeapItem;

typedef struct {
    HeapItem *items;
    Py_ssize_t size;
    Py_ssize_t cap;
} Heap;

static int heap_less(const HeapItem *a, const HeapItem *b) {
    if (a->f != b->f) return a->f < b->f;
    return a->g > b->g; /* among equal f, prefer the deeper node: fewer expansions */
}

/* A 4-ary min-heap: shallower than a binary heap, and a node's children share a cache line. */
static int heap_push(Heap *h, double f, double g, int32_t idx) {
    if (h->size == h->cap) {
        Py_ssize_t ncap = h->cap ? h->cap * 2 : 4096;
        HeapItem *n = (HeapItem *)realloc(h->items, (size_t)ncap * sizeof(HeapItem));
        if (!n) return -1;
        h->items = n;
        h->cap = ncap;
    }
    Py_ssize_t i = h->size++;
    HeapItem it = {f, (float)g, idx};
    while (i > 0) {
        Py_ssize_t p = (i - 1) >> 2;
        if (!heap_less(&it, &h->items[p])) break;
        h->items[i] = h->items[p];
        i = p;
    }
    h->items[i] = it;
    return 0;
}

static HeapItem heap_pop(Heap *h) {
    HeapItem top = h->items[0];
    HeapItem last = h->items[--h->size];
    Py_ssize_t i = 0, n = h->size;
    while (1) {
        Py_ssize_t c = 4 * i + 1;
        if (c >= n) break;
        Py_ssize_t best = c;
        Py_ssize_t end = c + 4 < n ? c + 4 : n;
        for (Py_ssize_t k = c + 1; k < end; k++)
            if (heap_less(&h->items[k], &h->items[best])) best = k;
        if (!heap_less(&h->items[best], &last)) break;
        h->items[i] = h->items[best];
        i = best;
    }
    if (n > 0) h->items[i] = last;
    return top;
}

/* A bucket queue for A* with a consistent heuristic: every open f lies in
 * [f_min, f_min + 2 * max_step_cost], so f / BQ_WIDTH indexes a circular array of buckets;
 * only the lowest bucket is kept as an exact (f, then larger g) heap, so pops are exact and
 * cheap. Buckets are reused between calls. */
#define BQ_WIDTH (1.0 / 64.0)
#define BQ_COUNT 256 /* covers 4 cells of f, more than 2 * sqrt 2 */

typedef struct {
    Heap bucket[BQ_COUNT];
    Heap current;
    Heap far;          /* items beyond the bucket window (long jumps of JPS), an exact heap */
    int64_t current_key;
    Py_ssize_t pending; /* items in the buckets */
} BucketQueue;

static BucketQueue BQ;

static void bq_clear(BucketQueue *q, double f0) {
    for (int i = 0; i < BQ_COUNT; i++) q->bucket[i].size = 0;
    q->current.size = 0;
    q->far.size = 0;
    q->current_key = (int64_t)floor(f0 / BQ_WIDTH);
    q->pending = 0;
}

static int bq_push(BucketQueue *q, double f, double g, int32_t idx) {
    int64_t key = (int64_t)floor(f / BQ_WIDTH);
    if (key <= q->current_key) return heap_push(&q->current, f, g, idx);
    if (key - q->current_key >= BQ_COUNT) return heap_push(&q->far, f, g, idx);
    Heap *b = &q->bucket[key % BQ_COUNT];
    if (b->size == b->cap) {
        Py_ssize_t ncap = b->cap ? b->cap * 2 : 256;
        HeapItem *n = (HeapItem *)realloc(b->items, (size_t)ncap * sizeof(HeapItem));
        if (!n) return -1;
        b->items = n;
        b->cap = ncap;
    }
    HeapItem it = {f, (float)g, idx};
    b->items[b->size++] = it;
    q->pending++;
    return 0;
}

/* Pop the exact minimum; returns 0 when empty. */
static int bq_pop(BucketQueue *q, HeapItem *out) {
    while (q->current.size == 0) {
        if (q->pending == 0) {
            if (q->far.size == 0) return 0;
            /* jump the window to the nearest far item */
            int64_t k = (int64_t)floor(q->far.items[0].f / BQ_WIDTH);
            q->current_key = k > q->current_key ? k - 1 : q->current_key;
        }
        q->current_key++;
        /* far items that now fall inside the current bucket join the current heap */
        while (q->far.size > 0 && (int64_t)floor(q->far.items[0].f / BQ_WIDTH) <= q->current_key) {
            HeapItem it = heap_pop(&q->far);
            if (heap_push(&q->current, it.f, it.g, it.idx) < 0) return -1;
        }
        Heap *b = &q->bucket[q->current_key % BQ_COUNT];
        for (Py_ssize_t i = 0; i < b->size; i++)
            if (heap_push(&q->current, b->items[i].f, b->items[i].g, b->items[i].idx) < 0) return -1;
        q->pending -= b->size;
        b->size = 0;
    }
    *out = heap_pop(&q->current);
    return 1;
}

static const int DX[8] = {1, -1, 0, 0, 1, 1, -1, -1};
static const int DY[8] = {0, 0, 1, -1, 1, -1, 1, -1};

static inline int is_free(const uint8_t *blocked, int w, int h, int x, int y) {
    return x >= 0 && y >= 0 && x < w && y < h && !blocked[(Py_ssize_t)y * w + x];
}

static inline double octile(int x, int y, int gx, int gy, int diagonal) {
    int dx = abs(x - gx), dy = abs(y - gy);
    if (!diagonal) return (double)(dx + dy);
    int mn = dx < dy ? dx : dy;
    int mx = dx < dy ? dy : dx;
    return (double)(mx - mn) + SQRT2 * (double)mn;
}

static int get_grid(PyObject *obj, Py_buffer *view, int w, int h) {
    if (PyObject_GetBuffer(obj, view, PyBUF_C_CONTIGUOUS | PyBUF_FORMAT) < 0) return -1;
    if (view->itemsize != 1 || view->len != (Py_ssize_t)w * h) {
        PyErr_SetString(PyExc_ValueError, "blocked must be a C-contiguous 1-byte array of height*width");
        PyBuffer_Release(view);
        return -1;
    }
    return 0;
}

/* Search buffers reused between calls (the GIL is held during a search, so one set is
 * enough). stamp[v] == 2*gen: v has a tentative g this search; 2*gen+1: v is closed. This
 * avoids clearing or page-faulting megabytes of fresh memory on every query. */
static double *A_g = NULL;
static int32_t *A_parent = NULL;
static uint32_t *A_stamp = NULL;
static Py_ssize_t A_cap = 0;
static uint32_t A_gen = 0;

static int ensure_buffers(Py_ssize_t n) {
    if (n > A_cap) {
        free(A_g); free(A_parent); free(A_stamp);
        A_g = (double *)malloc((size_t)n * sizeof(double));
        A_parent = (int32_t *)malloc((size_t)n * sizeof(int32_t));
        A_stamp = (uint32_t *)calloc((size_t)n, sizeof(uint32_t));
        if (!A_g || !A_parent || !A_stamp) {
            free(A_g); free(A_parent); free(A_stamp);
            A_g = NULL; A_parent = NULL; A_stamp = NULL; A_cap = 0;
            return -1;
        }
        A_cap = n;
        A_gen = 0;
    }
    if (A_gen >= 0x7ffffffe) {
        memset(A_stamp, 0, (size_t)A_cap * sizeof(uint32_t));
        A_gen = 0;
    }
    A_gen++;
    return 0;
}

/* Seed a search at ``start`` (f = f0) in the shared buffers; returns -1 when out of memory. */
static int start_search(int32_t start, double f0) {
    A_g[start] = 0.0;
    A_parent[start] = -1;
    A_stamp[start] = 2 * A_gen;
    bq_clear(&BQ, f0);
    return bq_push(&BQ, f0, 0.0, start) < 0 ? -1 : 0;
}

/* astar(blocked, width, height, sx, sy, gx, gy, diagonal) -> (cost, path_bytes | None, expansions) */
static PyObject *py_astar(PyObject *self, PyObject *args) {
    PyObject *grid_obj;
    int w, h, sx, sy, gx, gy, diagonal;
    if (!PyArg_ParseTuple(args, "Oiiiiiip", &grid_obj, &w, &h, &sx, &sy, &gx, &gy, &diagonal)) return NULL;
    Py_buffer view;
    if (get_grid(grid_obj, &view, w, h) < 0) return NULL;
    const uint8_t *blocked = (const uint8_t *)view.buf;
    if (!is_free(blocked, w, h, sx, sy) || !is_free(blocked, w, h, gx, gy)) {
        PyBuffer_Release(&view);
        return Py_BuildValue("(dOn)", INFINITY, Py_None, (Py_ssize_t)0);
    }
    Py_ssize_t n = (Py_ssize_t)w * h;
    if (ensure_buffers(n) < 0) {
        PyBuffer_Release(&view);
        return PyErr_NoMemory();
    }
    double *g = A_g;
    int32_t *parent = A_parent;
    uint32_t *stamp = A_stamp;
    const uint32_t seen = 2 * A_gen, closed = 2 * A_gen + 1;
    int32_t start = sy * w + sx, goal = gy * w + gx;
    Py_ssize_t expansions = 0;
    int found = 0, oom = start_search(start, octile(sx, sy, gx, gy, diagonal)) < 0;
    int nmoves = diagonal ? 8 : 4;
    HeapItem it;
    int popped;
    while (!oom && (popped = bq_pop(&BQ, &it)) != 0) {
        if (popped < 0) { oom = 1; break; }
        int32_t u = it.idx;
        if (stamp[u] == closed) continue;
        stamp[u] = closed;
        expansions++;
        if (u == goal) { found = 1; break; }
        int ux = u % w, uy = u / w;
        double gu = g[u];
        for (int k = 0; k < nmoves; k++) {
            int vx = ux + DX[k], vy = uy + DY[k];
            if (!is_free(blocked, w, h, vx, vy)) continue;
            double step = 1.0;
            if (k >= 4) {
                if (blocked[(Py_ssize_t)uy * w + vx] || blocked[(Py_ssize_t)vy * w + ux]) continue;
                step = SQRT2;
            }
            int32_t v = vy * w + vx;
            uint32_t sv = stamp[v];
            if (sv == closed) continue;
            double ng = gu + step;
            if (sv != seen || ng < g[v]) {
                g[v] = ng;
                parent[v] = u;
                stamp[v] = seen;
                if (bq_push(&BQ, ng + octile(vx, vy, gx, gy, diagonal), ng, v) < 0) { oom = 1; break; }
            }
        }
    }
    PyObject *result = NULL;
    if (oom) {
        PyErr_NoMemory();
    } else if (!found) {
        result = Py_BuildValue("(dOn)", INFINITY, Py_None, expansions);
    } else {
        Py_ssize_t len = 0;
        for (int32_t v = goal; v != -1; v = parent[v]) len++;
        PyObject *bytes = PyBytes_FromStringAndSize(NULL, len * 2 * (Py_ssize_t)sizeof(int32_t));
        if (bytes) {
            int32_t *out = (int32_t *)PyBytes_AS_STRING(bytes);
            Py_ssize_t i = len - 1;
            for (int32_t v = goal; v != -1; v = parent[v], i--) {
                out[2 * i] = v % w;
                out[2 * i + 1] = v / w;
            }
            result = Py_BuildValue("(dNn)", g[goal], bytes, expansions);
        }
    }
    PyBuffer_Release(&view);
    return result;
}

/* ---------------------------------------------------------------------------------------
 * Jump point search for 8-connected octile grids without corner cutting (Harabor & Grastien's
 * JPS with the "diagonal only when both orthogonal neighbours are free" rule). It expands the
 * same optimal costs as A* but only at jump points: cells where the straight-line scan meets a
 * forced neighbour. Diagonal moves have no forced neighbours under this rule; a diagonal scan
 * stops where one of its two straight scans finds a jump point.
 * ------------------------------------------------------------------------------------- */
/* The scans read a copy of the grid with a one-cell blocked border (stride w + 2), so they
 * need no bounds checks: pb[y * stride + x] is valid for -1 <= x <= w, -1 <= y <= h. */
static uint8_t *J_pad = NULL;
static Py_ssize_t J_pad_cap = 0;
#define W(x, y) (!pb[(Py_ssize_t)(y) * stride + (x)])

static int jump_straight(const uint8_t *pb, Py_ssize_t stride, int x, int y, int dx, int dy, int gx, int gy,
                         int *jx, int *jy) {
    while (1) {
        if (!W(x, y)) return 0;
        if (x == gx && y == gy) break;
        if (dx) {
            if ((W(x, y - 1) && !W(x - dx, y - 1)) || (W(x, y + 1) && !W(x - dx, y + 1))) break;
        } else {
            if ((W(x - 1, y) && !W(x - 1, y - dy)) || (W(x + 1, y) && !W(x + 1, y - dy))) break;
        }
        x += dx;
        y += dy;
    }
    *jx = x;
    *jy = y;
    return 1;
}

/* Scan from (x, y), entered by the move (dx, dy) (already known to be a legal move if (x, y) is
 * free), to the next jump point. */
static int jump(const uint8_t *pb, Py_ssize_t stride, int x, int y, int dx, int dy, int gx, int gy, int *jx, int *jy) {
    if (!(dx && dy)) return jump_straight(pb, stride, x, y, dx, dy, gx, gy, jx, jy);
    int tx, ty;
    while (1) {
        if (!W(x, y)) return 0;
        if ((x == gx && y == gy) || jump_straight(pb, stride, x + dx, y, dx, 0, gx, gy, &tx, &ty) ||
            jump_straight(pb, stride, x, y + dy, 0, dy, gx, gy, &tx, &ty)) {
            *jx = x;
            *jy = y;
            return 1;
        }
        if (!(W(x + dx, y) && W(x, y + dy))) return 0; /* the next diagonal step would cut a corner */
        x += dx;
        y += dy;
    }
}

/* Directions worth scanning from u, given the direction (dx, dy) it was reached by
 * ((0, 0) for the start): natural and forced neighbours only. */
static int pruned_directions(const uint8_t *pb, Py_ssize_t stride, int x, int y, int dx, int dy, int out[8][2]) {
    int n = 0;
#define ADD(a, b) do { out[n][0] = (a); out[n][1] = (b); n++; } while (0)
    if (!dx && !dy) {
        for (int k = 0; k < 8; k++) {
            int vx = x + DX[k], vy = y + DY[k];
            if (!W(vx, vy)) continue;
            if (k >= 4 && (!W(vx, y) || !W(x, vy))) continue;
            ADD(DX[k], DY[k]);
        }
    } else if (dx && dy) {
        int a = W(x + dx, y), b = W(x, y + dy);
        if (a) ADD(dx, 0);
        if (b) ADD(0, dy);
        if (a && b && W(x + dx, y + dy)) ADD(dx, dy);
    } else if (dx) {
        int next = W(x + dx, y), up = W(x, y + 1), down = W(x, y - 1);
        if (next) {
            ADD(dx, 0);
            if (up && W(x + dx, y + 1)) ADD(dx, 1);
            if (down && W(x + dx, y - 1)) ADD(dx, -1);
        }
        if (up) ADD(0, 1);
        if (down) ADD(0, -1);
    } else {
        int next = W(x, y + dy), right = W(x + 1, y), left = W(x - 1, y);
        if (next) {
            ADD(0, dy);
            if (right && W(x + 1, y + dy)) ADD(1, dy);
            if (left && W(x - 1, y + dy)) ADD(-1, dy);
        }
        if (right) ADD(1, 0);
        if (left) ADD(-1, 0);
    }
#undef ADD
    return n;
}

static inline int sgn(int v) { return (v > 0) - (v < 0); }

/* jps(blocked, width, height, sx, sy, gx, gy) -> (cost, path_bytes | None, expansions) */
static PyObject *py_jps(PyObject *self, PyObject *args) {
    PyObject *grid_obj;
    int w, h, sx, sy, gx, gy;
    if (!PyArg_ParseTuple(args, "Oiiiiii", &grid_obj, &w, &h, &sx, &sy, &gx, &gy)) return NULL;
    Py_buffer view;
    if (get_grid(grid_obj, &view, w, h) < 0) return NULL;
    const uint8_t *blocked = (const uint8_t *)view.buf;
    if (!is_free(blocked, w, h, sx, sy) || !is_free(blocked, w, h, gx, gy)) {
        PyBuffer_Release(&view);
        return Py_BuildValue("(dOn)", INFINITY, Py_None, (Py_ssize_t)0);
    }
    Py_ssize_t stride = (Py_ssize_t)w + 2, padded = stride * ((Py_ssize_t)h + 2);
    if (padded > J_pad_cap) {
        free(J_pad);
        J_pad = (uint8_t *)malloc((size_t)padded);
        J_pad_cap = J_pad ? padded : 0;
    }
    if (!J_pad || ensure_buffers((Py_ssize_t)w * h) < 0) {
        PyBuffer_Release(&view);
        return PyErr_NoMemory();
    }
    memset(J_pad, 1, (size_t)stride);
    memset(J_pad + stride * ((Py_ssize_t)h + 1), 1, (size_t)stride);
    for (int y = 0; y < h; y++) {
        uint8_t *row = J_pad + stride * ((Py_ssize_t)y + 1);
        row[0] = 1;
        row[stride - 1] = 1;
        memcpy(row + 1, blocked + (Py_ssize_t)y * w, (size_t)w); /* numpy bools are 0/1 bytes */
    }
    const uint8_t *pb = J_pad + stride + 1;
    double *g = A_g;
    int32_t *parent = A_parent;
    uint32_t *stamp = A_stamp;
    const uint32_t seen = 2 * A_gen, closed = 2 * A_gen + 1;
    int32_t start = sy * w + sx, goal = gy * w + gx;
    Py_ssize_t expansions = 0;
    int found = 0, oom = start_search(start, octile(sx, sy, gx, gy, 1)) < 0;
    int dirs[8][2];
    HeapItem it;
    int popped;
    while (!oom && (popped = bq_pop(&BQ, &it)) != 0) {
        if (popped < 0) { oom = 1; break; }
        int32_t u = it.idx;
        if (stamp[u] == closed) continue;
        stamp[u] = closed;
        expansions++;
        if (u == goal) { found = 1; break; }
        int ux = u % w, uy = u / w, pdx = 0, pdy = 0;
        if (parent[u] >= 0) {
            pdx = sgn(ux - parent[u] % w);
            pdy = sgn(uy - parent[u] / w);
        }
        int nd = pruned_directions(pb, stride, ux, uy, pdx, pdy, dirs);
        for (int k = 0; k < nd; k++) {
            int jx, jy;
            if (!jump(pb, stride, ux + dirs[k][0], uy + dirs[k][1], dirs[k][0], dirs[k][1], gx, gy, &jx, &jy))
                continue;
            int32_t v = jy * w + jx;
            if (stamp[v] == closed) continue;
            double ng = g[u] + octile(ux, uy, jx, jy, 1);
            if (stamp[v] != seen || ng < g[v]) {
                g[v] = ng;
                parent[v] = u;
                stamp[v] = seen;
                if (bq_push(&BQ, ng + octile(jx, jy, gx, gy, 1), ng, v) < 0) { oom = 1; break; }
            }
        }
    }
    PyObject *result = NULL;
    if (oom) {
        PyErr_NoMemory();
    } else if (!found) {
        result = Py_BuildValue("(dOn)", INFINITY, Py_None, expansions);
    } else {
        /* Expand the jump points into every cell of the straight or diagonal runs between them. */
        Py_ssize_t len = 1;
        for (int32_t v = goal; parent[v] != -1; v = parent[v]) {
            int ax = v % w, ay = v / w, bx = parent[v] % w, by = parent[v] / w;
            len += abs(ax - bx) > abs(ay - by) ? abs(ax - bx) : abs(ay - by);
        }
        PyObject *bytes = PyBytes_FromStringAndSize(NULL, len * 2 * (Py_ssize_t)sizeof(int32_t));
        if (bytes) {
            int32_t *out = (int32_t *)PyBytes_AS_STRING(bytes);
            Py_ssize_t i = len - 1;
            out[2 * i] = gx;
            out[2 * i + 1] = gy;
            for (int32_t v = goal; parent[v] != -1; v = parent[v]) {
                int x = v % w, y = v / w, bx = parent[v] % w, by = parent[v] / w;
                int sxd = sgn(bx - x), syd = sgn(by - y);
                while (x != bx || y != by) {
                    x += sxd;
                    y += syd;
                    i--;
                    out[2 * i] = x;
                    out[2 * i + 1] = y;
                }
            }
            result = Py_BuildValue("(dNn)", g[goal], bytes, expansions);
        }
    }
    PyBuffer_Release(&view);
    return result;
}
#undef W

/* distance_field(blocked, width, height, sources_int64_xy, out_float64, diagonal) -> expansions
 * Dijkstra from all sources at once; out receives the cost to the nearest source, inf where
 * unreachable. The moves are symmetric, so this is also the cost FROM each cell TO a source. */
static PyObject *py_distance_field(PyObject *self, PyObject *args) {
    PyObject *grid_obj, *src_obj, *out_obj;
    int w, h, diagonal;
    if (!PyArg_ParseTuple(args, "OiiOOp", &grid_obj, &w, &h, &src_obj, &out_obj, &diagonal)) return NULL;
    Py_buffer view, src, out;
    if (get_grid(grid_obj, &view, w, h) < 0) return NULL;
    if (PyObject_GetBuffer(src_obj, &src, PyBUF_C_CONTIGUOUS) < 0) { PyBuffer_Release(&view); return NULL; }
    if (PyObject_GetBuffer(out_obj, &out, PyBUF_C_CONTIGUOUS | PyBUF_WRITABLE) < 0) {
        PyBuffer_Release(&view); PyBuffer_Release(&src); return NULL;
    }
    Py_ssize_t n = (Py_ssize_t)w * h;
    if (out.len != n * (Py_ssize_t)sizeof(double) || src.len % (2 * (Py_ssize_t)sizeof(int64_t)) != 0) {
        PyErr_SetString(PyExc_ValueError, "out must be float64 of height*width; sources int64 pairs");
        PyBuffer_Release(&view); PyBuffer_Release(&src); PyBuffer_Release(&out);
        return NULL;
    }
    const uint8_t *blocked = (const uint8_t *)view.buf;
    const int64_t *sources = (const int64_t *)src.buf;
    Py_ssize_t nsrc = src.len / (2 * (Py_ssize_t)sizeof(int64_t));
    double *dist = (double *)out.buf;
    Heap heap = {NULL, 0, 0};
    Py_ssize_t expansions = 0;
    int oom = 0;
    Py_BEGIN_ALLOW_THREADS
    for (Py_ssize_t i = 0; i < n; i++) dist[i] = INFINITY;
    for (Py_ssize_t s = 0; !oom && s < nsrc; s++) {
        int x = (int)sources[2 * s], y = (int)sources[2 * s + 1];
        if (!is_free(blocked, w, h, x, y)) continue;
        int32_t v = y * w + x;
        dist[v] = 0.0;
        if (heap_push(&heap, 0.0, 0.0, v) < 0) oom = 1;
    }
    int nmoves = diagonal ? 8 : 4;
    while (!oom && heap.size > 0) {
        HeapItem it = heap_pop(&heap);
        int32_t u = it.idx;
        if (it.f > dist[u]) continue; /* stale entry: a shorter distance was found later */
        expansions++;
        int ux = u % w, uy = u / w;
        for (int k = 0; k < nmoves; k++) {
            int vx = ux + DX[k], vy = uy + DY[k];
            if (!is_free(blocked, w, h, vx, vy)) continue;
            double step = 1.0;
            if (k >= 4) {
                if (!is_free(blocked, w, h, vx, uy) || !is_free(blocked, w, h, ux, vy)) continue;
                step = SQRT2;
            }
            int32_t v = vy * w + vx;
            double nd = dist[u] + step;
            if (nd < dist[v]) {
                dist[v] = nd;
                if (heap_push(&heap, nd, 0.0, v) < 0) { oom = 1; break; }
            }
        }
    }
    Py_END_ALLOW_THREADS
    free(heap.items);
    PyBuffer_Release(&view); PyBuffer_Release(&src); PyBuffer_Release(&out);
    if (oom) return PyErr_NoMemory();
    return PyLong_FromSsize_t(expansions);
}

static PyMethodDef methods[] = {
    {"astar", py_astar, METH_VARARGS, "A* on an occupancy raster: (cost, path bytes or None, expansions)."},
    {"jps", py_jps, METH_VARARGS, "Jump point search (8-connected, no corner cutting): same result shape as astar."},
    {"distance_field", py_distance_field, METH_VARARGS, "Multi-source Dijkstra into a float64 buffer."},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_gridsearch",
                                    "Grid A* and distance fields (octile, no corner cutting).", -1, methods};

PyMODINIT_FUNC PyInit__gridsearch(void) { return PyModule_Create(&module); }
