/* Whole-or-nothing output files: see vr/atomic_file.h. */
#define _GNU_SOURCE /* sync_file_range */
#include "vr/atomic_file.h"

#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

vr_status vr_atomic_file_open(vr_atomic_file *f, const char *path, vr_error *err) {
  memset(f, 0, sizeof *f);
  if (strlen(path) >= sizeof f->path)
    return vr_error_set(err, VR_E_ARG, "output path too long: %.64s...", path);
  strcpy(f->path, path);
  snprintf(f->tmp, sizeof f->tmp, "%s.tmp-XXXXXX", path);
  int fd = mkstemp(f->tmp);
  if (fd < 0)
    return vr_error_at(err, VR_E_IO, path, 0, 0, "cannot create a temporary file beside it: %s",
                       strerror(errno));
  /* mkstemp creates 0600; outputs are meant to be shared like any other file. */
  fchmod(fd, 0644);
  f->fp = fdopen(fd, "w");
  if (!f->fp) {
    close(fd);
    unlink(f->tmp);
    return vr_error_at(err, VR_E_IO, path, 0, 0, "cannot open: %s", strerror(errno));
  }
  return VR_OK;
}

vr_status vr_atomic_file_commit(vr_atomic_file *f, vr_error *err) {
  int bad = ferror(f->fp) || fflush(f->fp) != 0 || fsync(fileno(f->fp)) != 0;
  int saved = errno;
  if (fclose(f->fp) != 0 && !bad) {
    bad = 1;
    saved = errno;
  }
  f->fp = NULL;
  if (bad || rename(f->tmp, f->path) != 0) {
    if (!bad) saved = errno;
    unlink(f->tmp);
    return vr_error_at(err, VR_E_IO, f->path, 0, 0, "write failed: %s", strerror(saved));
  }
  return VR_OK;
}

void vr_atomic_file_writeback(vr_atomic_file *f, long long end) {
  const long long step = 16LL << 20;
  if (!f->fp || end - f->queued < step) return;
  if (fflush(f->fp) != 0) return;
#ifdef SYNC_FILE_RANGE_WRITE
  sync_file_range(fileno(f->fp), (off_t)f->queued, (off_t)(end - f->queued), SYNC_FILE_RANGE_WRITE);
#endif
  f->queued = end;
}

void vr_atomic_file_abort(vr_atomic_file *f) {
  if (f->fp) fclose(f->fp);
  f->fp = NULL;
  if (f->tmp[0]) unlink(f->tmp);
}
