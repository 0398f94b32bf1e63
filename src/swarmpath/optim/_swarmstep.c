/*
 * One particle-swarm move in a single pass: velocity update (eq. 9-10 of Abbas & Abdulsahab),
 * velocity clamp, position update (eq. 11-12) and absorbing walls.
 *
 * The numpy kernels in swarmpath/optim/pso.py (pso_velocity_update, clamp_velocity,
 * pso_position_update) are the reference; this loop performs the same floating-point
 * operations in the same order, so both give bit-identical results (tested). It exists because
 * for the swarm sizes of the paper (8-100 particles) the sixteen numpy calls of one move cost
 * more in call overhead than in arithmetic.
 *
 * Compiled as swarmpath.optim._swarmstep; inputs arrive through the buffer protocol as
 * C-contiguous float64 arrays, so no numpy headers are needed.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

typedef struct {
    Py_buffer buf;
    int held;
} Arg;

static int get(PyObject *obj, Arg *a, int writable, const char *name) {
    int flags = PyBUF_C_CONTIGUOUS | PyBUF_FORMAT | (writable ? PyBUF_WRITABLE : 0);
    if (PyObject_GetBuffer(obj, &a->buf, flags) < 0) return -1;
    a->held = 1;
    const char *f = a->buf.format;
    if (a->buf.itemsize != 8 || f == NULL || !(f[0] == 'd' || (f[0] == '<' && f[1] == 'd') ||
                                                (f[0] == '=' && f[1] == 'd'))) {
        PyErr_Format(PyExc_TypeError, "%s must be a float64 array", name);
        return -1;
    }
    return 0;
}

static Py_ssize_t count(Arg *a) { return a->buf.len / 8; }

/* step(x, v, pbest, leaders, w, c1, c2, r1, r2, v_max, lower, upper) -> None
 *
 * x, v (n, d) are updated in place; pbest, r1, r2 are (n, d); leaders is (d,) (one global
 * best) or (n, d) (a leader per particle); w, c1, c2 have length 1 (shared) or n (per
 * particle); v_max, lower, upper have length d.
 */
static PyObject *step(PyObject *self, PyObject *args) {
    PyObject *o[12];
    static const char *names[12] = {"x", "v", "pbest", "leaders", "w", "c1", "c2",
                                    "r1", "r2", "v_max", "lower", "upper"};
    Arg a[12] = {{0}};
    PyObject *result = NULL;
    if (!PyArg_ParseTuple(args, "OOOOOOOOOOOO", &o[0], &o[1], &o[2], &o[3], &o[4], &o[5], &o[6],
                          &o[7], &o[8], &o[9], &o[10], &o[11]))
        return NULL;
    for (int k = 0; k < 12; k++)
        if (get(o[k], &a[k], k < 2, names[k]) < 0) goto done;

    Py_ssize_t d = count(&a[9]);
    Py_ssize_t nd = count(&a[0]);
    if (d == 0 || nd % d != 0 || count(&a[10]) != d || count(&a[11]) != d) {
        PyErr_SetString(PyExc_ValueError, "x must be (n, d) with v_max, lower, upper of length d");
        goto done;
    }
    Py_ssize_t n = nd / d;
    if (count(&a[1]) != nd || count(&a[2]) != nd || count(&a[7]) != nd || count(&a[8]) != nd) {
        PyErr_SetString(PyExc_ValueError, "v, pbest, r1 and r2 must have the shape of x");
        goto done;
    }
    Py_ssize_t nl = count(&a[3]);
    if (nl != d && nl != nd) {
        PyErr_SetString(PyExc_ValueError, "leaders must have length d or the shape of x");
        goto done;
    }
    for (int k = 4; k <= 6; k++) {
        if (count(&a[k]) != 1 && count(&a[k]) != n) {
            PyErr_Format(PyExc_ValueError, "%s must have length 1 or n", names[k]);
            goto done;
        }
    }
    double *x = (double *)a[0].buf.buf, *v = (double *)a[1].buf.buf;
    const double *p = (const double *)a[2].buf.buf, *g = (const double *)a[3].buf.buf;
    const double *W = (const double *)a[4].buf.buf, *C1 = (const double *)a[5].buf.buf;
    const double *C2 = (const double *)a[6].buf.buf;
    const double *r1 = (const double *)a[7].buf.buf, *r2 = (const double *)a[8].buf.buf;
    const double *vmax = (const double *)a[9].buf.buf, *lo = (const double *)a[10].buf.buf;
    const double *hi = (const double *)a[11].buf.buf;
    int per_w = count(&a[4]) == n && n > 1, per_c1 = count(&a[5]) == n && n > 1;
    int per_c2 = count(&a[6]) == n && n > 1, per_leader = nl == nd && n > 1;

    for (Py_ssize_t i = 0; i < n; i++) {
        double w = W[per_w ? i : 0], c1 = C1[per_c1 ? i : 0], c2 = C2[per_c2 ? i : 0];
        const double *gi = g + (per_leader ? i * d : 0);
        for (Py_ssize_t j = 0; j < d; j++) {
            Py_ssize_t k = i * d + j;
            /* the order of pso_velocity_update: ((p - x) r1) c1 + ((g - x) r2) c2, then + w v */
            double cognitive = ((p[k] - x[k]) * r1[k]) * c1;
            double social = ((gi[j] - x[k]) * r2[k]) * c2;
            double vk = (cognitive + social) + v[k] * w;
            double m = -vmax[j];
            vk = vk > m ? vk : m;             /* clamp_velocity: maximum, then minimum */
            vk = vk < vmax[j] ? vk : vmax[j];
            double moved = x[k] + vk;
            double clipped = moved > lo[j] ? moved : lo[j];
            clipped = clipped < hi[j] ? clipped : hi[j];
            if (clipped != moved) vk = 0.0;   /* absorbing wall */
            x[k] = clipped;
            v[k] = vk;
        }
    }
    Py_INCREF(Py_None);
    result = Py_None;
done:
    for (int k = 0; k < 12; k++)
        if (a[k].held) PyBuffer_Release(&a[k].buf);
    return result;
}

static PyMethodDef methods[] = {
    {"step", step, METH_VARARGS, "One PSO move in place: velocity, clamp, position, walls."},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_swarmstep",
                                    "One particle-swarm move in a single C pass.", -1, methods};

PyMODINIT_FUNC PyInit__swarmstep(void) { return PyModule_Create(&module); }
