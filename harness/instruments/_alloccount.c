/* _alloccount: exact counts of the memory allocations a piece of Python code makes.
 *
 * Wraps CPython's three allocator domains (PyMem_GetAllocator / PyMem_SetAllocator for RAW,
 * MEM and OBJ) with counters, and, when built against NumPy's headers, installs a NumPy
 * data-memory handler (NEP 49, PyDataMem_SetHandler) that counts array buffers, which bypass
 * those domains. The wrappers call the allocators that were in place before, so installing
 * and removing them while the interpreter runs is safe (CPython calls such wrappers "hooks").
 *
 * What is counted, per domain: calls that allocate (malloc, calloc, realloc of NULL), calls
 * that resize (realloc of a block), frees, and the bytes requested by all of them (a resize
 * counts its new size). Objects that CPython reuses from its free lists (floats, tuples,
 * frames ...) never reach an allocator and are not counted by this or any allocator hook.
 *
 * Counters of the RAW domain and of NumPy's handler are atomic: those allocators may be called
 * without the GIL. MEM and OBJ are only called with the GIL held, so plain increments do.
 *
 * Python API: install(), uninstall(), installed() -> bool, reset(), counts() -> dict of
 * domain -> (allocations, resizes, frees, bytes), has_numpy() -> bool.
 */

#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <stdint.h>

#ifdef RTC_WITH_NUMPY
#define NPY_NO_DEPRECATED_API NPY_1_22_API_VERSION
#include <numpy/arrayobject.h>
#endif

#if defined(__GNUC__) || defined(__clang__)
#define ATOMIC_ADD(field, value) __atomic_fetch_add(&(field), (value), __ATOMIC_RELAXED)
#define ATOMIC_LOAD(field) __atomic_load_n(&(field), __ATOMIC_RELAXED)
#define ATOMIC_STORE(field, value) __atomic_store_n(&(field), (value), __ATOMIC_RELAXED)
#else
#error "_alloccount needs GCC or Clang atomics; install without it to use the tracemalloc fallback"
#endif

#define PLAIN_ADD(field, value) ((field) += (value))

typedef struct {
    uint64_t allocations;
    uint64_t resizes;
    uint64_t frees;
    uint64_t bytes;
} Counts;

enum { RAW = 0, MEM = 1, OBJ = 2, NUMPY = 3, N_COUNTERS = 4 };

static const char *const COUNTER_NAMES[N_COUNTERS] = {"raw", "mem", "obj", "numpy"};
static const PyMemAllocatorDomain DOMAINS[3] = {
    PYMEM_DOMAIN_RAW, PYMEM_DOMAIN_MEM, PYMEM_DOMAIN_OBJ};

static Counts counts[N_COUNTERS];
static PyMemAllocatorEx previous[3];
static int hooks_installed = 0;

/* One set of wrapper functions per domain; INC is ATOMIC_ADD or PLAIN_ADD. */
#define DEFINE_WRAPPERS(NAME, INDEX, INC)                                                    \
    static void *NAME##_malloc(void *ctx, size_t size)                                       \
    {                                                                                        \
        (void)ctx;                                                                           \
        void *block = previous[INDEX].malloc(previous[INDEX].ctx, size);                     \
        if (block != NULL) {                                                                 \
            INC(counts[INDEX].allocations, 1);                                               \
            INC(counts[INDEX].bytes, (uint64_t)size);                                        \
        }                                                                                    \
        return block;                                                                        \
    }                                                                                        \
    static void *NAME##_calloc(void *ctx, size_t nelem, size_t elsize)                       \
    {                                                                                        \
        (void)ctx;                                                                           \
        void *block = previous[INDEX].calloc(previous[INDEX].ctx, nelem, elsize);            \
        if (block != NULL) {                                                                 \
            INC(counts[INDEX].allocations, 1);                                               \
            INC(counts[INDEX].bytes, (uint64_t)nelem * (uint64_t)elsize);                    \
        }                                                                                    \
        return block;                                                                        \
    }                                                                                        \
    static void *NAME##_realloc(void *ctx, void *ptr, size_t new_size)                       \
    {                                                                                        \
        (void)ctx;                                                                           \
        void *block = previous[INDEX].realloc(previous[INDEX].ctx, ptr, new_size);           \
        if (block != NULL) {                                                                 \
            if (ptr == NULL) {                                                               \
                INC(counts[INDEX].allocations, 1);                                           \
            }                                                                                \
            else {                                                                           \
                INC(counts[INDEX].resizes, 1);                                               \
            }                                                                                \
            INC(counts[INDEX].bytes, (uint64_t)new_size);                                    \
        }                                                                                    \
        return block;                                                                        \
    }                                                                                        \
    static void NAME##_free(void *ctx, void *ptr)                                            \
    {                                                                                        \
        (void)ctx;                                                                           \
        if (ptr != NULL) {                                                                   \
            INC(counts[INDEX].frees, 1);                                                     \
        }                                                                                    \
        previous[INDEX].free(previous[INDEX].ctx, ptr);                                      \
    }

DEFINE_WRAPPERS(raw, RAW, ATOMIC_ADD)
DEFINE_WRAPPERS(mem, MEM, PLAIN_ADD)
DEFINE_WRAPPERS(obj, OBJ, PLAIN_ADD)

static PyMemAllocatorEx wrappers[3] = {
    {NULL, raw_malloc, raw_calloc, raw_realloc, raw_free},
    {NULL, mem_malloc, mem_calloc, mem_realloc, mem_free},
    {NULL, obj_malloc, obj_calloc, obj_realloc, obj_free},
};

/* ------------------------------------------------------------------ NumPy (NEP 49) */

#ifdef RTC_WITH_NUMPY
static PyObject *numpy_previous_capsule = NULL; /* the handler we wrap, kept alive forever */
static PyDataMem_Handler *numpy_previous = NULL;
static PyObject *numpy_our_capsule = NULL;
static PyObject *numpy_replaced = NULL; /* what was current when we installed */

static void *np_malloc(void *ctx, size_t size)
{
    (void)ctx;
    void *block = numpy_previous->allocator.malloc(numpy_previous->allocator.ctx, size);
    if (block != NULL) {
        ATOMIC_ADD(counts[NUMPY].allocations, 1);
        ATOMIC_ADD(counts[NUMPY].bytes, (uint64_t)size);
    }
    return block;
}

static void *np_calloc(void *ctx, size_t nelem, size_t elsize)
{
    (void)ctx;
    void *block =
        numpy_previous->allocator.calloc(numpy_previous->allocator.ctx, nelem, elsize);
    if (block != NULL) {
        ATOMIC_ADD(counts[NUMPY].allocations, 1);
        ATOMIC_ADD(counts[NUMPY].bytes, (uint64_t)nelem * (uint64_t)elsize);
    }
    return block;
}

static void *np_realloc(void *ctx, void *ptr, size_t new_size)
{
    (void)ctx;
    void *block =
        numpy_previous->allocator.realloc(numpy_previous->allocator.ctx, ptr, new_size);
    if (block != NULL) {
        if (ptr == NULL) {
            ATOMIC_ADD(counts[NUMPY].allocations, 1);
        }
        else {
            ATOMIC_ADD(counts[NUMPY].resizes, 1);
        }
        ATOMIC_ADD(counts[NUMPY].bytes, (uint64_t)new_size);
    }
    return block;
}

static void np_free(void *ctx, void *ptr, size_t size)
{
    (void)ctx;
    if (ptr != NULL) {
        ATOMIC_ADD(counts[NUMPY].frees, 1);
    }
    numpy_previous->allocator.free(numpy_previous->allocator.ctx, ptr, size);
}

static PyDataMem_Handler numpy_handler = {
    "rtc_alloccount",
    1,
    {NULL, np_malloc, np_calloc, np_realloc, np_free},
};

static int numpy_install(void)
{
    if (numpy_previous == NULL) {
        /* Wrap the handler current at first install (NumPy's default) for good: arrays
         * allocated through our handler free through it even after we are removed. */
        numpy_previous_capsule = PyDataMem_GetHandler();
        if (numpy_previous_capsule == NULL) {
            return -1;
        }
        numpy_previous =
            (PyDataMem_Handler *)PyCapsule_GetPointer(numpy_previous_capsule, "mem_handler");
        if (numpy_previous == NULL) {
            return -1;
        }
        numpy_our_capsule = PyCapsule_New(&numpy_handler, "mem_handler", NULL);
        if (numpy_our_capsule == NULL) {
            return -1;
        }
    }
    PyObject *old = PyDataMem_SetHandler(numpy_our_capsule);
    if (old == NULL) {
        return -1;
    }
    Py_XSETREF(numpy_replaced, old);
    return 0;
}

static int numpy_uninstall(void)
{
    if (numpy_replaced == NULL) {
        return 0;
    }
    PyObject *ours = PyDataMem_SetHandler(numpy_replaced);
    if (ours == NULL) {
        return -1;
    }
    Py_DECREF(ours);
    Py_CLEAR(numpy_replaced);
    return 0;
}
#endif

/* ------------------------------------------------------------------ the module */

static PyObject *install(PyObject *self, PyObject *unused)
{
    (void)self;
    (void)unused;
    if (hooks_installed) {
        PyErr_SetString(PyExc_RuntimeError, "_alloccount: the counters are already installed");
        return NULL;
    }
    for (int i = 0; i < 3; i++) {
        PyMem_GetAllocator(DOMAINS[i], &previous[i]);
    }
    for (int i = 0; i < 3; i++) {
        PyMem_SetAllocator(DOMAINS[i], &wrappers[i]);
    }
    hooks_installed = 1;
#ifdef RTC_WITH_NUMPY
    if (numpy_install() < 0) {
        return NULL;
    }
#endif
    Py_RETURN_NONE;
}

static PyObject *uninstall(PyObject *self, PyObject *unused)
{
    (void)self;
    (void)unused;
    if (!hooks_installed) {
        PyErr_SetString(PyExc_RuntimeError, "_alloccount: the counters are not installed");
        return NULL;
    }
    for (int i = 0; i < 3; i++) {
        PyMemAllocatorEx current;
        PyMem_GetAllocator(DOMAINS[i], &current);
        if (current.malloc != wrappers[i].malloc) {
            PyErr_SetString(PyExc_RuntimeError,
                            "_alloccount: another allocator hook was installed over ours "
                            "(tracemalloc?); remove it first");
            return NULL;
        }
    }
#ifdef RTC_WITH_NUMPY
    if (numpy_uninstall() < 0) {
        return NULL;
    }
#endif
    for (int i = 0; i < 3; i++) {
        PyMem_SetAllocator(DOMAINS[i], &previous[i]);
    }
    hooks_installed = 0;
    Py_RETURN_NONE;
}

static PyObject *is_installed(PyObject *self, PyObject *unused)
{
    (void)self;
    (void)unused;
    return PyBool_FromLong(hooks_installed);
}

static PyObject *reset(PyObject *self, PyObject *unused)
{
    (void)self;
    (void)unused;
    for (int i = 0; i < N_COUNTERS; i++) {
        ATOMIC_STORE(counts[i].allocations, 0);
        ATOMIC_STORE(counts[i].resizes, 0);
        ATOMIC_STORE(counts[i].frees, 0);
        ATOMIC_STORE(counts[i].bytes, 0);
    }
    Py_RETURN_NONE;
}

static PyObject *get_counts(PyObject *self, PyObject *unused)
{
    (void)self;
    (void)unused;
    /* Read every counter before creating any Python object: building the result allocates,
     * and those allocations must not show up in the figures we return. */
    Counts copy[N_COUNTERS];
    for (int i = 0; i < N_COUNTERS; i++) {
        copy[i].allocations = ATOMIC_LOAD(counts[i].allocations);
        copy[i].resizes = ATOMIC_LOAD(counts[i].resizes);
        copy[i].frees = ATOMIC_LOAD(counts[i].frees);
        copy[i].bytes = ATOMIC_LOAD(counts[i].bytes);
    }
    PyObject *result = PyDict_New();
    if (result == NULL) {
        return NULL;
    }
    for (int i = 0; i < N_COUNTERS; i++) {
        PyObject *entry = Py_BuildValue("(KKKK)", (unsigned long long)copy[i].allocations,
                                        (unsigned long long)copy[i].resizes,
                                        (unsigned long long)copy[i].frees,
                                        (unsigned long long)copy[i].bytes);
        if (entry == NULL || PyDict_SetItemString(result, COUNTER_NAMES[i], entry) < 0) {
            Py_XDECREF(entry);
            Py_DECREF(result);
            return NULL;
        }
        Py_DECREF(entry);
    }
    return result;
}

static PyObject *has_numpy(PyObject *self, PyObject *unused)
{
    (void)self;
    (void)unused;
#ifdef RTC_WITH_NUMPY
    Py_RETURN_TRUE;
#else
    Py_RETURN_FALSE;
#endif
}

static PyMethodDef methods[] = {
    {"install", install, METH_NOARGS, "Start counting: wrap the three allocator domains."},
    {"uninstall", uninstall, METH_NOARGS, "Stop counting: restore the previous allocators."},
    {"installed", is_installed, METH_NOARGS, "True while the counters are installed."},
    {"reset", reset, METH_NOARGS, "Set every counter to zero."},
    {"counts", get_counts, METH_NOARGS,
     "{domain: (allocations, resizes, frees, bytes)} for raw, mem, obj and numpy."},
    {"has_numpy", has_numpy, METH_NOARGS,
     "True when built with NumPy's headers (array buffers are counted)."},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_alloccount",
    "Exact allocation counts: CPython's allocator domains and NumPy's data memory.", -1,
    methods, NULL, NULL, NULL, NULL,
};

PyMODINIT_FUNC PyInit__alloccount(void)
{
#ifdef RTC_WITH_NUMPY
    import_array();
#endif
    return PyModule_Create(&module);
}
