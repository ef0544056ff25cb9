/* A mesh line's materials=FILE (scn_map_file): the material.PATTERN=NAME
 * maps of a model kept in a file of their own, one per line, so that a
 * model with dozens of materials is mapped once for every scene that uses
 * it:
 *
 *   # office.map: the model's material names on the left (shell wildcards)
 *   Glass*       = clear
 *   *Oak*        = oak
 *
 * Blank lines and lines starting with '#' are skipped.  Errors name the
 * file and its line. */
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "scene/scene_parse.h"
#include "vr/file.h"

/* s without its surrounding blanks, in place. */
static char *trim(char *s, char *end) {
  while (s < end && (*s == ' ' || *s == '\t')) s++;
  while (end > s && (end[-1] == ' ' || end[-1] == '\t' || end[-1] == '\r')) end--;
  *end = '\0';
  return s;
}

vr_status scn_map_file(vr_scn_stmt *t, const vr_scn_opt *o, size_t object) {
  vr_scn_parser *p = t->p;
  if (!o->val[0]) return scn_fail(p, o->word, "\"%s\": materials= needs a map file", o->word);
  char *path = scn_resolve(p->s, o->val), *text = NULL;
  if (!path) return scn_nomem(p);
  struct stat sb;
  vr_status st = VR_OK;
  size_t len = 0;
  vr_error e = {0};
  if (stat(path, &sb))
    st = scn_fail(p, o->word, "\"%s\": cannot open the map file '%s': %s", o->word, path, strerror(errno));
  else if (!S_ISREG(sb.st_mode))
    st = scn_fail(p, o->word, "\"%s\": the map file '%s' is not a regular file", o->word, path);
  else if (vr_read_file(path, 1 << 20, &text, &len, &e))
    st = scn_fail(p, o->word, "\"%s\": %s", o->word, e.message);
  else if (memchr(text, '\0', len))
    st = vr_error_at(p->err, VR_E_PARSE, path, 0, 0,
                     "binary data (a NUL byte): a map file is text, PATTERN = MATERIAL per line");
  long ln = 0;
  for (char *line = text; !st && line && line < text + len; ln++) {
    char *nl = memchr(line, '\n', (size_t)(text + len - line)), *end = nl ? nl : text + len;
    char *l = trim(line, end);
    line = nl ? nl + 1 : NULL;
    if (!*l || *l == '#') continue;
    char *eq = strchr(l, '=');
    char *pat = eq ? trim(l, eq) : NULL, *alias = eq ? trim(eq + 1, eq + 1 + strlen(eq + 1)) : NULL;
    if (!eq || !*pat || !*alias || strpbrk(alias, " \t"))
      st = vr_error_at(p->err, VR_E_PARSE, path, ln + 1, 1,
                       "expected PATTERN = MATERIAL (a pattern of the model's material names, "
                       "then one material of the scene)");
    if (st) break;
    vr_scn_mesh_map *map = scn_grow((void **)&p->maps, &p->nmaps, sizeof *map);
    if (!map) {
      st = scn_nomem(p);
      break;
    }
    map->object = object;
    map->loc = (vr_scene_loc){ln + 1, (long)(pat - l) + 1};
    if (!(map->pattern = strdup(pat)) || !(map->alias = strdup(alias)) || !(map->file = strdup(path)))
      st = scn_nomem(p);
  }
  free(text);
  free(path);
  return st;
}
