/* Output paths checked against the run's inputs (vr/out_guard.h). */
#include "vr/out_guard.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

void vr_out_guard_init(vr_out_guard *g) { memset(g, 0, sizeof *g); }

void vr_out_guard_input(vr_out_guard *g, const char *path, const char *role) {
  struct stat st;
  if (!path || !*path || g->n >= VR_OUT_GUARD_MAX || stat(path, &st) != 0) return;
  g->in[g->n].dev = (unsigned long long)st.st_dev;
  g->in[g->n].ino = (unsigned long long)st.st_ino;
  snprintf(g->in[g->n].role, sizeof g->in[g->n].role, "%s", role ? role : "an input");
  snprintf(g->in[g->n].path, sizeof g->in[g->n].path, "%.511s", path);
  g->n++;
}

void vr_out_guard_database(vr_out_guard *g, const char *db_path) {
  if (!db_path || !*db_path) return;
  vr_out_guard_input(g, db_path, "the material database");
  static const char *const companion[] = {"-wal", "-shm", "-journal"};
  for (int i = 0; i < 3; i++) {
    char p[4200];
    snprintf(p, sizeof p, "%s%s", db_path, companion[i]);
    vr_out_guard_input(g, p, "the material database's journal");
  }
}

void vr_path_folder(const char *path, char *dir, size_t cap) {
  const char *slash = strrchr(path, '/');
  if (!slash) snprintf(dir, cap, ".");
  else if (slash == path) snprintf(dir, cap, "/");
  else snprintf(dir, cap, "%.*s", (int)(slash - path), path);
}

vr_status vr_out_guard_check(const vr_out_guard *g, const char *path, const char *option,
                             vr_error *err) {
  if (!option) option = "output";
  if (!path || !*path)
    return vr_error_set(err, VR_E_ARG, "%s: an empty file name is not an output", option);
  if (strcmp(path, "-") == 0) return VR_OK; /* standard output */
  struct stat st;
  if (stat(path, &st) == 0) {
    if (S_ISDIR(st.st_mode))
      return vr_error_set(err, VR_E_ARG, "%s %s: is a folder, not a file", option, path);
    for (int i = 0; g && i < g->n; i++)
      if (g->in[i].dev == (unsigned long long)st.st_dev &&
          g->in[i].ino == (unsigned long long)st.st_ino)
        return vr_error_set(err, VR_E_ARG,
                            "%s %s: is %s of this run (%s); refusing to overwrite it, "
                            "choose another output path",
                            option, path, g->in[i].role, g->in[i].path);
  }
  char dir[4096];
  vr_path_folder(path, dir, sizeof dir);
  if (stat(dir, &st) != 0)
    return vr_error_set(err, VR_E_IO, "%s %s: the folder %s does not exist", option, path, dir);
  if (!S_ISDIR(st.st_mode))
    return vr_error_set(err, VR_E_IO, "%s %s: %s is not a folder", option, path, dir);
  if (access(dir, W_OK | X_OK) != 0)
    return vr_error_set(err, VR_E_IO, "%s %s: cannot write in the folder %s: %s", option, path,
                        dir, strerror(errno));
  return VR_OK;
}

vr_status vr_out_guard_distinct(const char *a, const char *option_a, const char *b,
                                const char *option_b, vr_error *err) {
  if (!a || !b || strcmp(a, "-") == 0 || strcmp(b, "-") == 0) return VR_OK;
  int same = strcmp(a, b) == 0;
  struct stat sa, sb;
  if (!same && stat(a, &sa) == 0 && stat(b, &sb) == 0)
    same = sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
  if (same)
    return vr_error_set(err, VR_E_ARG, "%s and %s name the same file (%s); give each its own",
                        option_a, option_b, a);
  return VR_OK;
}
