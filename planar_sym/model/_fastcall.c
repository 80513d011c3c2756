/* _fastcall: call a generated sample loop from Python with C-level argument handling.
 *
 * One Python call costs a few hundred nanoseconds here (input conversion, the finiteness
 * check naming the bad sample, output allocation, the loop) where the same work written in
 * Python costs microseconds. Built at install as an extension (setup.py), else compiled on
 * first use by planar_sym/model/library.py; without either the runtime falls back to ctypes.
 *
 * Loop signature (derive/simd.py): int f(long long n, const double *const *in, double *const *out)
 * with per-sample blocks row-major (n, size) and the shared parameter vector among the inputs.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#define NPY_NO_DEPRECATED_API NPY_1_7_API_VERSION
#include <numpy/arrayobject.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#define MAX_IO 8
/* calls over at least this many samples release the GIL: below it, releasing and taking it
 * back (~100 ns) would cost more than the loop itself */
#define GIL_SAMPLES 64

typedef int (*loop_fn)(long long, const double *const *, double *const *);

typedef struct {
    PyObject_HEAD
    vectorcallfunc vectorcall;
    loop_fn fn;
    int n_in;                      /* per-sample inputs, in call order */
    Py_ssize_t in_size[MAX_IO];
    int p_slot;                    /* position of p among the loop's inputs */
    int n_out;
    Py_ssize_t out_rows[MAX_IO], out_cols[MAX_IO];
    int out_kind[MAX_IO];          /* 0 scalar, 1 vector, 2 matrix */
    PyObject *p;                   /* float64 contiguous parameter vector */
    PyObject *error;               /* exception class for bad input */
    PyObject *names;               /* tuple of input names, for messages */
    PyObject *doc;
    int checked;                   /* the loop reports a non-finite input itself (returns 2) */
} Caller;

/* what a loop returns for an input that is not finite (derive/simd.py NONFINITE) */
#define LOOP_NONFINITE 2

static void caller_dealloc(Caller *self) {
    Py_XDECREF(self->p);
    Py_XDECREF(self->error);
    Py_XDECREF(self->names);
    Py_XDECREF(self->doc);
    Py_TYPE(self)->tp_free((PyObject *)self);
}

/* Scan for a non-finite entry; sets the package's error naming it and returns 1. ``rows``
 * rows of ``width`` values, each ``what`` (a sample, a design); with ``per`` > 0 the rows are
 * blocks of ``per`` samples, one block per design, and the message names both. The first pass
 * is branch-free (x - x is 0 for finite x, NaN otherwise), so it vectorises. */
static int check_finite(Caller *self, PyObject *name, const double *x, npy_intp rows,
                        npy_intp width, const char *what, npy_intp per) {
    npy_intp total = rows * width;
    int bad = 0;
    for (npy_intp k = 0; k < total; ++k) bad |= !(x[k] - x[k] == 0.0);
    for (npy_intp k = 0; bad && k < total; ++k)
        if (!isfinite(x[k])) {
            Py_ssize_t r = (Py_ssize_t)(k / width), c = (Py_ssize_t)(k % width);
            PyObject *v = PyFloat_FromDouble(x[k]);
            if (v && per > 0)
                PyErr_Format(self->error, "%U[%zd, %zd, %zd] is %R at design %zd, sample %zd: "
                             "inputs must be finite", name, r / (Py_ssize_t)per,
                             r % (Py_ssize_t)per, c, v, r / (Py_ssize_t)per,
                             r % (Py_ssize_t)per);
            else if (v)
                PyErr_Format(self->error, "%U[%zd, %zd] is %R at %s %zd: inputs must be finite",
                             name, r, c, v, what, r);
            Py_XDECREF(v);
            return 1;
        }
    return 0;
}

/* The outputs as the call's result: one array alone, several as a tuple (the references move
 * from ``outs`` into the result). */
static PyObject *pack(PyObject **outs, int n_out) {
    if (n_out == 1) {
        PyObject *one = outs[0];
        outs[0] = NULL;
        return one;
    }
    PyObject *result = PyTuple_New(n_out);
    if (result)
        for (int i = 0; i < n_out; ++i) { PyTuple_SET_ITEM(result, i, outs[i]); outs[i] = NULL; }
    return result;
}

/* 1 where ``obj`` holds booleans (a bool array, a bool, a list of them): numbers only. An
 * ndarray is judged by its dtype at no cost; anything else by the array numpy makes of it. */
static int is_bool(PyObject *obj) {
    if (PyArray_Check(obj)) return PyArray_TYPE((PyArrayObject *)obj) == NPY_BOOL;
    if (PyBool_Check(obj)) return 1;
    if (PyFloat_Check(obj) || PyLong_Check(obj)) return 0;
    PyArrayObject *a = (PyArrayObject *)PyArray_FROM_O(obj);
    if (!a) {
        PyErr_Clear();
        return 0;  /* the conversion below says what is wrong */
    }
    int out = PyArray_TYPE(a) == NPY_BOOL;
    Py_DECREF(a);
    return out;
}

static PyObject *caller_call(Caller *self, PyObject *const *args, size_t nargsf,
                             PyObject *kwnames) {
    Py_ssize_t nargs = PyVectorcall_NARGS(nargsf);
    PyObject *given[MAX_IO] = {0};
    PyArrayObject *arr[MAX_IO] = {0};
    PyObject *outs[MAX_IO] = {0};
    const double *in[MAX_IO + 1];
    double *out[MAX_IO];
    PyObject *result = NULL;
    int ndim = 1, i, j;
    npy_intp n = -1;
    Py_ssize_t nkw = kwnames ? PyTuple_GET_SIZE(kwnames) : 0;
    if (nargs > self->n_in) {
        PyErr_Format(PyExc_TypeError, "expected %d arrays, got %zd", self->n_in, nargs);
        return NULL;
    }
    for (i = 0; i < nargs; ++i) given[i] = args[i];
    for (Py_ssize_t k = 0; k < nkw; ++k) {  /* keywords by input name: q=..., qd=... */
        PyObject *key = PyTuple_GET_ITEM(kwnames, k);
        for (j = 0; j < self->n_in; ++j)
            if (PyUnicode_Compare(key, PyTuple_GET_ITEM(self->names, j)) == 0) break;
        if (j == self->n_in || given[j]) {
            PyErr_Format(PyExc_TypeError, "unexpected or repeated argument %R (inputs: %R)",
                         key, self->names);
            return NULL;
        }
        given[j] = args[nargs + k];
    }
    for (i = 0; i < self->n_in; ++i)
        if (!given[i]) {
            PyErr_Format(PyExc_TypeError, "missing input %R", PyTuple_GET_ITEM(self->names, i));
            return NULL;
        }
    for (i = 0; i < self->n_in; ++i) {
        if (is_bool(given[i])) {  /* True read as 1 rad (a trial): a description refuses it */
            PyErr_Format(self->error, "%U must be numbers, got booleans (True/False)",
                         PyTuple_GET_ITEM(self->names, i));
            goto done;
        }
        arr[i] = (PyArrayObject *)PyArray_FROMANY(given[i], NPY_DOUBLE, 1, 2,
                                                  NPY_ARRAY_C_CONTIGUOUS | NPY_ARRAY_ALIGNED);
        if (!arr[i]) {
            PyErr_Clear();
            PyErr_Format(self->error, "%U must be a float array of shape (N, %zd) or (%zd,)",
                         PyTuple_GET_ITEM(self->names, i), self->in_size[i], self->in_size[i]);
            goto done;
        }
        int d = PyArray_NDIM(arr[i]);
        npy_intp rows = d == 2 ? PyArray_DIM(arr[i], 0) : 1;
        if (PyArray_DIM(arr[i], d - 1) != self->in_size[i]) {
            PyErr_Format(self->error, "%U must have shape (N, %zd) or (%zd,), got last axis %zd",
                         PyTuple_GET_ITEM(self->names, i), self->in_size[i], self->in_size[i],
                         (Py_ssize_t)PyArray_DIM(arr[i], d - 1));
            goto done;
        }
        if (d == 2) ndim = 2;  /* one (size,) sample mixes with a batch of one, as in numpy */
        if (n < 0) n = rows;
        else if (rows != n) {
            PyErr_Format(self->error, "inputs must have the same number of samples, got "
                         "%U: %zd, %U: %zd", PyTuple_GET_ITEM(self->names, 0), (Py_ssize_t)n,
                         PyTuple_GET_ITEM(self->names, i), (Py_ssize_t)rows);
            goto done;
        }
        if (!self->checked && check_finite(self, PyTuple_GET_ITEM(self->names, i),
                                           PyArray_DATA(arr[i]), n, self->in_size[i],
                                           "sample", 0))
            goto done;
    }
    for (i = 0, j = 0; j < self->n_in + 1; ++j)
        in[j] = j == self->p_slot ? (const double *)PyArray_DATA((PyArrayObject *)self->p)
                                  : (const double *)PyArray_DATA(arr[i++]);
    for (i = 0; i < self->n_out; ++i) {
        npy_intp dims[3];
        int nd = 0;
        if (ndim == 2) dims[nd++] = n;
        if (self->out_kind[i] >= 1) dims[nd++] = self->out_rows[i];
        if (self->out_kind[i] == 2) dims[nd++] = self->out_cols[i];
        outs[i] = PyArray_SimpleNew(nd, dims, NPY_DOUBLE);
        if (!outs[i]) {  /* say what was asked and what to do, as the package's own error */
            if (PyErr_ExceptionMatches(PyExc_MemoryError)) {
                double gb = 8.0 * (double)n * self->out_rows[i] * self->out_cols[i] / 1e9;
                PyErr_Clear();
                PyErr_Format(self->error, "not enough memory for the output of %zd samples "
                             "(%.3g GB): evaluate them in smaller batches", (Py_ssize_t)n, gb);
            }
            goto done;
        }
        out[i] = (double *)PyArray_DATA((PyArrayObject *)outs[i]);
    }
    int status;
    if (n >= GIL_SAMPLES) {  /* long loops let other threads run (a sweep on several cores) */
        Py_BEGIN_ALLOW_THREADS
        status = self->fn((long long)n, in, out);
        Py_END_ALLOW_THREADS
    } else {
        status = self->fn((long long)n, in, out);
    }
    if (status == LOOP_NONFINITE && self->checked) {  /* find and name it, as the pass would */
        for (i = 0; i < self->n_in; ++i)
            if (check_finite(self, PyTuple_GET_ITEM(self->names, i), PyArray_DATA(arr[i]), n,
                             self->in_size[i], "sample", 0))
                goto done;
    }
    if (status) {
        PyErr_SetString(PyExc_RuntimeError, "generated function failed");
        goto done;
    }
    for (i = 0; i < self->n_out; ++i)  /* one sample's scalar: a Python float */
        if (ndim == 1 && self->out_kind[i] == 0) {
            PyObject *f = PyFloat_FromDouble(out[i][0]);
            Py_SETREF(outs[i], f);
            if (!f) goto done;
        }
    result = pack(outs, self->n_out);
done:
    for (i = 0; i < MAX_IO; ++i) { Py_XDECREF(arr[i]); Py_XDECREF(outs[i]); }
    return result;
}

/* designs(P, *arrays, reduce=False, weights=None): the loop once per design, each with its own
 * parameter vector P[d] (D, n_p), over the same N samples: an array of shape (N, size) is shared
 * by every design, one of shape (D, N, size) is per design. Outputs gain a leading design axis;
 * with reduce=True only per-design statistics come back, shape (D, components, 3): the minimum,
 * the maximum and the mean square of every output component over the samples (the per-sample
 * values pass through one reused buffer, so a sweep's memory does not grow with N). The mean
 * square is sum w_s v_s^2 with weights (N,) given (a time average by the trapezoidal rule, as
 * one run's RMS: a trial found the plain mean 1e-3 off it on a fast move), else the plain mean.
 * The loop over the designs runs without the GIL. */
static PyObject *caller_designs(Caller *self, PyObject *const *args, Py_ssize_t nargs,
                                PyObject *kwnames) {
    PyArrayObject *P = NULL, *W = NULL, *arr[MAX_IO] = {0};
    PyObject *outs[MAX_IO] = {0}, *result = NULL;
    double *scratch = NULL;
    int reduce = 0, i, shared[MAX_IO];
    npy_intp D, N = -1, np_ = PyArray_DIM((PyArrayObject *)self->p, 0), comps = 0;
    Py_ssize_t nkw = kwnames ? PyTuple_GET_SIZE(kwnames) : 0;
    PyObject *weights = NULL;
    for (Py_ssize_t k = 0; k < nkw; ++k) {
        PyObject *key = PyTuple_GET_ITEM(kwnames, k);
        if (PyUnicode_CompareWithASCIIString(key, "weights") == 0) {
            weights = args[nargs + k] == Py_None ? NULL : args[nargs + k];
            continue;
        }
        if (PyUnicode_CompareWithASCIIString(key, "reduce") != 0) {
            PyErr_Format(PyExc_TypeError, "designs: unexpected keyword %R", key);
            return NULL;
        }
        reduce = PyObject_IsTrue(args[nargs + k]);
        if (reduce < 0) return NULL;
    }
    if (nargs != self->n_in + 1) {
        PyErr_Format(PyExc_TypeError, "designs: expected the parameters and %d arrays, got %zd "
                     "arguments", self->n_in, nargs);
        return NULL;
    }
    P = (PyArrayObject *)PyArray_FROMANY(args[0], NPY_DOUBLE, 2, 2,
                                         NPY_ARRAY_C_CONTIGUOUS | NPY_ARRAY_ALIGNED);
    if (!P || PyArray_DIM(P, 1) != np_) {
        PyErr_Clear();
        PyErr_Format(self->error, "parameters must be a float array of shape (designs, %zd)",
                     (Py_ssize_t)np_);
        goto done;
    }
    D = PyArray_DIM(P, 0);
    {
        PyObject *pname = PyUnicode_FromString("parameters");
        int bad = pname ? check_finite(self, pname, PyArray_DATA(P), D, np_, "design", 0) : 1;
        Py_XDECREF(pname);
        if (bad) goto done;
    }
    for (i = 0; i < self->n_in; ++i) {
        PyObject *name = PyTuple_GET_ITEM(self->names, i);
        arr[i] = (PyArrayObject *)PyArray_FROMANY(args[i + 1], NPY_DOUBLE, 2, 3,
                                                  NPY_ARRAY_C_CONTIGUOUS | NPY_ARRAY_ALIGNED);
        if (!arr[i]) {
            PyErr_Clear();
            PyErr_Format(self->error, "%U must be a float array of shape (N, %zd) or "
                         "(designs, N, %zd)", name, self->in_size[i], self->in_size[i]);
            goto done;
        }
        int d = PyArray_NDIM(arr[i]);
        shared[i] = d == 2;
        npy_intp rows = PyArray_DIM(arr[i], d - 2);
        if (PyArray_DIM(arr[i], d - 1) != self->in_size[i] || (d == 3 && PyArray_DIM(arr[i], 0) != D)) {
            PyErr_Format(self->error, "%U must have shape (N, %zd) or (%zd, N, %zd)", name,
                         self->in_size[i], (Py_ssize_t)D, self->in_size[i]);
            goto done;
        }
        if (N < 0) N = rows;
        else if (rows != N) {
            PyErr_Format(self->error, "inputs must have the same number of samples, got %zd "
                         "and %zd (%U)", (Py_ssize_t)N, (Py_ssize_t)rows, name);
            goto done;
        }
        if (check_finite(self, name, PyArray_DATA(arr[i]), (d == 3 ? D : 1) * rows,
                         self->in_size[i], "sample", d == 3 ? rows : 0))
            goto done;
    }
    for (i = 0; i < self->n_out; ++i) comps += self->out_rows[i] * self->out_cols[i];
    if (weights) {
        W = (PyArrayObject *)PyArray_FROMANY(weights, NPY_DOUBLE, 1, 1,
                                             NPY_ARRAY_C_CONTIGUOUS | NPY_ARRAY_ALIGNED);
        if (!W || !reduce || PyArray_DIM(W, 0) != N) {
            PyErr_Clear();
            PyErr_Format(self->error, "weights must be a float array of shape (%zd,), one per "
                         "sample, and only with reduce=True", (Py_ssize_t)N);
            goto done;
        }
    }
    if (reduce) {
        npy_intp dims[3] = {D, comps, 3};
        outs[0] = PyArray_SimpleNew(3, dims, NPY_DOUBLE);
        scratch = PyMem_RawMalloc(sizeof(double) * (size_t)(N > 0 ? N : 1) * (size_t)comps);
        if (!outs[0] || !scratch) { PyErr_NoMemory(); goto done; }
    } else {
        for (i = 0; i < self->n_out; ++i) {
            npy_intp dims[4] = {D, N, self->out_rows[i], self->out_cols[i]};
            int nd = 2 + (self->out_kind[i] >= 1) + (self->out_kind[i] == 2);
            outs[i] = PyArray_SimpleNew(nd, dims, NPY_DOUBLE);
            if (!outs[i]) {
                if (PyErr_ExceptionMatches(PyExc_MemoryError)) {
                    PyErr_Clear();
                    PyErr_Format(self->error, "not enough memory for the outputs of %zd designs "
                                 "of %zd samples (%.3g GB): use reduce=True or fewer designs "
                                 "per call", (Py_ssize_t)D, (Py_ssize_t)N,
                                 8.0 * D * N * comps / 1e9);
                }
                goto done;
            }
        }
    }
    {
        long long failed = -1;
        const double *pp = PyArray_DATA(P);
        const double *wt = W ? (const double *)PyArray_DATA(W) : NULL;
        Py_BEGIN_ALLOW_THREADS
        for (npy_intp d = 0; d < D && failed < 0; ++d) {
            const double *in[MAX_IO + 1];
            double *out[MAX_IO];
            for (int j = 0, k = 0; j < self->n_in + 1; ++j) {
                if (j == self->p_slot) { in[j] = pp + d * np_; continue; }
                const double *x = PyArray_DATA(arr[k]);
                in[j] = shared[k] ? x : x + d * N * self->in_size[k];
                ++k;
            }
            double *at = scratch;
            for (int k = 0; k < self->n_out; ++k) {
                npy_intp size = self->out_rows[k] * self->out_cols[k];
                if (reduce) { out[k] = at; at += N * size; }
                else out[k] = (double *)PyArray_DATA((PyArrayObject *)outs[k]) + d * N * size;
            }
            if (self->fn((long long)N, in, out)) { failed = d; break; }
            if (!reduce) continue;
            double *stats = (double *)PyArray_DATA((PyArrayObject *)outs[0]) + d * comps * 3;
            npy_intp c0 = 0;
            for (int k = 0; k < self->n_out; ++k) {
                npy_intp size = self->out_rows[k] * self->out_cols[k];
                for (npy_intp c = 0; c < size; ++c) {
                    double lo = INFINITY, hi = -INFINITY, sq = 0.0;
                    for (npy_intp s = 0; s < N; ++s) {
                        double v = out[k][s * size + c];
                        lo = v < lo ? v : lo;
                        hi = v > hi ? v : hi;
                        sq += wt ? wt[s] * v * v : v * v;
                        if (v != v) { lo = hi = v; }  /* NaN poisons both: a failed sample shows */
                    }
                    double *st = stats + (c0 + c) * 3;
                    st[0] = lo; st[1] = hi; st[2] = wt ? sq : N > 0 ? sq / (double)N : 0.0;
                }
                c0 += size;
            }
        }
        Py_END_ALLOW_THREADS
        if (failed >= 0) {
            PyErr_Format(PyExc_RuntimeError, "generated function failed at design %lld", failed);
            goto done;
        }
    }
    result = pack(outs, reduce ? 1 : self->n_out);
done:
    PyMem_RawFree(scratch);
    Py_XDECREF(P);
    Py_XDECREF(W);
    for (i = 0; i < MAX_IO; ++i) { Py_XDECREF(arr[i]); Py_XDECREF(outs[i]); }
    return result;
}

static PyMethodDef caller_methods[] = {
    {"designs", (PyCFunction)(void (*)(void))caller_designs, METH_FASTCALL | METH_KEYWORDS,
     "designs($self, P, /, *arrays, reduce=False, weights=None)\n--\n\n"
     "The loop once per parameter vector P[d] (D, n_p), over shared (N, size) or per-design\n"
     "(D, N, size) inputs; reduce: min, max and mean square per design (sum of weights[s]\n"
     "v[s]^2 with weights (N,), else the plain mean)."},
    {NULL, NULL, 0, NULL}};

static PyObject *caller_get_doc(Caller *self, void *closure) {
    (void)closure;
    return Py_NewRef(self->doc ? self->doc : Py_None);
}

/* inspect.signature(robot.inverse_dynamics) -> (q, qd, qdd): notebooks and IDEs show the
 * inputs of a C-level caller like those of the Python method it replaces */
static PyObject *caller_get_signature(Caller *self, void *closure) {
    (void)closure;
    PyObject *inspect = PyImport_ImportModule("inspect"), *result = NULL;
    if (!inspect) return NULL;
    PyObject *param = PyObject_GetAttrString(inspect, "Parameter");
    PyObject *sigcls = PyObject_GetAttrString(inspect, "Signature");
    PyObject *kind = param ? PyObject_GetAttrString(param, "POSITIONAL_OR_KEYWORD") : NULL;
    PyObject *params = PyList_New(0);
    if (!sigcls || !kind || !params) goto done;
    for (Py_ssize_t i = 0; i < PyTuple_GET_SIZE(self->names); ++i) {
        PyObject *one = PyObject_CallFunctionObjArgs(param, PyTuple_GET_ITEM(self->names, i),
                                                     kind, NULL);
        int failed = !one || PyList_Append(params, one) < 0;
        Py_XDECREF(one);
        if (failed) goto done;
    }
    result = PyObject_CallOneArg(sigcls, params);
done:
    Py_XDECREF(params);
    Py_XDECREF(kind);
    Py_XDECREF(sigcls);
    Py_XDECREF(param);
    Py_DECREF(inspect);
    return result;
}

static PyGetSetDef caller_getset[] = {
    {"__doc__", (getter)caller_get_doc, NULL, NULL, NULL},
    {"__signature__", (getter)caller_get_signature, NULL, NULL, NULL},
    {NULL, NULL, NULL, NULL, NULL}};

static PyTypeObject CallerType = {
    PyVarObject_HEAD_INIT(NULL, 0)
    .tp_name = "planar_sym._fastcall.Caller",
    .tp_basicsize = sizeof(Caller),
    .tp_dealloc = (destructor)caller_dealloc,
    .tp_flags = Py_TPFLAGS_DEFAULT | Py_TPFLAGS_HAVE_VECTORCALL,
    .tp_vectorcall_offset = offsetof(Caller, vectorcall),
    .tp_call = PyVectorcall_Call,
    .tp_getset = caller_getset,
    .tp_methods = caller_methods,
};

/* make(address, in_sizes, p_slot, out_specs ((rows, cols, kind), ...), p, error, names, doc,
 *      checked=False): with ``checked`` the loop finds non-finite inputs itself */
static PyObject *make(PyObject *mod, PyObject *args) {
    unsigned long long address;
    PyObject *in_sizes, *out_specs, *p, *error, *names, *doc;
    int p_slot;
    (void)mod;
    int checked = 0;
    if (!PyArg_ParseTuple(args, "KO!iO!OOO!O|p", &address, &PyTuple_Type, &in_sizes, &p_slot,
                          &PyTuple_Type, &out_specs, &p, &error, &PyTuple_Type, &names, &doc,
                          &checked))
        return NULL;
    if (PyTuple_GET_SIZE(in_sizes) > MAX_IO || PyTuple_GET_SIZE(out_specs) > MAX_IO) {
        PyErr_SetString(PyExc_ValueError, "too many inputs or outputs");
        return NULL;
    }
    Caller *self = PyObject_New(Caller, &CallerType);
    if (!self) return NULL;
    self->vectorcall = (vectorcallfunc)caller_call;
    self->fn = (loop_fn)(uintptr_t)address;
    self->checked = checked;
    self->n_in = (int)PyTuple_GET_SIZE(in_sizes);
    for (int i = 0; i < self->n_in; ++i) self->in_size[i] = PyLong_AsSsize_t(PyTuple_GET_ITEM(in_sizes, i));
    self->p_slot = p_slot;
    self->n_out = (int)PyTuple_GET_SIZE(out_specs);
    for (int i = 0; i < self->n_out; ++i) {
        PyObject *spec = PyTuple_GET_ITEM(out_specs, i);
        if (!PyArg_ParseTuple(spec, "nni", &self->out_rows[i], &self->out_cols[i], &self->out_kind[i])) {
            self->p = self->error = self->names = self->doc = NULL;
            Py_DECREF(self);
            return NULL;
        }
    }
    self->p = PyArray_FROMANY(p, NPY_DOUBLE, 1, 1, NPY_ARRAY_C_CONTIGUOUS | NPY_ARRAY_ALIGNED);
    self->error = Py_NewRef(error);
    self->names = Py_NewRef(names);
    self->doc = Py_NewRef(doc);
    if (!self->p || PyErr_Occurred()) { Py_DECREF(self); return NULL; }
    return (PyObject *)self;
}

/* ---- closed chains: torques and multipliers from the passive rows ------------------------
 * [S^T Phi_q^T] [tau; lambda] = b splits, with a = actuated and p = passive coordinates, into
 *   Phi_p^T lambda = b_p   (m x m),   tau = b_a - Phi_a^T lambda,
 * so the whole matrix is singular exactly when Phi_p is; its 1-norm condition number
 * ||Phi_p||_1 ||Phi_p^-1||_1 is computed exactly from the inverse (m is 2 or 4 here). */
#define MAXM 16

static int invert(int m, double *a, double *inv) {  /* Gauss-Jordan, partial pivoting */
    for (int i = 0; i < m; ++i)
        for (int j = 0; j < m; ++j) inv[i * m + j] = i == j;
    for (int c = 0; c < m; ++c) {
        int piv = c;
        for (int r = c + 1; r < m; ++r) if (fabs(a[r * m + c]) > fabs(a[piv * m + c])) piv = r;
        if (a[piv * m + c] == 0.0) return 1;
        for (int j = 0; j < m; ++j) {
            double t = a[c * m + j]; a[c * m + j] = a[piv * m + j]; a[piv * m + j] = t;
            t = inv[c * m + j]; inv[c * m + j] = inv[piv * m + j]; inv[piv * m + j] = t;
        }
        double d = 1.0 / a[c * m + c];
        for (int j = 0; j < m; ++j) { a[c * m + j] *= d; inv[c * m + j] *= d; }
        for (int r = 0; r < m; ++r) {
            if (r == c) continue;
            double f = a[r * m + c];
            if (f == 0.0) continue;
            for (int j = 0; j < m; ++j) { a[r * m + j] -= f * a[c * m + j]; inv[r * m + j] -= f * inv[c * m + j]; }
        }
    }
    return 0;
}

static double norm1(int m, const double *a) {
    double best = 0.0;
    for (int j = 0; j < m; ++j) {
        double s = 0.0;
        for (int i = 0; i < m; ++i) s += fabs(a[i * m + j]);
        if (s > best) best = s;
    }
    return best;
}

/* closed_solve(b (N, n), jac (N, m, n), act (tuple), tau_out (N, n_act), lam_out (N, m),
 *              cond_out (N,)) -> None; infinite cond where Phi_p is exactly singular */
static PyObject *closed_solve(PyObject *mod, PyObject *args) {
    PyObject *ob, *oj, *oact, *ot, *ol, *oc;
    (void)mod;
    if (!PyArg_ParseTuple(args, "OOO!OOO", &ob, &oj, &PyTuple_Type, &oact, &ot, &ol, &oc))
        return NULL;
    PyArrayObject *b = (PyArrayObject *)PyArray_FROMANY(ob, NPY_DOUBLE, 2, 2, NPY_ARRAY_CARRAY_RO);
    PyArrayObject *j = (PyArrayObject *)PyArray_FROMANY(oj, NPY_DOUBLE, 3, 3, NPY_ARRAY_CARRAY_RO);
    PyObject *result = NULL;
    if (!b || !j) goto out;
    npy_intp N = PyArray_DIM(b, 0), n = PyArray_DIM(b, 1), m = PyArray_DIM(j, 1);
    Py_ssize_t na = PyTuple_GET_SIZE(oact);
    if (PyArray_DIM(j, 0) != N || PyArray_DIM(j, 2) != n || na + m != n || m > MAXM || n > 4 * MAXM
        || !PyArray_Check(ot) || !PyArray_Check(ol) || !PyArray_Check(oc)) {
        PyErr_SetString(PyExc_ValueError, "closed_solve: inconsistent shapes");
        goto out;
    }
    int act[4 * MAXM], pas[4 * MAXM], is_act[4 * MAXM] = {0};
    for (Py_ssize_t k = 0; k < na; ++k) { act[k] = (int)PyLong_AsLong(PyTuple_GET_ITEM(oact, k)); is_act[act[k]] = 1; }
    for (int i = 0, k = 0; i < n; ++i) if (!is_act[i]) pas[k++] = i;
    double *tau = (double *)PyArray_DATA((PyArrayObject *)ot);
    double *lam = (double *)PyArray_DATA((PyArrayObject *)ol);
    double *cond = (double *)PyArray_DATA((PyArrayObject *)oc);
    const double *bb = (const double *)PyArray_DATA(b), *jj = (const double *)PyArray_DATA(j);
    Py_BEGIN_ALLOW_THREADS
    for (npy_intp s = 0; s < N; ++s) {
        const double *bs = bb + s * n, *js = jj + s * m * n;
        double pt[MAXM * MAXM], inv[MAXM * MAXM], work[MAXM * MAXM];
        for (int r = 0; r < m; ++r)          /* Phi_p^T: row r = passive coordinate pas[r] */
            for (int c = 0; c < m; ++c) pt[r * m + c] = js[c * n + pas[r]];
        memcpy(work, pt, sizeof(double) * m * m);
        if (invert((int)m, work, inv)) {
            cond[s] = INFINITY;
            for (int c = 0; c < m; ++c) lam[s * m + c] = NAN;
            for (Py_ssize_t k = 0; k < na; ++k) tau[s * na + k] = NAN;
            continue;
        }
        cond[s] = norm1((int)m, pt) * norm1((int)m, inv);
        for (int c = 0; c < m; ++c) {
            double v = 0.0;
            for (int r = 0; r < m; ++r) v += inv[c * m + r] * bs[pas[r]];
            lam[s * m + c] = v;
        }
        for (Py_ssize_t k = 0; k < na; ++k) {   /* tau = b_a - Phi_a^T lambda */
            double v = bs[act[k]];
            for (int c = 0; c < m; ++c) v -= js[c * n + act[k]] * lam[s * m + c];
            tau[s * na + k] = v;
        }
    }
    Py_END_ALLOW_THREADS
    result = Py_NewRef(Py_None);
out:
    Py_XDECREF(b);
    Py_XDECREF(j);
    return result;
}

static PyMethodDef methods[] = {
    {"make", make, METH_VARARGS,
     "make($module, address, in_sizes, p_slot, out_specs, p, error, names, doc, /)\n--\n\n"
     "A Caller for the sample loop at address."},
    {"closed_solve", closed_solve, METH_VARARGS,
     "closed_solve($module, b, jac, act, tau_out, lam_out, cond_out, /)\n--\n\n"
     "Closed-chain torques (N, n_act) and multipliers (N, m), batched, with the condition\n"
     "number of Phi_p (N,)."},
                                {NULL, NULL, 0, NULL}};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_fastcall", NULL, -1, methods};

PyMODINIT_FUNC PyInit__fastcall(void) {
    import_array();
    if (PyType_Ready(&CallerType) < 0) return NULL;
    PyObject *m = PyModule_Create(&module);
#ifdef PLANAR_SYM_SOURCE_HASH /* built at install (setup.py): the runtime checks it is current */
    if (m && PyModule_AddStringConstant(m, "SOURCE_HASH", PLANAR_SYM_SOURCE_HASH) < 0) {
        Py_DECREF(m);
        return NULL;
    }
#endif
    return m;
}
