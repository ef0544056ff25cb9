/* Output paths checked against the run's inputs (vr/out_guard.h). */
#include "vr/out_guard.h"

#include <errno.h>
#include <stdbool.h>
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

static const char *const JOURNAL[] = {"-wal", "-shm", "-journal"};

void vr_out_guard_database(vr_out_guard *g, const char *db_path) {
  if (!db_path || !*db_path) return;
  vr_out_guard_input(g, db_path, "the material database");
  struct stat st;
  g->has_db = 1;
  snprintf(g->db_path, sizeof g->db_path, "%s", db_path);
  if (stat(db_path, &st) == 0) {
    g->db_dev = (unsigned long long)st.st_dev;
    g->db_ino = (unsigned long long)st.st_ino;
  } else {
    g->db_dev = g->db_ino = 0; /* made by this run: compared by place and name */
  }
  for (int i = 0; i < 3; i++) {
    char p[4200];
    snprintf(p, sizeof p, "%s%s", db_path, JOURNAL[i]);
    vr_out_guard_input(g, p, "the material database's journal");
  }
}

void vr_path_folder(const char *path, char *dir, size_t cap) {
  const char *slash = strrchr(path, '/');
  if (!slash) snprintf(dir, cap, ".");
  else if (slash == path) snprintf(dir, cap, "/");
  else snprintf(dir, cap, "%.*s", (int)(slash - path), path);
}

/* Two paths to files that need not exist: the same folder (by device and
 * inode) and the same name in it. */
static bool same_place(const char *a, const char *b) {
  const char *na = strrchr(a, '/'), *nb = strrchr(b, '/');
  na = na ? na + 1 : a;
  nb = nb ? nb + 1 : b;
  if (strcmp(na, nb)) return false;
  char da[4096], db[4096];
  vr_path_folder(a, da, sizeof da);
  vr_path_folder(b, db, sizeof db);
  struct stat sa, sb;
  return stat(da, &sa) == 0 && stat(db, &sb) == 0 && sa.st_dev == sb.st_dev &&
         sa.st_ino == sb.st_ino;
}

vr_status vr_out_guard_check(const vr_out_guard *g, const char *path, const char *option,
                             vr_error *err) {
  if (!option) option = "output";
  if (!path || !*path)
    return vr_error_set(err, VR_E_ARG, "%s: an empty file name is not an output", option);
  if (strcmp(path, "-") == 0) return VR_OK; /* standard output */
  struct stat st;
  /* The database's journal names: the output's name less a journal
   * suffix is the database itself. */
  for (int i = 0; g && g->has_db && i < 3; i++) {
    size_t n = strlen(path), m = strlen(JOURNAL[i]);
    if (n <= m || strcmp(path + n - m, JOURNAL[i])) continue;
    char stem[4200];
    snprintf(stem, sizeof stem, "%.*s", (int)(n - m), path);
    bool same = g->db_ino ? stat(stem, &st) == 0 &&
                                (unsigned long long)st.st_dev == g->db_dev &&
                                (unsigned long long)st.st_ino == g->db_ino
                          : same_place(stem, g->db_path);
    if (same)
      return vr_error_set(err, VR_E_ARG,
                          "%s %s: is the material database's journal of this run (%s%s); "
                          "refusing to overwrite it, choose another output path",
                          option, path, g->db_path, JOURNAL[i]);
  }
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
