/* A progress bar with an ETA on stderr, drawn only when stderr is a
 * terminal (logs and CI stay clean).  One thread updates a given bar; the
 * redraw is throttled to ten times a second. */
#ifndef VR_PROGRESS_H
#define VR_PROGRESS_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vr_progress vr_progress;

/* total > 0 units of work; label is copied.  Returns NULL (a valid "silent"
 * bar: every call below accepts NULL) when stderr is not a terminal. */
vr_progress *vr_progress_create(const char *label, size_t total);
void vr_progress_update(vr_progress *p, size_t done);
/* Draws the final state, ends the line and frees the bar. */
void vr_progress_finish(vr_progress *p);

/* The text of one bar line for done/total after elapsed seconds, without
 * drawing it (for tests and for logs): "label [#####     ]  50%  ETA 0:05". */
void vr_progress_format(char *buf, size_t size, const char *label, size_t done, size_t total,
                        double elapsed_s, int width);

#ifdef __cplusplus
}
#endif
#endif
