/* LD_PRELOAD library for the fault case open_one_rank: open() and openat() of a path ending
 * in FAIL_OPEN_SUFFIX fail with errno FAIL_OPEN_ERRNO (default EACCES) in the process whose
 * OMPI_COMM_WORLD_RANK is FAIL_OPEN_RANK, so that one rank of a job cannot open a file the
 * others can (permissions, no descriptors left, a mount another node lacks). The first
 * FAIL_OPEN_AFTER such opens (default 0) succeed: a failure at a later stage of the run. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

static int should_fail(const char* path) {
    const char* suffix = getenv("FAIL_OPEN_SUFFIX");
    const char* rank = getenv("OMPI_COMM_WORLD_RANK");
    const char* wanted = getenv("FAIL_OPEN_RANK");
    if (!suffix || !rank || !wanted || !path || strcmp(rank, wanted) != 0) return 0;
    const size_t n = strlen(path), m = strlen(suffix);
    if (n < m || strcmp(path + n - m, suffix) != 0) return 0;
    static int passed = 0; /* matching opens let through so far */
    const char* after = getenv("FAIL_OPEN_AFTER");
    return passed++ >= (after ? atoi(after) : 0);
}

static int injected_errno(void) {
    const char* e = getenv("FAIL_OPEN_ERRNO");
    return e ? atoi(e) : EACCES;
}

/* The mode argument exists only with O_CREAT or O_TMPFILE. */
#define MODE_OF(flags)                                 \
    mode_t mode = 0;                                   \
    if ((flags) & (O_CREAT | O_TMPFILE)) {             \
        va_list ap;                                    \
        va_start(ap, flags);                           \
        mode = (mode_t)va_arg(ap, int);                \
        va_end(ap);                                    \
    }

#define WRAP_OPEN(name)                                                              \
    int name(const char* path, int flags, ...) {                                     \
        MODE_OF(flags)                                                               \
        if (should_fail(path)) {                                                     \
            errno = injected_errno();                                                \
            return -1;                                                               \
        }                                                                            \
        int (*real)(const char*, int, ...) = (int (*)(const char*, int, ...))dlsym(RTLD_NEXT, #name); \
        return real(path, flags, mode);                                              \
    }

#define WRAP_OPENAT(name)                                                            \
    int name(int dir, const char* path, int flags, ...) {                            \
        MODE_OF(flags)                                                               \
        if (should_fail(path)) {                                                     \
            errno = injected_errno();                                                \
            return -1;                                                               \
        }                                                                            \
        int (*real)(int, const char*, int, ...) = (int (*)(int, const char*, int, ...))dlsym(RTLD_NEXT, #name); \
        return real(dir, path, flags, mode);                                         \
    }

WRAP_OPEN(open)
WRAP_OPEN(open64)
WRAP_OPENAT(openat)
WRAP_OPENAT(openat64)
