/* fault_shim.c — an LD_PRELOAD library that makes file writes fail the way a full disk or a
 * killed process does, for the fault-injection tests (tests/test_faults.cpp) where a real full
 * file system (a small tmpfs) cannot be mounted (the tests do not run as root).
 *
 *   CLHAIR_FAULT_FULL_DIR=/path   writes to files under /path fail with ENOSPC once
 *   CLHAIR_FAULT_FULL_BYTES=N     N bytes (default 0) have been written to them in this process
 *   CLHAIR_FAULT_FSYNC_EIO=1      fsync of a file under CLHAIR_FAULT_FULL_DIR fails with EIO
 *   CLHAIR_FAULT_KILL_AT_RENAME=/path  renaming a file under /path whose name starts with
 *                                 ".tmp-" (clhair's temporaries) kills the process with SIGKILL
 *                                 first: a run killed between writing and renaming
 *
 * The file of a descriptor is found through /proc/self/fd. Nothing else changes.
 */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <limits.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <sys/uio.h>
#include <unistd.h>

static long long written_under_dir = 0;

static int under_full_dir(int fd) {
  const char* dir = getenv("CLHAIR_FAULT_FULL_DIR");
  if (!dir || !*dir) return 0;
  char link[64], target[PATH_MAX];
  snprintf(link, sizeof link, "/proc/self/fd/%d", fd);
  const ssize_t n = readlink(link, target, sizeof target - 1);
  if (n <= 0) return 0;
  target[n] = '\0';
  const size_t len = strlen(dir);
  return strncmp(target, dir, len) == 0 && (target[len] == '/' || target[len] == '\0');
}

/* How many of `count` bytes may still be written to `fd`; -1 with errno ENOSPC when none. */
static ssize_t allowance(int fd, size_t count) {
  if (!under_full_dir(fd)) return (ssize_t)count;
  const char* b = getenv("CLHAIR_FAULT_FULL_BYTES");
  const long long budget = b ? atoll(b) : 0;
  const long long left = budget - written_under_dir;
  if (left <= 0) {
    errno = ENOSPC;
    return -1;
  }
  return (ssize_t)((long long)count < left ? (long long)count : left);
}

ssize_t write(int fd, const void* buf, size_t count) {
  static ssize_t (*real)(int, const void*, size_t) = NULL;
  if (!real) real = (ssize_t(*)(int, const void*, size_t))dlsym(RTLD_NEXT, "write");
  const ssize_t allowed = allowance(fd, count);
  if (allowed < 0) return -1;
  const ssize_t n = real(fd, buf, (size_t)allowed);
  if (n > 0 && under_full_dir(fd)) written_under_dir += n;
  return n;
}

ssize_t pwrite(int fd, const void* buf, size_t count, off_t offset) {
  static ssize_t (*real)(int, const void*, size_t, off_t) = NULL;
  if (!real) real = (ssize_t(*)(int, const void*, size_t, off_t))dlsym(RTLD_NEXT, "pwrite");
  const ssize_t allowed = allowance(fd, count);
  if (allowed < 0) return -1;
  const ssize_t n = real(fd, buf, (size_t)allowed, offset);
  if (n > 0 && under_full_dir(fd)) written_under_dir += n;
  return n;
}

ssize_t writev(int fd, const struct iovec* iov, int iovcnt) {
  static ssize_t (*real)(int, const struct iovec*, int) = NULL;
  if (!real) real = (ssize_t(*)(int, const struct iovec*, int))dlsym(RTLD_NEXT, "writev");
  size_t total = 0;
  for (int i = 0; i < iovcnt; ++i) total += iov[i].iov_len;
  if (allowance(fd, total) != (ssize_t)total) {
    errno = ENOSPC;
    return -1;
  }
  const ssize_t n = real(fd, iov, iovcnt);
  if (n > 0 && under_full_dir(fd)) written_under_dir += n;
  return n;
}

int fsync(int fd) {
  static int (*real)(int) = NULL;
  if (!real) real = (int (*)(int))dlsym(RTLD_NEXT, "fsync");
  const char* eio = getenv("CLHAIR_FAULT_FSYNC_EIO");
  if (eio && strcmp(eio, "1") == 0 && under_full_dir(fd)) {
    errno = EIO;
    return -1;
  }
  return real(fd);
}

int rename(const char* from, const char* to) {
  static int (*real)(const char*, const char*) = NULL;
  if (!real) real = (int (*)(const char*, const char*))dlsym(RTLD_NEXT, "rename");
  const char* dir = getenv("CLHAIR_FAULT_KILL_AT_RENAME");
  if (dir && *dir) {
    const char* base = strrchr(from, '/');
    base = base ? base + 1 : from;
    char resolved[PATH_MAX];
    const size_t len = strlen(dir);
    if (strncmp(base, ".tmp-", 5) == 0 && realpath(from, resolved) &&
        strncmp(resolved, dir, len) == 0 && resolved[len] == '/')
      raise(SIGKILL);
  }
  return real(from, to);
}
