/* A render's files as one set (vr/film.h): written into a staging folder
 * PREFIX.partial.<pid> beside the outputs, moved into place one by one, and
 * then described by PREFIX.manifest.json (the run's id, each file's name,
 * size and SHA-256), written atomically and last.
 *
 * Renames of several files cannot be one atomic step, so a process killed
 * between them leaves new files beside old ones.  The manifest makes that
 * detectable instead: until the new manifest replaces the old one, the old
 * manifest describes the old files, and any new file beside it differs from
 * what it lists (vr_film_verify).  A killed run's staging folder is named by
 * its process id, so the next run can tell it from a live run's and remove
 * it (vr_film_clean_stale). */
#include "film/film_set.h"
#include "vr/out_guard.h"

#include <dirent.h>
#include <errno.h>
#include <limits.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "vr/atomic_file.h"
#include "vr/film.h"
#include "vr/json.h"
#include "vr/sha256.h"
#include "vr/version.h"

/* ---- names ---- */

/* a + b + c in a new string; NULL when out of memory. */
static char *cat3(const char *a, const char *b, const char *c) {
  size_t n = strlen(a) + strlen(b) + strlen(c) + 1;
  char *s = malloc(n);
  if (s) snprintf(s, n, "%s%s%s", a, b, c);
  return s;
}

static const char *base_of(const char *path) {
  const char *slash = strrchr(path, '/');
  return slash ? slash + 1 : path;
}

static bool same_folder(const char *a, const char *b) {
  char da[PATH_MAX], db[PATH_MAX], ra[PATH_MAX], rb[PATH_MAX];
  vr_path_folder(a, da, sizeof da);
  vr_path_folder(b, db, sizeof db);
  if (!realpath(da, ra) || !realpath(db, rb)) return !strcmp(da, db);
  return !strcmp(ra, rb);
}

/* ".partial.<pid>" of this process. */
static void partial_suffix(char out[40]) { snprintf(out, 40, ".partial.%ld", (long)getpid()); }

static bool remove_folder(const char *dir);

/* ---- staging ---- */

vr_status film_set_begin(vr_film_set *s, const char *prefix, vr_error *err) {
  memset(s, 0, sizeof *s);
  char suffix[40];
  partial_suffix(suffix);
  s->prefix = strdup(prefix);
  s->dir = cat3(prefix, suffix, "");
  if (!s->prefix || !s->dir) {
    film_set_abort(s);
    return vr_error_set(err, VR_E_NOMEM, "out of memory");
  }
  /* A folder of this name already is a previous holder of this process id's
   * (ids restart in every container): dead, since the id is now ours. */
  if (mkdir(s->dir, 0755) != 0 && (errno != EEXIST || !remove_folder(s->dir) ||
                                   mkdir(s->dir, 0755) != 0)) {
    vr_status st = vr_error_set(err, VR_E_IO,
                                "%s: cannot make the staging folder beside the outputs: %s",
                                s->dir, strerror(errno));
    film_set_abort(s);
    return st;
  }
  s->made_dir = true;
  return VR_OK;
}

static vr_status add(vr_film_set *s, char *target, char *stage, vr_film_staged **out, vr_error *err) {
  if (!target || !stage || s->n >= FILM_SET_MAX) {
    free(target), free(stage);
    if (s->n >= FILM_SET_MAX) return vr_error_set(err, VR_E_ARG, "film: too many outputs");
    return vr_error_set(err, VR_E_NOMEM, "out of memory");
  }
  vr_film_staged *g = &s->f[s->n++];
  g->target = target, g->stage = stage, g->renamed = false;
  *out = g;
  return VR_OK;
}

vr_status film_set_add(vr_film_set *s, const char *suffix, vr_film_staged **out, vr_error *err) {
  char *target = cat3(s->prefix, suffix, "");
  char *stage = target ? cat3(s->dir, "/", base_of(target)) : NULL;
  return add(s, target, stage, out, err);
}

vr_status film_set_add_path(vr_film_set *s, const char *target, vr_film_staged **out, vr_error *err) {
  size_t np = strlen(s->prefix);
  bool clash = !strncmp(target, s->prefix, np) && !strcmp(target + np, ".manifest.json");
  for (int i = 0; i < s->n && !clash; i++) clash = !strcmp(s->f[i].target, target);
  if (clash)
    return vr_error_set(err, VR_E_ARG, "%s: is already one of the set's files", target);
  char suffix[40];
  partial_suffix(suffix);
  char *stage = same_folder(target, s->prefix) ? cat3(s->dir, "/", base_of(target))
                                               : cat3(target, suffix, "");
  return add(s, strdup(target), stage, out, err);
}

static void release(vr_film_set *s) {
  for (int i = 0; i < s->n; i++) free(s->f[i].target), free(s->f[i].stage);
  s->n = 0;
  if (s->made_dir) rmdir(s->dir);
  s->made_dir = false;
  free(s->dir), free(s->prefix);
  s->dir = s->prefix = NULL;
}

void film_set_abort(vr_film_set *s) {
  for (int i = 0; i < s->n; i++) unlink(s->f[i].renamed ? s->f[i].target : s->f[i].stage);
  release(s);
}

/* ---- the manifest ---- */

/* How the manifest names a file: its name when it lies beside the
 * manifest, else its absolute path. */
static void manifest_name(const char *manifest, const char *target, char *out, size_t cap) {
  if (same_folder(manifest, target)) {
    snprintf(out, cap, "%s", base_of(target));
    return;
  }
  char dir[PATH_MAX], real[PATH_MAX];
  vr_path_folder(target, dir, sizeof dir);
  if (target[0] != '/' && realpath(dir, real)) snprintf(out, cap, "%s/%s", real, base_of(target));
  else snprintf(out, cap, "%s", target);
}

typedef struct vr_file_sum {
  long long bytes;
  char sha[65];
} vr_file_sum;

static vr_status sum_file(const char *path, vr_file_sum *out, vr_error *err) {
  struct stat st;
  if (stat(path, &st) != 0)
    return vr_error_set(err, VR_E_IO, "%s: %s", path, strerror(errno));
  out->bytes = (long long)st.st_size;
  return vr_sha256_file(path, out->sha, err);
}

static vr_status write_manifest(const vr_film_set *s, const vr_file_sum *sums, const char *run_id,
                                vr_error *err) {
  char *path = cat3(s->prefix, ".manifest.json", "");
  if (!path) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  vr_atomic_file af;
  vr_status st = vr_atomic_file_open(&af, path, err);
  if (st) {
    free(path);
    return st;
  }
  FILE *f = af.fp;
  fputs("{\n  \"manifest\": \"vr-render output set\",\n  \"version\": ", f);
  vr_json_string(f, vr_version());
  fputs(",\n  \"run_id\": ", f);
  vr_json_string(f, run_id);
  fputs(",\n  \"files\": [", f);
  for (int i = 0; i < s->n; i++) {
    char name[PATH_MAX + 256];
    manifest_name(path, s->f[i].target, name, sizeof name);
    fputs(i ? ",\n    {\"name\": " : "\n    {\"name\": ", f);
    vr_json_string(f, name);
    fprintf(f, ", \"bytes\": %lld, \"sha256\": \"%s\"}", sums[i].bytes, sums[i].sha);
  }
  fputs(s->n ? "\n  ]\n}\n" : "]\n}\n", f);
  st = vr_atomic_file_commit(&af, err);
  free(path);
  return st;
}

vr_status film_set_commit(vr_film_set *s, const char *run_id, vr_error *err) {
  vr_file_sum sums[FILM_SET_MAX];
  vr_status st = VR_OK;
  for (int i = 0; i < s->n && !st; i++) st = sum_file(s->f[i].stage, &sums[i], err);
  /* From here until the manifest is replaced, files already moved differ
   * from what the old manifest lists: a mixed set is detectable. */
  for (int i = 0; i < s->n && !st; i++) {
    if (rename(s->f[i].stage, s->f[i].target) != 0) {
      st = vr_error_set(err, VR_E_IO, "%s: cannot move into place: %s", s->f[i].target,
                        strerror(errno));
      break;
    }
    s->f[i].renamed = true;
  }
  if (!st) st = write_manifest(s, sums, run_id, err);
  if (st) {
    film_set_abort(s);
    return st;
  }
  release(s);
  return VR_OK;
}

/* ---- the run's id ---- */

void vr_film_run_id(char out[VR_FILM_RUN_ID_MAX]) {
  struct timespec ts;
  clock_gettime(CLOCK_REALTIME, &ts);
  struct tm tm;
  gmtime_r(&ts.tv_sec, &tm);
  char when[32];
  strftime(when, sizeof when, "%Y%m%dT%H%M%SZ", &tm);
  unsigned long long r = (unsigned long long)ts.tv_nsec ^ ((unsigned long long)getpid() << 32);
  FILE *u = fopen("/dev/urandom", "rb");
  if (u) {
    if (fread(&r, sizeof r, 1, u) != 1) r ^= (unsigned long long)ts.tv_nsec;
    fclose(u);
  }
  snprintf(out, VR_FILM_RUN_ID_MAX, "%s-%ld-%08llx", when, (long)getpid(), r & 0xffffffffULL);
}

/* ---- leftovers of killed runs ---- */

/* "NAME.partial.<pid>" -> pid, else 0. */
static long partial_pid(const char *entry, const char *base) {
  size_t n = strlen(base);
  if (strncmp(entry, base, n) || strncmp(entry + n, ".partial.", 9)) return 0;
  const char *d = entry + n + 9;
  if (!*d) return 0;
  char *end;
  long pid = strtol(d, &end, 10);
  return *end || pid <= 0 ? 0 : pid;
}

static bool process_gone(long pid) {
  return pid != (long)getpid() && kill((pid_t)pid, 0) != 0 && errno == ESRCH;
}

/* Removes a staging folder's files, then the folder; false if anything stays. */
static bool remove_folder(const char *dir) {
  DIR *d = opendir(dir);
  if (!d) return false;
  struct dirent *e;
  while ((e = readdir(d))) {
    if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..")) continue;
    char *p = cat3(dir, "/", e->d_name);
    if (p) unlink(p);
    free(p);
  }
  closedir(d);
  return rmdir(dir) == 0;
}

size_t vr_film_clean_stale(const char *name, char *removed, size_t cap) {
  if (removed && cap) removed[0] = '\0';
  if (!name || !*name) return 0;
  char dir[PATH_MAX];
  vr_path_folder(name, dir, sizeof dir);
  const char *base = base_of(name);
  DIR *d = opendir(dir);
  if (!d) return 0;
  size_t count = 0;
  struct dirent *e;
  while ((e = readdir(d))) {
    long pid = partial_pid(e->d_name, base);
    if (!pid || !process_gone(pid)) continue;
    /* The entry's path: the name's folder part as written, then the entry. */
    char *p = malloc((size_t)(base - name) + strlen(e->d_name) + 1);
    if (!p) break;
    memcpy(p, name, (size_t)(base - name));
    strcpy(p + (base - name), e->d_name);
    struct stat st;
    bool gone = lstat(p, &st) == 0 && (S_ISDIR(st.st_mode) ? remove_folder(p) : unlink(p) == 0);
    if (gone) {
      count++;
      if (removed && cap) {
        size_t used = strlen(removed);
        snprintf(removed + used, cap - used, "%s%s", used ? " " : "", p);
      }
    }
    free(p);
  }
  closedir(d);
  return count;
}

/* ---- checking a set against its manifest ---- */

/* Reads a JSON string at *q (just past its opening quote) into out. */
static bool json_str(const char **q, char *out, size_t cap) {
  size_t n = 0;
  const char *c = *q;
  for (; *c && *c != '"'; c++) {
    char ch = *c;
    if (ch == '\\') {
      c++;
      switch (*c) {
      case 'n': ch = '\n'; break;
      case 't': ch = '\t'; break;
      case 'r': ch = '\r'; break;
      case 'b': ch = '\b'; break;
      case 'f': ch = '\f'; break;
      case 'u': {
        unsigned v = 0;
        if (sscanf(c + 1, "%4x", &v) != 1 || v > 0x7f) return false;
        ch = (char)v, c += 4;
        break;
      }
      case '\0': return false;
      default: ch = *c;
      }
    }
    if (n + 1 >= cap) return false;
    out[n++] = ch;
  }
  if (*c != '"') return false;
  out[n] = '\0';
  *q = c + 1;
  return true;
}

/* The text after "key": in s (from s on), or NULL. */
static const char *after_key(const char *s, const char *key) {
  char k[64];
  snprintf(k, sizeof k, "\"%s\":", key);
  const char *at = strstr(s, k);
  if (!at) return NULL;
  at += strlen(k);
  while (*at == ' ') at++;
  return at;
}

vr_status vr_film_verify(const char *prefix, vr_film_verify_line line, void *user,
                         vr_film_check *out, vr_error *err) {
  memset(out, 0, sizeof *out);
  char *path = cat3(prefix, ".manifest.json", "");
  if (!path) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  char *text = NULL;
  size_t len = 0;
  vr_status st = VR_OK;
  FILE *f = fopen(path, "rb");
  if (!f) {
    st = vr_error_set(err, VR_E_IO, "%s: cannot read the manifest: %s", path, strerror(errno));
    goto out;
  }
  if (fseek(f, 0, SEEK_END) == 0) len = (size_t)ftell(f);
  rewind(f);
  text = malloc(len + 1);
  if (!text || fread(text, 1, len, f) != len) {
    fclose(f);
    st = vr_error_set(err, VR_E_IO, "%s: cannot read the manifest", path);
    goto out;
  }
  fclose(f);
  text[len] = '\0';
  const char *q = after_key(text, "run_id"), *files = after_key(text, "files");
  if (!q || *q != '"' || !(q++, json_str(&q, out->run_id, sizeof out->run_id)) || !files) {
    st = vr_error_set(err, VR_E_PARSE, "%s: not a vr-render manifest (no run_id or files)", path);
    goto out;
  }
  char dir[PATH_MAX];
  vr_path_folder(path, dir, sizeof dir);
  for (const char *c = after_key(files, "name"); c; c = after_key(c, "name")) {
    char name[PATH_MAX], sha[72], msg[3 * PATH_MAX];
    long long bytes = -1;
    const char *b, *h;
    if (*c != '"' || !(c++, json_str(&c, name, sizeof name)) || !(b = after_key(c, "bytes")) ||
        sscanf(b, "%lld", &bytes) != 1 || !(h = after_key(c, "sha256")) || *h != '"' ||
        !(h++, json_str(&h, sha, sizeof sha))) {
      st = vr_error_set(err, VR_E_PARSE, "%s: a damaged entry after %d files", path, out->files);
      goto out;
    }
    char full[2 * PATH_MAX];
    if (name[0] == '/' || !strcmp(dir, ".")) snprintf(full, sizeof full, "%s", name);
    else snprintf(full, sizeof full, "%s/%s", dir, name);
    vr_file_sum now;
    vr_error ferr = {0};
    out->files++;
    if (sum_file(full, &now, &ferr)) {
      snprintf(msg, sizeof msg, "missing  %s", ferr.message);
      out->bad++;
    } else if (now.bytes != bytes || strcmp(now.sha, sha)) {
      snprintf(msg, sizeof msg, "differs  %s: %lld bytes, SHA-256 %.12s..., the manifest says "
               "%lld bytes, %.12s...", full, now.bytes, now.sha, bytes, sha);
      out->bad++;
    } else {
      snprintf(msg, sizeof msg, "ok       %s", full);
    }
    if (line) line(user, msg);
  }
  if (out->bad)
    st = vr_error_set(err, VR_E_RANGE,
                      "%s: %d of %d files do not match %s (run %s): a mixed or altered set",
                      prefix, out->bad, out->files, path, out->run_id);
out:
  free(text);
  free(path);
  return st;
}
