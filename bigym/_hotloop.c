/* The env's per-step work that Python's call overhead made cost more than physics on the
 * lighter tasks: validating and applying an action, the physics steps of one control step
 * (with the servo-target ramp below 500 Hz), the instability check, the proprioception
 * gather and the reduction of the contacts to the registered geom sets' label pairs.
 *
 * Every function does exactly the floating-point operations of the Python code it stands
 * for (bigym/action_modes.py, bigym/env.py, bigym/observations.py, bigym/contacts.py), in
 * the same order, so both paths give the same bits; the build turns off fused multiply-add
 * contraction for that. Python keeps the fallback and the error messages: a return code
 * says what happened. MuJoCo is called through the addresses of mj_step1 and mj_step2
 * that Python looked up in the library the mujoco bindings loaded, on the bindings' own
 * mjModel and mjData, so no MuJoCo header or link is needed here.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

typedef void (*step_fn)(const void *model, void *data);

/* ------------------------------------------------------------------ control step */

typedef struct {
    step_fn step1, step2;
    const void *model;
    void *data;
    double *ctrl;           /* the robot's slice of data.ctrl */
    Py_ssize_t nu;
    Py_ssize_t substeps;
    int absolute;           /* every entry absolute: ctrl = action */
    const double *keep;     /* 1 for delta entries, 0 for absolute ones */
    const double *ctrl_low, *ctrl_high;
    const double *check_low, *check_high;      /* float64 bounds for float64 actions */
    const float *check_low32, *check_high32;   /* the same bounds for float32 actions */
    const uint8_t *held;    /* entries held (not ramped) over a control step, or NULL */
    const double *fractions;                   /* k / substeps, k = 1 .. substeps - 1 */
    const char *warnings;   /* data.warning[0].number */
    Py_ssize_t warning_stride, warning_count;
    double *start, *end;    /* scratch, nu each */
} ControlPlan;

enum { STEP_OK = 0, STEP_INVALID = 1, STEP_UNSUPPORTED = 2, STEP_UNSTABLE = 3 };

static void free_capsule(PyObject *capsule) {
    free(PyCapsule_GetPointer(capsule, PyCapsule_GetName(capsule)));
}

static int as_address(PyObject *obj, void **out) {
    *out = PyLong_AsVoidPtr(obj);
    return (*out == NULL && PyErr_Occurred()) ? -1 : 0;
}

static PyObject *make_control_plan(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    (void)self;
    if (nargs != 21) {
        PyErr_SetString(PyExc_TypeError, "make_control_plan takes 21 arguments");
        return NULL;
    }
    ControlPlan *plan = calloc(1, sizeof(ControlPlan));
    if (plan == NULL) return PyErr_NoMemory();
    void *p[21];
    for (Py_ssize_t i = 0; i < nargs; i++) {
        if (i == 5 || i == 6 || i == 7 || i == 18 || i == 19) continue; /* plain integers */
        if (as_address(args[i], &p[i]) < 0) { free(plan); return NULL; }
    }
    plan->step1 = (step_fn)p[0];
    plan->step2 = (step_fn)p[1];
    plan->model = p[2];
    plan->data = p[3];
    plan->ctrl = p[4];
    plan->nu = PyLong_AsSsize_t(args[5]);
    plan->substeps = PyLong_AsSsize_t(args[6]);
    plan->absolute = PyObject_IsTrue(args[7]);
    plan->keep = p[8];
    plan->ctrl_low = p[9];
    plan->ctrl_high = p[10];
    plan->check_low = p[11];
    plan->check_high = p[12];
    plan->check_low32 = p[13];
    plan->check_high32 = p[14];
    plan->held = p[15];
    plan->fractions = p[16];
    plan->warnings = p[17];
    plan->warning_stride = PyLong_AsSsize_t(args[18]);
    plan->warning_count = PyLong_AsSsize_t(args[19]);
    plan->start = p[20];
    plan->end = plan->start + plan->nu;
    if (PyErr_Occurred() || plan->step1 == NULL || plan->step2 == NULL || plan->nu <= 0 || plan->substeps < 1) {
        free(plan);
        if (!PyErr_Occurred()) PyErr_SetString(PyExc_ValueError, "invalid control plan");
        return NULL;
    }
    PyObject *capsule = PyCapsule_New(plan, "bigym.control_plan", free_capsule);
    if (capsule == NULL) free(plan);
    return capsule;
}

/* np.clip's ufunc for doubles: max then min, NaN kept. */
static inline double clip(double x, double low, double high) {
    x = isnan(x) ? x : (x > low ? x : low);
    return isnan(x) ? x : (x < high ? x : high);
}

static int read_action(const ControlPlan *plan, PyObject *action, double *out) {
    Py_buffer view;
    if (PyObject_GetBuffer(action, &view, PyBUF_C_CONTIGUOUS | PyBUF_FORMAT) < 0) {
        PyErr_Clear();
        return STEP_UNSUPPORTED;
    }
    int code = STEP_UNSUPPORTED;
    const char *format = view.format ? view.format : "B";
    if (view.ndim == 1 && view.shape[0] == plan->nu && format[1] == '\0') {
        Py_ssize_t n = plan->nu;
        code = STEP_OK;
        if (format[0] == 'f') {
            const float *a = view.buf;
            for (Py_ssize_t i = 0; i < n; i++) {
                if (!(a[i] >= plan->check_low32[i] && a[i] <= plan->check_high32[i])) code = STEP_INVALID;
                out[i] = (double)a[i];
            }
        } else if (format[0] == 'd') {
            const double *a = view.buf;
            for (Py_ssize_t i = 0; i < n; i++) {
                if (!(a[i] >= plan->check_low[i] && a[i] <= plan->check_high[i])) code = STEP_INVALID;
                out[i] = a[i];
            }
        } else {
            code = STEP_UNSUPPORTED;
        }
    }
    PyBuffer_Release(&view);
    return code;
}

/* control_step(plan, action) -> code: validate, apply, run the control step's physics. */
static PyObject *control_step(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    (void)self;
    if (nargs != 2) {
        PyErr_SetString(PyExc_TypeError, "control_step takes (plan, action)");
        return NULL;
    }
    ControlPlan *plan = PyCapsule_GetPointer(args[0], "bigym.control_plan");
    if (plan == NULL) return NULL;
    Py_ssize_t n = plan->nu;
    double *ctrl = plan->ctrl, *start = plan->start, *end = plan->end;
    /* the action, widened to float64, goes into `end` until it is applied */
    int code = read_action(plan, args[1], end);
    if (code != STEP_OK) return PyLong_FromLong(code);

    Py_BEGIN_ALLOW_THREADS
    int ramp = plan->substeps > 1;
    if (ramp) memcpy(start, ctrl, (size_t)n * sizeof(double));
    for (Py_ssize_t i = 0; i < n; i++) {
        double value = end[i];
        if (!plan->absolute) {
            double kept = ctrl[i] * plan->keep[i];
            value = kept + value;
        }
        ctrl[i] = clip(value, plan->ctrl_low[i], plan->ctrl_high[i]);
    }
    if (ramp) {
        memcpy(end, ctrl, (size_t)n * sizeof(double));
        if (plan->held != NULL) {
            for (Py_ssize_t i = 0; i < n; i++)
                if (plan->held[i]) start[i] = end[i];
        }
        for (Py_ssize_t k = 0; k < plan->substeps - 1; k++) {
            double fraction = plan->fractions[k];
            for (Py_ssize_t i = 0; i < n; i++) {
                double part = fraction * (end[i] - start[i]);
                ctrl[i] = start[i] + part;
            }
            plan->step2(plan->model, plan->data);
            plan->step1(plan->model, plan->data);
        }
        memcpy(ctrl, end, (size_t)n * sizeof(double));
    }
    plan->step2(plan->model, plan->data);
    plan->step1(plan->model, plan->data);
    for (Py_ssize_t w = 0; w < plan->warning_count; w++) {
        if (*(const int *)(plan->warnings + w * plan->warning_stride)) code = STEP_UNSTABLE;
    }
    Py_END_ALLOW_THREADS
    return PyLong_FromLong(code);
}

/* ------------------------------------------------------------------ proprioception */

typedef struct {
    const double *span;     /* data.qpos .. data.ctrl as one float64 run */
    const int64_t *index;   /* what each row reads, then the four gripper driver angles */
    Py_ssize_t rows;
    Py_ssize_t left_row, right_row;
    double scale;           /* gripper opening per driver angle */
    const int64_t *constant_rows;
    const double *constant_values;
    Py_ssize_t constant_count;
} GatherPlan;

static PyObject *make_gather_plan(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    (void)self;
    if (nargs != 9) {
        PyErr_SetString(PyExc_TypeError, "make_gather_plan takes 9 arguments");
        return NULL;
    }
    GatherPlan *plan = calloc(1, sizeof(GatherPlan));
    if (plan == NULL) return PyErr_NoMemory();
    void *span, *index, *rows_at, *values_at;
    if (as_address(args[0], &span) < 0 || as_address(args[1], &index) < 0 || as_address(args[6], &rows_at) < 0 ||
        as_address(args[7], &values_at) < 0) {
        free(plan);
        return NULL;
    }
    plan->span = span;
    plan->index = index;
    plan->rows = PyLong_AsSsize_t(args[2]);
    plan->left_row = PyLong_AsSsize_t(args[3]);
    plan->right_row = PyLong_AsSsize_t(args[4]);
    plan->scale = PyFloat_AsDouble(args[5]);
    plan->constant_rows = rows_at;
    plan->constant_values = values_at;
    plan->constant_count = PyLong_AsSsize_t(args[8]);
    if (PyErr_Occurred()) {
        free(plan);
        return NULL;
    }
    PyObject *capsule = PyCapsule_New(plan, "bigym.gather_plan", free_capsule);
    if (capsule == NULL) free(plan);
    return capsule;
}

static inline double unit_clip(double x) { return x <= 0.0 ? 0.0 : (x > 1.0 ? 1.0 : x); }

/* gather(plan, out): fill the float32 array `out` (rows long) with the proprioception. */
static PyObject *gather(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    (void)self;
    if (nargs != 2) {
        PyErr_SetString(PyExc_TypeError, "gather takes (plan, out)");
        return NULL;
    }
    GatherPlan *plan = PyCapsule_GetPointer(args[0], "bigym.gather_plan");
    if (plan == NULL) return NULL;
    Py_buffer view;
    if (PyObject_GetBuffer(args[1], &view, PyBUF_C_CONTIGUOUS | PyBUF_WRITABLE | PyBUF_FORMAT) < 0) return NULL;
    if (view.ndim != 1 || view.shape[0] != plan->rows || strcmp(view.format ? view.format : "B", "f") != 0) {
        PyBuffer_Release(&view);
        PyErr_SetString(PyExc_ValueError, "gather needs a float32 array of one row per entry");
        return NULL;
    }
    float *out = view.buf;
    const double *span = plan->span;
    const int64_t *index = plan->index;
    Py_ssize_t rows = plan->rows;
    for (Py_ssize_t i = 0; i < rows; i++) out[i] = (float)span[index[i]];
    double scale = plan->scale;
    double left_a = scale * span[index[rows]], left_b = scale * span[index[rows + 1]];
    double right_a = scale * span[index[rows + 2]], right_b = scale * span[index[rows + 3]];
    out[plan->left_row] = (float)unit_clip(left_a + left_b);
    out[plan->right_row] = (float)unit_clip(right_a + right_b);
    for (Py_ssize_t k = 0; k < plan->constant_count; k++)
        out[plan->constant_rows[k]] = (float)plan->constant_values[k];
    PyBuffer_Release(&view);
    Py_RETURN_NONE;
}

/* ------------------------------------------------------------------ contacts */

#define LABEL_BITS 31
#define MAX_PAIRS 64

/* label_pairs(labels_address, geoms, dists or None) -> tuple of distinct (label, label)
 * pairs of the contacts whose two geoms both carry labels (and that touch: dist <= 0). */
static PyObject *label_pairs(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    (void)self;
    if (nargs != 3) {
        PyErr_SetString(PyExc_TypeError, "label_pairs takes (labels_address, geoms, dists)");
        return NULL;
    }
    void *labels_at;
    if (as_address(args[0], &labels_at) < 0) return NULL;
    const int64_t *labels = labels_at;
    Py_buffer geoms, dists;
    int with_dists = args[2] != Py_None;
    if (PyObject_GetBuffer(args[1], &geoms, PyBUF_STRIDES | PyBUF_FORMAT) < 0) return NULL;
    if (geoms.ndim != 2 || geoms.shape[1] != 2 || geoms.itemsize != 4) {
        PyBuffer_Release(&geoms);
        PyErr_SetString(PyExc_ValueError, "geoms must be an (n, 2) int32 array");
        return NULL;
    }
    if (with_dists) {
        if (PyObject_GetBuffer(args[2], &dists, PyBUF_STRIDES | PyBUF_FORMAT) < 0) {
            PyBuffer_Release(&geoms);
            return NULL;
        }
        if (dists.ndim != 1 || dists.shape[0] != geoms.shape[0] || dists.itemsize != 8) {
            PyBuffer_Release(&geoms);
            PyBuffer_Release(&dists);
            PyErr_SetString(PyExc_ValueError, "dists must be an (n,) float64 array");
            return NULL;
        }
    }
    int64_t codes[MAX_PAIRS];
    Py_ssize_t count = 0;
    int overflow = 0;
    const char *row = geoms.buf;
    for (Py_ssize_t c = 0; c < geoms.shape[0]; c++, row += geoms.strides[0]) {
        if (with_dists && !(*(const double *)((const char *)dists.buf + c * dists.strides[0]) <= 0.0)) continue;
        int64_t first = labels[*(const int32_t *)row];
        int64_t second = labels[*(const int32_t *)(row + geoms.strides[1])];
        if (!first || !second) continue;
        int64_t code = (first << LABEL_BITS) | second;
        Py_ssize_t k = 0;
        while (k < count && codes[k] != code) k++;
        if (k < count) continue;
        if (count == MAX_PAIRS) {
            overflow = 1;
            break;
        }
        codes[count++] = code;
    }
    PyBuffer_Release(&geoms);
    if (with_dists) PyBuffer_Release(&dists);
    if (overflow) Py_RETURN_NONE; /* more distinct pairs than fit: Python counts them */
    PyObject *pairs = PyTuple_New(count);
    if (pairs == NULL) return NULL;
    for (Py_ssize_t k = 0; k < count; k++) {
        PyObject *pair = Py_BuildValue("(LL)", (long long)(codes[k] >> LABEL_BITS),
                                       (long long)(codes[k] & (((int64_t)1 << LABEL_BITS) - 1)));
        if (pair == NULL) {
            Py_DECREF(pairs);
            return NULL;
        }
        PyTuple_SET_ITEM(pairs, k, pair);
    }
    return pairs;
}

/* ------------------------------------------------------------------ module */

static PyMethodDef methods[] = {
    {"make_control_plan", (PyCFunction)(void (*)(void))make_control_plan, METH_FASTCALL,
     "make_control_plan(...) -> plan for control_step"},
    {"control_step", (PyCFunction)(void (*)(void))control_step, METH_FASTCALL,
     "control_step(plan, action) -> 0 ok, 1 invalid action, 2 not a float32/float64 vector, 3 unstable"},
    {"make_gather_plan", (PyCFunction)(void (*)(void))make_gather_plan, METH_FASTCALL,
     "make_gather_plan(...) -> plan for gather"},
    {"gather", (PyCFunction)(void (*)(void))gather, METH_FASTCALL, "gather(plan, out) fills the proprioception"},
    {"label_pairs", (PyCFunction)(void (*)(void))label_pairs, METH_FASTCALL,
     "label_pairs(labels_address, geoms, dists) -> distinct label pairs, or None past 64"},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_hotloop", "bigym's compiled step path", -1, methods};

PyMODINIT_FUNC PyInit__hotloop(void) { return PyModule_Create(&module); }
