/*
 * One layer of the walker-evasion value on one square tile of the grid, compiled as
 * swarmpath.control.evasion._evasion (the Python side is walker.py; it holds the tiles).
 *
 * V_k(r, o) is the chance that a robot on cell r is hit by a random walker standing at
 * r + o (just after the walker's move) within the next k steps, when the robot plays best:
 *
 *   V_k(r, o) = min over robot moves a of  sum over walker moves d of  P(r + o, d) *
 *               ( 1                          if the walker's sweep d hits the robot at r + a,
 *                 V_{k-1}(r + a, o + d - a)  otherwise; 0 once |o + d - a| > R )
 *
 * where a ranges over the static moves of r (staying included) that do not enter or cross
 * the walker's footprint where it stands now (phase 2 of a step), and P(w, d) is the chance
 * that a walker on cell w steps d (uniform over the directions its footprint fits in; it
 * stays only when boxed in). V_0 = 0. Offsets are indexed (oy + R) * K + (ox + R), K = 2R + 1.
 *
 * Arguments of layer(): the tile's side t; R; the previous layer on the tile's cells and a
 * one-cell border, float32 (t + 2, t + 2, K, K); the robots' static moves on the tile, uint8
 * (t, t, 9) (index 0 set on free cells); the walker's step chances on the tile and R cells
 * around, float32 (t + 2R, t + 2R, 9); hit, uint8 (9, K + 2, K + 2): hit[d][cy][cx] when the
 * sweep d hits a robot resting at offset c - (R + 1) from the walker's start; forbid, uint8
 * (9, K, K): forbid[a][o] when robot move a crosses the footprint of a walker at offset o;
 * and the output, float32 (t, t, K, K).
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <stdint.h>

#define NMOVES 9

static const int MX[9] = {0, 1, 1, 0, -1, -1, -1, 0, 1};
static const int MY[9] = {0, 0, 1, 1, 1, 0, -1, -1, -1};

static int get(PyObject *o, Py_buffer *b, Py_ssize_t len, int writable, const char *what) {
    if (PyObject_GetBuffer(o, b, PyBUF_C_CONTIGUOUS | (writable ? PyBUF_WRITABLE : 0)) < 0)
        return -1;
    if (b->len != len) {
        PyErr_Format(PyExc_ValueError, "%s: expected %zd bytes, got %zd", what, len, b->len);
        PyBuffer_Release(b);
        return -1;
    }
    return 0;
}

static PyObject *layer(PyObject *self, PyObject *args) {
    int t, R;
    PyObject *po, *mo, *wo, *ho, *fo, *oo;
    if (!PyArg_ParseTuple(args, "iiOOOOOO", &t, &R, &po, &mo, &wo, &ho, &fo, &oo))
        return NULL;
    if (t < 1 || R < 1 || R > 64) {
        PyErr_SetString(PyExc_ValueError, "layer: tile side and R must be positive (R <= 64)");
        return NULL;
    }
    const int K = 2 * R + 1, KK = K * K, K2 = K + 2, tb = t + 2, tw = t + 2 * R;
    Py_buffer pb, mb, wb, hb, fb, ob;
    if (get(po, &pb, (Py_ssize_t)tb * tb * KK * 4, 0, "previous layer") < 0) return NULL;
    if (get(mo, &mb, (Py_ssize_t)t * t * NMOVES, 0, "moves") < 0) { PyBuffer_Release(&pb); return NULL; }
    if (get(wo, &wb, (Py_ssize_t)tw * tw * NMOVES * 4, 0, "walker chances") < 0) {
        PyBuffer_Release(&pb); PyBuffer_Release(&mb); return NULL;
    }
    if (get(ho, &hb, (Py_ssize_t)NMOVES * K2 * K2, 0, "hit") < 0) {
        PyBuffer_Release(&pb); PyBuffer_Release(&mb); PyBuffer_Release(&wb); return NULL;
    }
    if (get(fo, &fb, (Py_ssize_t)NMOVES * KK, 0, "forbid") < 0) {
        PyBuffer_Release(&pb); PyBuffer_Release(&mb); PyBuffer_Release(&wb); PyBuffer_Release(&hb); return NULL;
    }
    if (get(oo, &ob, (Py_ssize_t)t * t * KK * 4, 1, "out") < 0) {
        PyBuffer_Release(&pb); PyBuffer_Release(&mb); PyBuffer_Release(&wb); PyBuffer_Release(&hb);
        PyBuffer_Release(&fb); return NULL;
    }
    const float *prev = (const float *)pb.buf;
    const uint8_t *moves = (const uint8_t *)mb.buf;
    const float *walk = (const float *)wb.buf;
    const uint8_t *hit = (const uint8_t *)hb.buf;
    const uint8_t *forbid = (const uint8_t *)fb.buf;
    float *out = (float *)ob.buf;

    Py_BEGIN_ALLOW_THREADS
    for (int y = 0; y < t; y++) {
        for (int x = 0; x < t; x++) {
            const uint8_t *mv = moves + (y * t + x) * NMOVES;
            float *o_cell = out + (size_t)(y * t + x) * KK;
            if (!mv[0]) {                       /* not a free cell: never a robot's state */
                for (int k = 0; k < KK; k++) o_cell[k] = 0.0f;
                continue;
            }
            for (int oy = -R; oy <= R; oy++) {
                for (int ox = -R; ox <= R; ox++) {
                    const int oi = (oy + R) * K + (ox + R);
                    /* the walker's cell, in the chance block (offset R cells around the tile) */
                    const float *pw = walk + ((size_t)(y + oy + R) * tw + (x + ox + R)) * NMOVES;
                    float total = 0.0f;
                    for (int d = 0; d < NMOVES; d++) total += pw[d];
                    if (total == 0.0f || (ox == 0 && oy == 0)) {   /* no walker can stand there */
                        o_cell[oi] = 0.0f;
                        continue;
                    }
                    float best = 2.0f;
                    for (int a = 0; a < NMOVES; a++) {
                        if (!mv[a] || forbid[a * KK + oi]) continue;
                        const int ax = MX[a], ay = MY[a];
                        /* the robot after its move, relative to the walker's start */
                        const int cx = ax - ox + R + 1, cy = ay - oy + R + 1;
                        const float *vnext = prev + ((size_t)(y + 1 + ay) * tb + (x + 1 + ax)) * KK;
                        float acc = 0.0f;
                        for (int d = 0; d < NMOVES; d++) {
                            const float p = pw[d];
                            if (p == 0.0f) continue;
                            if (hit[(d * K2 + cy) * K2 + cx]) {
                                acc += p;
                                if (acc >= best) break;
                                continue;
                            }
                            const int nx = ox + MX[d] - ax, ny = oy + MY[d] - ay;
                            if (nx < -R || nx > R || ny < -R || ny > R) continue;
                            acc += p * vnext[(ny + R) * K + (nx + R)];
                            if (acc >= best) break;     /* terms are >= 0: this move cannot win */
                        }
                        if (acc < best) best = acc;
                        if (best == 0.0f) break;        /* nothing beats a sure escape */
                    }
                    o_cell[oi] = best > 1.0f ? 1.0f : best;
                }
            }
        }
    }
    Py_END_ALLOW_THREADS

    PyBuffer_Release(&pb); PyBuffer_Release(&mb); PyBuffer_Release(&wb); PyBuffer_Release(&hb);
    PyBuffer_Release(&fb); PyBuffer_Release(&ob);
    Py_RETURN_NONE;
}

static PyMethodDef methods[] = {
    {"layer", layer, METH_VARARGS, "One layer of the walker-evasion value on one tile (see the file's comment)."},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_evasion",
                                    "The walker-evasion value, one tile and layer at a time.", -1, methods};

PyMODINIT_FUNC PyInit__evasion(void) { return PyModule_Create(&module); }
