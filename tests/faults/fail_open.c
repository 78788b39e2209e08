/* LD_PRELOAD library for the fault case open_one_rank: open() and openat() of a path ending
 * in FAIL_OPEN_SUFFIX fail with errno FAIL_OPEN_ERRNO (default EACCES) in the process whose
 * OMPI_COMM_WORLD_RANK is FAIL_OPEN_RANK, so that one rank of a job cannot open a file the
 * others can (permissions, no descriptors left, a mount another node lacks). The first
 * FAIL_OPEN_AFTER such opens (default 0) succeed: a failure at a later stage of the run.
 * For the fault case archive_changed_before_lock, in any process: an open() that creates a
 * path ending in HOLD_CREATE_SUFFIX (O_CREAT) first makes the file HOLD_CREATE_UNTIL.waiting
 * and waits until HOLD_CREATE_UNTIL exists (at most 120 s): the test acts in between.
 * For the fault case rename_fails_at_checkpoint, in any process: rename() onto a path ending in
 * FAIL_RENAME_SUFFIX fails with EIO once FAIL_RENAME_AFTER such renames (default 0) have
 * succeeded (a filesystem that stops taking a checkpoint's last step). */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

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

/* Waits as the header says when `path` and `flags` are the ones to hold. */
static void hold_create(const char* path, int flags) {
    const char* suffix = getenv("HOLD_CREATE_SUFFIX");
    const char* until = getenv("HOLD_CREATE_UNTIL");
    if (!suffix || !until || !path || !(flags & O_CREAT)) return;
    const size_t n = strlen(path), m = strlen(suffix);
    if (n < m || strcmp(path + n - m, suffix) != 0) return;
    char waiting[4096];
    snprintf(waiting, sizeof waiting, "%s.waiting", until);
    int (*real)(const char*, int, ...) = (int (*)(const char*, int, ...))dlsym(RTLD_NEXT, "open");
    const int fd = real(waiting, O_WRONLY | O_CREAT | O_CLOEXEC, 0644);
    if (fd >= 0) close(fd);
    for (int k = 0; k < 6000 && access(until, F_OK) != 0; ++k) usleep(20000);
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
        hold_create(path, flags);                                                    \
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
        hold_create(path, flags);                                                    \
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

int rename(const char* from, const char* to) {
    const char* suffix = getenv("FAIL_RENAME_SUFFIX");
    if (suffix && to) {
        const size_t n = strlen(to), m = strlen(suffix);
        static int passed = 0; /* matching renames let through so far */
        const char* after = getenv("FAIL_RENAME_AFTER");
        if (n >= m && strcmp(to + n - m, suffix) == 0 && passed++ >= (after ? atoi(after) : 0)) {
            errno = EIO;
            return -1;
        }
    }
    int (*real)(const char*, const char*) = (int (*)(const char*, const char*))dlsym(RTLD_NEXT, "rename");
    return real(from, to);
}
