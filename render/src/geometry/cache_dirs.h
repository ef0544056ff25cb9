/* The geometry cache's folders on disk: removing a flat folder (a cache
 * of one S, a build's temporary folder) and the folders an interrupted
 * build left beside one.  Private to render/. */
#ifndef VR_CACHE_DIRS_H
#define VR_CACHE_DIRS_H

/* Removes the files of a flat folder, then the folder (quietly: what is
 * already gone is fine). */
void vr_cache_remove_flat(const char *dir);
/* Removes dir.tmp-PID and dir.old-PID beside dir; the caller holds the
 * cache's lock, so no other build is under way and they are stale. */
void vr_cache_remove_leftovers(const char *dir);

#endif
