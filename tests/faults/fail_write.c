/* LD_PRELOAD library for the fault cases write_one_rank, write_stalls_one_rank and
 * write_refused: pwrite(), pwrite64(), pwritev() and write() to a file whose path ends in
 * FAIL_WRITE_SUFFIX (or in one of its ':'-separated suffixes) fail with ENOSPC in the process
 * whose OMPI_COMM_WORLD_RANK is FAIL_WRITE_RANK ("any": every process), after FAIL_WRITE_AFTER
 * such writes that succeed (default 0): one rank's share of a collective write meets a full
 * disk or quota. With FAIL_WRITE_HANG_SECONDS set, the first such write instead waits that long
 * and then goes through, as do the rest (a filesystem that stops answering
 * one node; a merge held while a test sends it a signal). FAIL_WRITE_ERRNO names
 * another error: EDQUOT (a quota) or EIO (a failing disk). */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <sys/uio.h>
#include <unistd.h>

static int should_fail(int fd) {
    const char* suffix = getenv("FAIL_WRITE_SUFFIX");
    const char* rank = getenv("OMPI_COMM_WORLD_RANK");
    const char* wanted = getenv("FAIL_WRITE_RANK");
    if (!suffix || !wanted || (strcmp(wanted, "any") != 0 && (!rank || strcmp(rank, wanted) != 0))) return 0;
    char link[64], path[4096];
    snprintf(link, sizeof link, "/proc/self/fd/%d", fd);
    const ssize_t n = readlink(link, path, sizeof path - 1);
    if (n < 0) return 0;
    path[n] = '\0';
    int matches = 0;
    for (const char* from = suffix; *from && !matches;) {
        const char* colon = strchr(from, ':');
        const size_t m = colon ? (size_t)(colon - from) : strlen(from);
        matches = m > 0 && (size_t)n >= m && strncmp(path + n - m, from, m) == 0;
        from += colon ? m + 1 : m;
    }
    if (!matches) return 0;
    static int passed = 0; /* matching writes let through so far */
    const char* after = getenv("FAIL_WRITE_AFTER");
    if (passed++ < (after ? atoi(after) : 0)) return 0;
    const char* hang = getenv("FAIL_WRITE_HANG_SECONDS");
    if (hang) {
        static int waited = 0; /* the first such write waits, through signals that are caught */
        if (!waited++)
            for (unsigned left = (unsigned)atoi(hang); left > 0;) left = sleep(left);
        return 0;
    }
    const char* name = getenv("FAIL_WRITE_ERRNO");
    errno = !name                        ? ENOSPC
            : strcmp(name, "EDQUOT") == 0 ? EDQUOT
            : strcmp(name, "EIO") == 0    ? EIO
                                          : ENOSPC;
    return 1;
}

ssize_t pwrite(int fd, const void* buffer, size_t count, off_t offset) {
    if (should_fail(fd)) return -1;
    ssize_t (*next)(int, const void*, size_t, off_t) = dlsym(RTLD_NEXT, "pwrite");
    return next(fd, buffer, count, offset);
}

ssize_t pwrite64(int fd, const void* buffer, size_t count, off_t offset) {
    if (should_fail(fd)) return -1;
    ssize_t (*next)(int, const void*, size_t, off_t) = dlsym(RTLD_NEXT, "pwrite64");
    return next(fd, buffer, count, offset);
}

ssize_t pwritev(int fd, const struct iovec* vectors, int count, off_t offset) {
    if (should_fail(fd)) return -1;
    ssize_t (*next)(int, const struct iovec*, int, off_t) = dlsym(RTLD_NEXT, "pwritev");
    return next(fd, vectors, count, offset);
}

ssize_t write(int fd, const void* buffer, size_t count) {
    if (should_fail(fd)) return -1;
    ssize_t (*next)(int, const void*, size_t) = dlsym(RTLD_NEXT, "write");
    return next(fd, buffer, count);
}
