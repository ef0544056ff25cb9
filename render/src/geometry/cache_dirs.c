/* The cache's folders on disk (cache_dirs.h). */
#include "geometry/cache_dirs.h"

#include <dirent.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#define DIRMAX 4000  /* longest cache folder name (as cache_build.c) */
#define PATHMAX 4200 /* a folder name and a file name in it */

/* Removes the files of a flat folder, then the folder. */
void vr_cache_remove_flat(const char *dir) {
  DIR *d = opendir(dir);
  if (d) {
    struct dirent *e;
    char p[PATHMAX];
    while ((e = readdir(d)))
      if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) {
        snprintf(p, sizeof p, "%s/%s", dir, e->d_name);
        unlink(p);
      }
    closedir(d);
  }
  rmdir(dir);
}

/* Folders an interrupted build left beside dir (dir.tmp-PID, dir.old-PID):
 * the caller holds the cache's lock, so no other build is under way and
 * they are all stale. */
void vr_cache_remove_leftovers(const char *dir) {
  char parent[DIRMAX], prefix[DIRMAX + 8];
  snprintf(parent, sizeof parent, "%s", dir);
  char *slash = strrchr(parent, '/');
  const char *base = slash ? slash + 1 : parent;
  snprintf(prefix, sizeof prefix, "%s.", base);
  if (slash) *slash = '\0';
  DIR *d = opendir(slash ? parent : ".");
  if (!d) return;
  struct dirent *e;
  size_t np = strlen(prefix);
  while ((e = readdir(d))) {
    if (strncmp(e->d_name, prefix, np) || (strncmp(e->d_name + np, "tmp-", 4) &&
                                           strncmp(e->d_name + np, "old-", 4)))
      continue;
    char p[DIRMAX + 300];
    snprintf(p, sizeof p, "%s/%s", slash ? parent : ".", e->d_name);
    vr_cache_remove_flat(p);
  }
  closedir(d);
}
