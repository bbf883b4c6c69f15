/* A failing disk, on demand, for the command-line tests (LD_PRELOAD=libsimpli_fault_injection.so).
 * Opening for writing a file whose path ends in $SIMPLI_FAULT_PATH fails with ENOSPC (as on a full
 * disk), or, with SIMPLI_FAULT_ACTION=kill, kills the process with SIGKILL at that moment. Every
 * other open goes to the C library unchanged. Covers open, open64, openat, openat64, creat,
 * fopen, fopen64: what libtiff, libjpeg (through OpenCV) and the C++ streams use. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>

static int is_target(const char* path) {
  const char* suffix = getenv("SIMPLI_FAULT_PATH");
  if (!suffix || !*suffix || !path)
    return 0;
  const size_t n = strlen(path), m = strlen(suffix);
  return n >= m && strcmp(path + n - m, suffix) == 0;
}

static int writes(int flags) {
  return (flags & (O_WRONLY | O_RDWR | O_CREAT | O_TRUNC)) != 0;
}

static int mode_writes(const char* mode) {
  return mode && (strchr(mode, 'w') || strchr(mode, 'a') || strchr(mode, '+'));
}

/* The fault: -1 with errno = ENOSPC, or SIGKILL. */
static int fault(void) {
  const char* action = getenv("SIMPLI_FAULT_ACTION");
  if (action && strcmp(action, "kill") == 0)
    raise(SIGKILL);
  errno = ENOSPC;
  return -1;
}

static mode_t mode_arg(int flags, va_list ap) {
  return (flags & (O_CREAT | O_TMPFILE)) ? (mode_t)va_arg(ap, int) : 0;
}

#define REAL(name, type) ((type)dlsym(RTLD_NEXT, #name))

int open(const char* path, int flags, ...) {
  va_list ap;
  va_start(ap, flags);
  const mode_t mode = mode_arg(flags, ap);
  va_end(ap);
  if (writes(flags) && is_target(path))
    return fault();
  return REAL(open, int (*)(const char*, int, ...))(path, flags, mode);
}

int open64(const char* path, int flags, ...) {
  va_list ap;
  va_start(ap, flags);
  const mode_t mode = mode_arg(flags, ap);
  va_end(ap);
  if (writes(flags) && is_target(path))
    return fault();
  return REAL(open64, int (*)(const char*, int, ...))(path, flags, mode);
}

int openat(int dir, const char* path, int flags, ...) {
  va_list ap;
  va_start(ap, flags);
  const mode_t mode = mode_arg(flags, ap);
  va_end(ap);
  if (writes(flags) && is_target(path))
    return fault();
  return REAL(openat, int (*)(int, const char*, int, ...))(dir, path, flags, mode);
}

int openat64(int dir, const char* path, int flags, ...) {
  va_list ap;
  va_start(ap, flags);
  const mode_t mode = mode_arg(flags, ap);
  va_end(ap);
  if (writes(flags) && is_target(path))
    return fault();
  return REAL(openat64, int (*)(int, const char*, int, ...))(dir, path, flags, mode);
}

int creat(const char* path, mode_t mode) {
  if (is_target(path))
    return fault();
  return REAL(creat, int (*)(const char*, mode_t))(path, mode);
}

FILE* fopen(const char* path, const char* mode) {
  if (mode_writes(mode) && is_target(path)) {
    fault();
    return NULL;
  }
  return REAL(fopen, FILE * (*)(const char*, const char*))(path, mode);
}

FILE* fopen64(const char* path, const char* mode) {
  if (mode_writes(mode) && is_target(path)) {
    fault();
    return NULL;
  }
  return REAL(fopen64, FILE * (*)(const char*, const char*))(path, mode);
}
