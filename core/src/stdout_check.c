/* Standard output checked when a tool exits (vr/args.h): a write that
 * failed (a full disk, /dev/full, a closed pipe with SIGPIPE ignored) is a
 * failure of the tool, not a silent empty file.  The check runs from
 * atexit, after main has returned its status: on a failed write it says so
 * on stderr and ends the process with status 1 (as gnulib's close_stdout
 * does). */
#include "vr/args.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const char *checked_tool;

static void check_stdout(void) {
  errno = 0;
  int flushed = fflush(stdout);
  int e = errno;
  if (flushed == 0 && !ferror(stdout)) return;
  /* fflush reports its own errno; an earlier failed write left only the
   * error flag. */
  if (flushed != 0 && e)
    fprintf(stderr, "%s: cannot write standard output: %s\n", checked_tool, strerror(e));
  else
    fprintf(stderr, "%s: cannot write standard output: a write failed (disk full or output "
                    "closed?)\n", checked_tool);
  fflush(stderr);
  _exit(1);
}

void vr_stdout_check_at_exit(const char *tool) {
  if (checked_tool) return;
  checked_tool = tool ? tool : "vr";
  atexit(check_stdout);
}
